"""What a study measures, as pure functions a Dask worker runs: parameters in, table rows out.

    reference_states(scene, times, cache)          the converged reference at the sample times
    measure_batch(points, references, threads, twin, bundle) -> rows of study.csv: stable,
        position_error_max (m, to the reference every plan.SAMPLE s), twin_position_error_max (m),
        wall_time (s), force_evals

`stable` is custom_sim not stopping the run and the sweep's energy criterion
(stability_search.energy_verdict). The user's runs (simulator "yours", their code from
`bundle`, compare.usersim.bundle) are judged the same way: a blow-up (out of custom_sim's healthy
range, or a non-finite state) is unstable, an exception of their code failed, a scene their
code does not do (SHAPES, NotImplementedError) skipped; each run imports their module afresh,
as `run` does.
Every column: docs/studies.md#what-each-run-measures.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from custom_sim import SimulationDiverged, stable_step

from ..accuracy.stability_search import energy_scale
from ..accuracy.workprecision import grid_verdict
from .plan import Point, sample_rows

# s: two sample times are the same instant when closer than this (a step count times dt
# rounds differently in the last bits of a double; the smallest step studied is far larger)
SAME_TIME = 1e-12
# How the user's runner says a state it was given is not finite (compare/usersim/functions.py):
# a blow-up, so the run is unstable, not failed
NON_FINITE = "non-finite"


def reference_states(scene, times: np.ndarray, cache_dir: str | None):
    """(states (T, 6) at `times`, "") or (None, why) when the reference cannot follow the motion."""
    from ...oracle.reference import ReferenceFailed, cached_reference

    try:
        return cached_reference(scene, times, cache_dir).states, ""
    except ReferenceFailed as exc:
        return None, f"no reference: {exc}"


def _distance_max(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.hypot(a[:, 0] - b[:, 0], a[:, 1] - b[:, 1])))


def _finite(x: float) -> float | None:
    return x if x is not None and math.isfinite(x) else None


def twin_rows(scene, twin_dt: float, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(our sample indices, the twin's step indices) at the sample times both share."""
    times = rows * scene.dt
    theirs = np.rint(times / twin_dt).astype(np.int64)
    same = np.abs(theirs * twin_dt - times) <= SAME_TIME
    return np.flatnonzero(same), theirs[same]


def measure_batch(points: list[Point], references: list, threads: int = 1, twin: bool = True,
                  bundle=None) -> list[dict]:
    """Rows (one per run of every point) for points whose reference states at their sample
    times are references[i] = (states or None, note); bundle: the user's shipped code, for the
    runs of simulator "yours"."""
    from custom_sim.batch import simulate_batch

    ours = [(p, run) for p in points for run in p.runs if run.simulator == "custom_sim"]
    rows_of = {p.key: sample_rows(p.scene) for p in points}
    results = simulate_batch([r.scene for _, r in ours], [rows_of[p.key] for p, _ in ours],
                             threads=threads) if ours else []
    twins = {}
    if twin:
        from mujoco_models.batch import simulate_mujoco_batch

        plans = []
        for p in points:
            twin_dt = p.scene.mujoco.dt or p.scene.dt
            plans.append(twin_rows(p.scene, twin_dt, rows_of[p.key]))
        done = simulate_mujoco_batch([p.scene for p in points], [t for _, t in plans], threads=threads)
        twins = {p.key: (plan[0], t) for p, plan, t in zip(points, plans, done)}
    simulator = None
    if bundle is not None and len(ours) < sum(len(p.runs) for p in points):
        simulator = _your_simulator(bundle)
    out = []
    it = iter(results)
    for p, (ref, ref_note) in zip(points, references):
        for run in p.runs:
            if run.simulator == "yours":
                out.append(_your_row(simulator, run, rows_of[p.key], ref, ref_note, twins.get(p.key), twin))
            else:
                out.append(_row(run, next(it), ref, ref_note, twins.get(p.key), twin))
    return out


@dataclass(frozen=True)
class _YourResult:
    """The user's run in the shape of custom_sim.batch's result: states at the sample rows."""

    states: np.ndarray | None
    wall_time: float | None
    diverged: bool = False
    note: str = ""
    force_evals = None


def _your_simulator(bundle):
    """The user's simulator from its shipped code, or the one line why it does not import here."""
    from ...usersim import UserCodeError

    try:
        return bundle.simulator()
    except UserCodeError as exc:   # e.g. a package the user's machine has and the worker lacks
        import socket
        return f"on the worker at {socket.gethostname()}: {exc}"


def _your_row(simulator, run, rows: np.ndarray, ref, ref_note: str, twin_result, twin: bool) -> dict:
    """The row of one run of the user's code (a fresh import, the whole run in order);
    simulator: from _your_simulator (a string: why there is none)."""
    from ...usersim import SceneSkipped, UserCodeError, UserFault, run_user
    from ...usersim.errors import UserDiverged

    status = None
    try:
        if isinstance(simulator, str):
            raise UserCodeError(simulator)
        trajectory = run_user(simulator, run.scene)
    except SceneSkipped as exc:   # SHAPES leaves the body out, or the code raised NotImplementedError
        status, note = "skipped", f"not done by your code: {exc.reason}"
    except UserDiverged as exc:
        status, note = "unstable", str(exc)
    except UserFault as exc:
        if NON_FINITE in str(exc):
            status, note = "unstable", str(exc)
        else:
            status, note = "failed", str(exc)
    except UserCodeError as exc:   # a fault of the protocol (a wrong return, ending the process)
        status, note = "failed", str(exc)
    if status is not None:
        return {"values": list(run.values), "integrator": run.integrator, "key": run.key, "simulator": "yours",
                "stable": False if status == "unstable" else None, "status": status,
                "position_error_max": None, "twin_position_error_max": None, "wall_time": None,
                "force_evals": None, "stable_step_theory": _theory(run), "note": note}
    states = np.column_stack([trajectory.x, trajectory.y, trajectory.theta,
                              trajectory.vx, trajectory.vy, trajectory.omega])[rows]
    row = _row(run, _YourResult(states, trajectory.wall_time), ref, ref_note, twin_result, twin)
    row["note"] = "; ".join(n for n in (row["note"], "force evaluations: not counted by your code") if n)
    return row


def _theory(run) -> float | None:
    """custom_sim's stable step for the run's scene and integrator (None: no limit, or an
    integrator the harness does not know)."""
    from custom_sim import INTEGRATORS
    return _finite(stable_step(run.scene, run.integrator)) if run.integrator in INTEGRATORS else None


def _row(run, res, ref, ref_note: str, twin_result, twin: bool) -> dict:
    scene = run.scene
    notes = []
    row = {"values": list(run.values), "integrator": run.integrator, "key": run.key, "simulator": run.simulator,
           "wall_time": res.wall_time, "force_evals": res.force_evals, "stable_step_theory": _theory(run),
           "position_error_max": None, "twin_position_error_max": None}
    if res.diverged:
        row.update(stable=False, status="unstable")
        notes.append(_diverged_text(scene, res))
    else:
        row.update(stable=True, status="ok")
        if ref is not None:
            row["position_error_max"] = _distance_max(res.states, ref)
            calm, why = grid_verdict(scene, res.states, energy_scale(ref, scene))
            if not calm:
                row.update(stable=False, status="unstable")
                notes.append(f"{run.integrator} with dt = {scene.dt:g} s: {why} (energy growth)")
        else:
            notes.append(ref_note)
        if twin_result is not None:
            ours, tw = twin_result
            if tw.diverged:
                notes.append(f"twin: {tw.note}")
            elif ours.size:
                row["twin_position_error_max"] = _distance_max(res.states[ours], tw.states)
        elif not twin:
            notes.append("twin not run (--no-twin)")
    row["note"] = "; ".join(n for n in notes if n)
    return row


def _diverged_text(scene, res) -> str:
    try:
        return str(SimulationDiverged(scene, scene.integrator, scene.dt, res.failed_step, res.failed_state))
    except Exception:  # noqa: BLE001 - the message only; the row says unstable either way
        return f"{scene.integrator} diverged at step {res.failed_step} with dt = {scene.dt:g} s"


def failed_rows(points: list[Point], reason: str) -> list[dict]:
    """Rows of runs that failed twice (their worker died, or the task raised)."""
    return [{"values": list(r.values), "integrator": r.integrator, "key": r.key, "simulator": r.simulator,
             "stable": None,
             "status": "failed", "position_error_max": None, "twin_position_error_max": None,
             "wall_time": None, "force_evals": None,
             "stable_step_theory": _theory(r), "note": f"failed twice: {reason}"} for p in points for r in p.runs]
