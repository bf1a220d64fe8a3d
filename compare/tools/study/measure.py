"""What a study measures, as pure functions a Dask worker runs: parameters in, table rows out.

    reference_states(scene, times, cache)          the converged reference at the sample times
    measure_batch(points, references, threads, twin) -> rows of study.csv: stable,
        position_error_max (m, to the reference every plan.SAMPLE s), twin_position_error_max (m),
        wall_time (s), force_evals

`stable` is custom_sim not stopping the run and the sweep's energy criterion
(stability_search.energy_verdict). Every column: docs/studies.md#what-each-run-measures.
"""
from __future__ import annotations

import math

import numpy as np

from custom_sim import SimulationDiverged, stable_step

from ..accuracy.stability_search import energy_scale
from ..accuracy.workprecision import grid_verdict
from .plan import Point, sample_rows

# s: two sample times are the same instant when closer than this (a step count times dt
# rounds differently in the last bits of a double; the smallest step studied is far larger)
SAME_TIME = 1e-12


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


def measure_batch(points: list[Point], references: list, threads: int = 1, twin: bool = True) -> list[dict]:
    """Rows (one per run of every point) for points whose reference states at their sample
    times are references[i] = (states or None, note)."""
    from custom_sim.batch import simulate_batch

    runs = [run for p in points for run in p.runs]
    rows_of = {p.key: sample_rows(p.scene) for p in points}
    results = simulate_batch([r.scene for r in runs], [rows_of[p.key] for p in points for _ in p.runs],
                             threads=threads)
    twins = {}
    if twin:
        from mujoco_models.batch import simulate_mujoco_batch

        plans = []
        for p in points:
            twin_dt = p.scene.mujoco.dt or p.scene.dt
            ours, theirs = twin_rows(p.scene, twin_dt, rows_of[p.key])
            plans.append((ours, theirs))
        done = simulate_mujoco_batch([p.scene for p in points], [t for _, t in plans], threads=threads)
        twins = {p.key: (plan[0], t) for p, plan, t in zip(points, plans, done)}
    out = []
    it = iter(results)
    for p, (ref, ref_note) in zip(points, references):
        for run in p.runs:
            res = next(it)
            out.append(_row(run, res, ref, ref_note, twins.get(p.key), twin))
    return out


def _row(run, res, ref, ref_note: str, twin_result, twin: bool) -> dict:
    scene = run.scene
    notes = []
    row = {"values": list(run.values), "integrator": run.integrator, "key": run.key,
           "wall_time": res.wall_time, "force_evals": res.force_evals,
           "stable_step_theory": _finite(stable_step(scene, run.integrator)),
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
    return [{"values": list(r.values), "integrator": r.integrator, "key": r.key, "stable": None,
             "status": "failed", "position_error_max": None, "twin_position_error_max": None,
             "wall_time": None, "force_evals": None,
             "stable_step_theory": _finite(stable_step(r.scene, r.integrator)),
             "note": f"failed twice: {reason}"} for p in points for r in p.runs]
