"""The penalty mapping's force error, read from MuJoCo along the twin's own run.

With flat impedance d and solref = (-k A_hat, -c A_hat) (mujoco_models/solref.py) the rows in
contact solve (A + R) f = aref - a0 with R = (1 - d) / d A_hat and aref = A_hat f* / d, where
f* = k depth - c v is the spring-damper we asked for, A = J M^-1 J^T the contacts' true inverse
inertia (a matrix: two corners touching couple through the body) and a0 = J qacc_smooth the
acceleration the rows would see without contact. Multiplying by d / A_hat:

    f = f* - e,     e = d [ (A / A_hat - 1) f + a0 / A_hat ]         (N, per row)

So MuJoCo's force is ours up to e: the relative part d (A / A_hat - 1) (A reaches 4 to 5 A_hat
on a box's corner) and the absolute part d a0 / A_hat (about 1.5e-4 m g while resting). The
error is read from MuJoCo's own quantities at every touching step of the twin's run (efc_J,
the mass matrix through mj_solveM, efc_diagA for A_hat, efc_force, qacc_smooth): nothing here
assumes the formula for A. tests/test_contact_check.py checks e against efc_force - f*.
"""
from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np
from mujoco import rollout

from custom_sim import Scene
from custom_sim.bodies import contact_points_world
from scene_types.errors import Diverged

from mujoco_models.frames import states_from_q
from mujoco_models.geometry import CONTACT_SPHERE_RADIUS
from mujoco_models.run import FULL_STATE, setup_rollout
from mujoco_models.solref import PENALTY_IMPEDANCE

MAX_EVALUATIONS = 4000   # touching steps read back from MuJoCo (evenly spread): ~10 us each
# A step counts when its rows carry at least this share of the body's weight (without gravity:
# of the run's largest load): below it the absolute parts of e (d a0 / A_hat, k r_s) are a
# large share of a tiny force that barely moves the body.
LOAD_SHARE = 0.5
# The torque's relative error counts at steps whose contact torque is at least this share of
# the run's largest: near a balance (torque -> 0) the absolute parts dominate a vanishing torque.
TORQUE_SHARE = 0.1


@dataclass(frozen=True)
class MappingError:
    """What the penalty rows did over the run.

    relative          max over touching steps of sum |e| / sum f (-): the mapping's force error
    torque_relative   max over touching steps of |torque of e| / |contact torque| (-): two
                      corners touching at once couple through A's off-diagonal terms, so the
                      torque's error (d (sum r_x^2 / (I A_hat) - 1) on two corners) can exceed
                      the force's
    ratio_min/max     range of A_ii / A_hat over the touching rows (-)
    a_hat             MuJoCo's A_hat (1/kg)
    steps             touching steps read back
    force_check       max |(efc_force - f*) + e| / max f (-): how well e explains MuJoCo's force
    """

    relative: float
    torque_relative: float
    ratio_min: float
    ratio_max: float
    a_hat: float
    steps: int
    force_check: float

    def as_dict(self) -> dict:
        return {"relative_force_error": self.relative, "relative_torque_error": self.torque_relative,
                "A_over_A_hat_min": self.ratio_min,
                "A_over_A_hat_max": self.ratio_max, "A_hat": self.a_hat, "steps_read": self.steps,
                "force_residual": self.force_check}


class NativeDiverged(Diverged):
    """MuJoCo's native twin met a bad acceleration or left finite numbers."""


def native_run(scene: Scene, integrator: str | None = None, dt: float | None = None):
    """(states (steps + 1, 6), twin, MappingError): the scene's penalty twin run once with
    MuJoCo's own loop, its states, and the force error e read at its touching steps.
    Raises NativeDiverged."""
    twin, model, data, start, n = setup_rollout(scene, "penalty", integrator, dt)
    rows, _ = rollout.rollout(model, data, start, nstep=n)
    rows = np.vstack([start[None, :], rows[0]])
    nv = model.nv
    props = twin.props          # the twin's own rigid body (mujoco_models/rigid_body.py)
    states = states_from_q(props, rows[:, 1:1 + nv], rows[:, 1 + nv:1 + 2 * nv])
    if data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number or not np.all(np.isfinite(states)):
        raise NativeDiverged(f"{scene.name}: MuJoCo ({twin.integrator}, dt = {twin.dt:g} s, penalty) met a "
                             f"bad acceleration or left finite numbers")
    return states, twin, _read_error(scene, model, data, rows, states, props)


def mapping_error(scene: Scene, integrator: str | None = None, dt: float | None = None) -> MappingError:
    """Run the scene's penalty twin and read the force error e at its touching steps."""
    return native_run(scene, integrator, dt)[2]


def _read_error(scene: Scene, model, data, rows: np.ndarray, states: np.ndarray, props) -> MappingError:
    """Read MuJoCo's rows at the touching steps (one mj_forward each), then e for all of them at
    once: each step's m rows padded with zero rows to the most any step has, which add nothing
    (J = 0, f = 0 there)."""
    nv = model.nv
    _, py = contact_points_world(props, states[:, 0], states[:, 1], states[:, 2])
    touching = np.flatnonzero(np.any(py < 0.0, axis=1))
    if len(touching) > MAX_EVALUATIONS:
        touching = touching[np.linspace(0, len(touching) - 1, MAX_EVALUATIONS).astype(int)]
    k, c, d = scene.contact.k, scene.contact.c, PENALTY_IMPEDANCE
    read = []   # per step with rows: (J, J M^-1, f, k depth - c v on MuJoCo's depth and velocity, A_hat)
    for i in touching:
        mujoco.mj_setState(model, data, rows[i], FULL_STATE)
        mujoco.mj_forward(model, data)
        m = data.nefc
        if m == 0:
            continue
        jac = data.efc_J[:m * nv].reshape(m, nv).copy()
        minv_jt = np.empty((m, nv))
        mujoco.mj_solveM(model, data, minv_jt, jac)
        read.append((jac, minv_jt, data.efc_force[:m].copy(),
                     k * (-data.efc_pos[:m]) - c * data.efc_vel[:m], jac @ data.qacc_smooth, data.efc_diagA[0]))
    if not read:
        return MappingError(0.0, 0.0, 1.0, 1.0, float(model.body_invweight0[1, 0]), 0, 0.0)
    T, width = len(read), max(len(r[2]) for r in read)
    J, minv_jt = np.zeros((T, width, nv)), np.zeros((T, width, nv))
    f, wanted, a0 = np.zeros((T, width)), np.zeros((T, width)), np.zeros((T, width))
    real = np.zeros((T, width), dtype=bool)
    for t, (jac, jm, force, want, acc, _) in enumerate(read):
        m = len(force)
        J[t, :m], minv_jt[t, :m], f[t, :m], wanted[t, :m], a0[t, :m], real[t, :m] = jac, jm, force, want, acc, True
    a_hat = np.array([r[5] for r in read])
    A = J @ minv_jt.transpose(0, 2, 1)                     # J M^-1 J^T, (steps, rows, rows)
    scaled = A / a_hat[:, None, None] - np.eye(A.shape[1])
    e = d * (np.einsum("tij,tj->ti", scaled, f) + a0 / a_hat[:, None])
    on = f > 0.0                                            # rows the solver did not clamp
    residual = float(np.max(np.abs(f - wanted + e)[on])) if np.any(on) else 0.0
    fmax = float(np.max(f))
    ratios = (np.diagonal(A, axis1=1, axis2=2) / a_hat[:, None])[real]
    # against our law on our depth: MuJoCo's depth is ours + the contact sphere's radius
    # (mujoco_models/geometry.py) for a box or compound body, so its spring adds k r_s
    offset = k * CONTACT_SPHERE_RADIUS if props.points_rotate else 0.0
    wrong = np.where(on, offset - e, 0.0)
    load = f.sum(axis=1)
    wrong_sum = np.abs(wrong).sum(axis=1)
    # generalised: the torque of the rows (J's hinge column) and of their error
    torque = np.abs(np.einsum("ti,ti->t", J[:, :, 2], f)) if nv == 3 else np.zeros(len(f))
    torque_wrong = np.abs(np.einsum("ti,ti->t", J[:, :, 2], wrong)) if nv == 3 else np.zeros(len(f))
    weight = props.mass * scene.g if scene.has("gravity") else 0.0
    floor = LOAD_SHARE * (weight if weight > 0.0 else load.max())
    counted = (load >= floor) & (load > 0.0)
    relative = float(np.max(wrong_sum[counted] / load[counted])) if np.any(counted) else 0.0
    turning = (torque >= TORQUE_SHARE * torque.max()) & (torque > 0.0)
    torque_relative = float(np.max(torque_wrong[turning] / torque[turning])) if np.any(turning) else 0.0
    return MappingError(relative, torque_relative, float(ratios.min()), float(ratios.max()), float(a_hat[-1]),
                        len(touching), residual / fmax if fmax > 0 else 0.0)
