"""Many twins in few calls: mujoco.rollout over several models at once, on MuJoCo's own threads.

    simulate_mujoco_batch(scenes, samples, threads) -> list[TwinRun]

Each scene's twin is built as simulate_mujoco builds it (setup_rollout) and rolled out from
the same start state, so a twin of the batch is bit for bit simulate_mujoco's (a test checks
it). Twins with the same number of steps share one rollout call, `threads` MjData (one per
thread). A twin has diverged when MuJoCo reset its state (the time column of rollout's rows
falls back: mjWARN_BADQACC resets the data, and the warning count of a shared MjData cannot
say which model tripped it) or when the twin's own guard (guard.py) finds the state blown up.
"""
from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np
from mujoco import rollout

from scene_types.schema import Scene

from .frames import joint_count, states_from_q
from .guard import first_blowup
from .run import setup_rollout

# Largest array of rollout rows one call may fill (bytes): models of a group are rolled out
# this many at a time (7 doubles a step for a turning body: 200 000 steps take 11 MB a model).
ROWS_BUDGET = 256e6


@dataclass(frozen=True)
class TwinRun:
    """One twin: states (len(samples), 6) at the requested step indices of the twin's own step
    (NaN past a divergence), dt (s), diverged, note (why, when diverged)."""

    samples: np.ndarray
    states: np.ndarray
    dt: float
    steps: int
    diverged: bool
    note: str = ""


def _reset_step(times: np.ndarray) -> int:
    """Step at which MuJoCo reset the data (time fell back), or -1; times[i]: after step i."""
    back = np.flatnonzero(np.diff(times) < 0.0)
    return int(back[0]) + 1 if back.size else -1


def simulate_mujoco_batch(scenes: list[Scene], samples: list[np.ndarray] | None = None,
                          threads: int = 1) -> list[TwinRun]:
    """Twins of the scenes (each at its [mujoco] settings) by rollout; samples[b]: step indices
    0..steps of twin b to keep (default every step). threads: MjData, i.e. rollout's threads."""
    setups = [setup_rollout(scene) for scene in scenes]
    if samples is None:
        samples = [np.arange(n + 1) for *_, n in setups]
    samples = [np.asarray(r, dtype=np.int64) for r in samples]
    groups: dict[tuple, list[int]] = {}
    for b, (_, model, _, start, n) in enumerate(setups):
        groups.setdefault((n, start.size, model.nq, model.nv, model.ngeom, model.npair), []).append(b)
    out: list[TwinRun | None] = [None] * len(scenes)
    for (n, nstate, *_), members in groups.items():
        per_call = max(1, int(ROWS_BUDGET // (8 * nstate * n)))
        for first in range(0, len(members), per_call):
            chunk = members[first:first + per_call]
            models = [setups[b][1] for b in chunk]
            datas = [mujoco.MjData(models[0]) for _ in range(max(1, min(threads, len(chunk))))]
            starts = np.stack([setups[b][3] for b in chunk])
            rows, _ = rollout.rollout(models, datas, starts, nstep=n)
            for j, b in enumerate(chunk):
                out[b] = _twin_run(scenes[b], setups[b], rows[j], samples[b])
    return out


def _twin_run(scene: Scene, setup, rows: np.ndarray, samples: np.ndarray) -> TwinRun:
    twin, _, _, start, n = setup
    nq = joint_count(twin.props)
    rows = np.vstack([start[None, :], rows])
    states = states_from_q(twin.props, rows[:, 1:1 + nq], rows[:, 1 + nq:1 + 2 * nq])
    what = f"{scene.name}: MuJoCo ({twin.integrator}, dt = {twin.dt:g} s, solref {twin.contact.mapping})"
    stop, note = _reset_step(rows[:, 0]), ""
    if stop >= 0:
        note = f"{what} met a bad acceleration at step {stop} and reset the state"
    else:
        rb, g = twin.props, (scene.g if scene.has("gravity") else 0.0)
        x, y, theta, vx, vy, om = states.T
        kinetic = 0.5 * rb.mass * (vx * vx + vy * vy) + 0.5 * rb.inertia * om * om  # J, the rows' own
        stop = first_blowup(states, kinetic, rb.mass * g * y, rb, g)
        if stop >= 0:
            note = f"{what} blew up at step {stop} (t = {stop * twin.dt:.6g} s)"
    picked = states[samples].copy()
    if stop >= 0:
        picked[samples >= stop] = np.nan
    return TwinRun(samples=samples, states=picked, dt=twin.dt, steps=n, diverged=stop >= 0, note=note)
