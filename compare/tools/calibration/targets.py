"""One scene of a fit: its twin compiled once, the trajectory to match, and batched rollouts.

    prepare(scene, mapping, reference=None)  a Target (reference: custom_sim's run by default)
    Batch(nthread)                           mujoco.rollout's thread pool and the count of steps
    batch.paths(target, settings_list)       (k, steps + 1, 3) x, y, theta of k twins at once

The k twins of a finite-difference Jacobian differ only in their pair settings, so they are
k copies of one compiled MjModel with different pair_* arrays, rolled out in one call to
mujoco.rollout over its own threads: no Python loop per parameter, no recompiling.
"""
from __future__ import annotations

import copy
from dataclasses import dataclass

import mujoco
import numpy as np
from mujoco import rollout

from custom_sim import Scene, Trajectory, mass_properties, simulate
from mujoco_models import build_twin

from .settings import BaseSettings, read_model, write_model

FULL_STATE = mujoco.mjtState.mjSTATE_FULLPHYSICS
# At most this many samples per scene enter the residual: the trajectories are smooth between
# contact events on this grid (2.5 s / 500 = 5 ms, a quarter of a 20 ms impact).
MAX_SAMPLES = 500
# A twin that blew up (MuJoCo reset its state, or a non-finite value) scores this distance (m)
# at every sample: far beyond any scene's size, so the optimiser backs off.
DIVERGED_DISTANCE = 10.0


@dataclass
class Target:
    """A scene, its twin's compiled base model and start state, and the path to match."""

    scene: Scene
    base: BaseSettings
    model: mujoco.MjModel
    start: np.ndarray          # MuJoCo's full physics state at the scene's start
    steps: int
    dt: float
    com: tuple[float, float]   # COM in the body frame, m (COM = qpos_xy + com)
    rotates: bool
    length: float              # m: radius of gyration, turns an angle residual into metres
    reference: np.ndarray      # (steps + 1, 3) x, y, theta to match, on the twin's step grid
    samples: np.ndarray        # indices of the rows that enter the residual

    @property
    def name(self) -> str:
        return self.scene.name


def prepare(scene: Scene, mapping: str, reference: Trajectory | None = None,
            integrator: str | None = None) -> Target:
    """The scene's target: the twin of `mapping` and the reference path (custom_sim's run of
    the scene when none is given), resampled on the twin's step grid."""
    from mujoco_models import solref_for

    twin = build_twin(scene, mapping, integrator=integrator)
    model = twin.spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    start = np.empty(mujoco.mj_stateSize(model, FULL_STATE))
    mujoco.mj_getState(model, data, start, FULL_STATE)
    steps = max(1, int(round(scene.duration / twin.dt)))
    ref = reference if reference is not None else simulate(scene)
    t = np.arange(steps + 1) * twin.dt
    path = np.column_stack([np.interp(t, ref.t, ref.x), np.interp(t, ref.t, ref.y),
                            np.interp(t, ref.t, ref.theta)])
    props = mass_properties(scene.body)
    length = float(np.sqrt(props.inertia / props.mass)) if props.rotates else 0.0
    penalty = solref_for(scene, "penalty", model, twin.dt)
    settings = read_model(model)
    # MuJoCo's friction-row damping is B = -solreffriction[1] / dwidth: rescaled to the base's
    # dwidth, gain 1 gives the penalty mapping's B whatever the base
    friction_damping = penalty.solreffriction[1]
    if settings.solimp[1] != penalty.solimp[1]:
        friction_damping *= settings.solimp[1] / penalty.solimp[1]
    base = BaseSettings(mapping, settings, friction_damping)
    samples = np.unique(np.linspace(1, steps, min(MAX_SAMPLES, steps)).round().astype(int))
    return Target(scene, base, model, start, steps, twin.dt, tuple(props.com), props.rotates,
                  length, path, samples)


class Batch:
    """mujoco.rollout's thread pool, reused for every call, and the MuJoCo steps taken."""

    def __init__(self, nthread: int = 2):
        self.nthread = max(1, nthread)
        self.steps = 0
        self._pool = rollout.Rollout(nthread=self.nthread)

    def close(self) -> None:
        self._pool.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def paths(self, target: Target, settings_list) -> np.ndarray:
        """(k, steps + 1, 3): x, y, theta of the COM for each settings; rows of a twin that
        blew up are NaN from that step on."""
        models = []
        for s in settings_list:
            m = copy.copy(target.model)
            write_model(m, s)
            models.append(m)
        datas = [mujoco.MjData(target.model) for _ in range(self.nthread)]
        k = len(models)
        # a zero warm start for every rollout: the result cannot depend on which thread ran
        # which model before
        warm = np.zeros((k, target.model.nv))
        state, _ = self._pool.rollout(models, datas, np.tile(target.start, (k, 1)), nstep=target.steps,
                                      initial_warmstart=warm)
        self.steps += k * target.steps
        nq = target.model.nq
        out = np.empty((k, target.steps + 1, 3))
        qpos0 = target.start[1:1 + nq]
        for rows, dst in ((qpos0[None, None, :], out[:, :1]), (state[:, :, 1:1 + nq], out[:, 1:])):
            dst[..., 0] = rows[..., 0] + target.com[0]
            dst[..., 1] = rows[..., 1] + target.com[1]
            dst[..., 2] = rows[..., 2] if target.rotates else 0.0
        out[~np.isfinite(out)] = np.nan
        # MuJoCo resets a state whose acceleration went bad: the time column jumps back
        time_col = state[:, :, 0]
        reset = np.diff(time_col, axis=1, prepend=0.0) <= 0.0
        for i in range(k):
            hit = np.flatnonzero(reset[i])
            if hit.size:
                out[i, 1 + hit[0]:] = np.nan
        return out


def residual_of(target: Target, paths: np.ndarray) -> np.ndarray:
    """(k, 3 n) residuals of paths against the reference at the samples: dx, dy and
    length * dtheta (m), divided by sqrt(n), so each scene weighs by its mean square, whatever
    its duration."""
    d = paths[:, target.samples, :] - target.reference[None, target.samples, :]
    d[..., 2] *= target.length
    d = np.where(np.isfinite(d), d, DIVERGED_DISTANCE)
    return d.reshape(len(paths), -1) / np.sqrt(len(target.samples))


def errors(target: Target, path: np.ndarray) -> dict:
    """position_error_max (m) and angle_error_max (rad) of one path over every step."""
    d = path - target.reference
    pos = np.hypot(d[:, 0], d[:, 1])
    if not np.all(np.isfinite(pos)):
        return {"position_error_max": None, "angle_error_max": None, "diverged": True}
    return {"position_error_max": float(pos.max()), "angle_error_max": float(np.abs(d[:, 2]).max()),
            "diverged": False}
