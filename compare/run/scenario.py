"""One scenario: run the simulator under test, judge every check, measure every difference,
and diagnose a user's run (the walk over compare/checks; its Result is compare/checks/result.py).

The checks are the registry's (compare/checks/registry.py, one unit each under the Check
protocol of compare/checks/check.py): collect_runs gathers and validates the runs once, judge
walks every check that applies; `validate` walks the same with those needing no MuJoCo.

The scenario passes when every judged check passes.
"""
from __future__ import annotations

import dataclasses
import warnings

import numpy as np

from custom_sim import INTEGRATORS, Scene, SimulationDiverged, Trajectory, stable_step

from ..checks.case import Case
from ..checks.check import Runs
from ..checks.registry import CHECKS
from ..checks.result import CUSTOM, Result
from ..checks.row import CheckRow
from ..diagnosis import diagnose
from ..store import cached


def custom_runs(case: Case) -> dict:
    """custom_sim with each of the four integrators at the scene's dt: a Trajectory, or the
    divergence message where that integrator is unstable at this step."""
    runs = {}
    for name in INTEGRATORS:
        try:
            runs[name] = case.trajectory(name)
        except SimulationDiverged as exc:
            runs[name] = str(exc)
    return runs


def run_scenario(scene: Scene, simulator=None) -> Result:
    """Run every check of the scene on custom_sim (simulator None) or on a user's simulator
    (compare.usersim); MuJoCo with every solref mapping beside."""
    from ..usersim import SceneSkipped, UserFault
    from ..usersim.errors import UserDiverged

    result = Result(scene)
    result.case = Case(scene)
    try:
        _run(result, result.case, simulator)
    except SceneSkipped as exc:   # the user's code does not do this scene: nothing judged, nothing fails
        result.skipped, result.simulator = exc.reason, simulator.name
    except SimulationDiverged as exc:
        result.error, result.unstable = str(exc), True
    except UserFault as exc:  # the user's code failed on this scene: its row, the others go on
        result.error, result.error_details = str(exc), exc.details
        result.unstable = isinstance(exc, UserDiverged)
    return result


def _run(result: Result, case: Case, simulator) -> None:
    """The scenario: the runs collected (and validated) once, every check of the registry
    walked over them, then what the report measures beside the checks."""
    scene = result.scene
    warned, result.stable_dt, result.stable_dt_reason = cached(stability)(scene)
    result.warnings = list(warned)
    runs = collect_runs(result, case, simulator)
    result.checks, result.residuals = judge(runs, CHECKS)
    result.reference = reference_states(case)
    twins = runs.twins
    result.by_mapping, result.mujoco, result.metrics = twins.by_mapping, twins.mujoco, twins.metrics
    result.balances = energy_balances(result, case)
    result.attribution = attribution_ladder(case, result.mujoco)
    if scene.scene_contact is not None:
        from ..checks.law_difference import law_differences
        result.law_differences = law_differences(scene, result.under_test.t, result.under_test.states())
    if runs.user:
        tested = result.under_test
        step_row = next((c for c in result.checks if c.name == "step" and c.integrator == tested.integrator), None)
        result.diagnosis = diagnose(simulator, scene, tested, probe=result.keeps_state is None, case=case,
                                    step_row=step_row)


def judge(runs: Runs, checks: dict) -> tuple[list[CheckRow], dict]:
    """Every check that applies to the runs, in the registry's order: their rows (without
    arrays), and the per-step traces of the rows that carry residuals, by integrator (plots)."""
    from ..checks.step_check import step_trace

    rows, traces = [], {}
    for check in checks.values():
        if not check.applies(runs):
            continue
        for row in check.judge(runs):
            if row.residual is not None:   # the step check's, per step: onto the plots, not into the row
                r, b = row.residual, row.bound
                traces[row.integrator] = None if b is None or not len(r) else step_trace(r, b)
                row = dataclasses.replace(row, residual=None, bound=None)
            rows.append(row)
    return rows, traces


def collect_runs(result: Result, case: Case, simulator) -> Runs:
    """custom_sim's four runs, and the simulator under test's (custom_sim's own, or the user's
    with its warnings and whether its step keeps state), validated here once: every run judged
    has the scene's steps + 1 states of 6 finite components."""
    scene = result.scene
    if simulator is not None:   # first: a scene the user's code skips runs nothing else
        from ..usersim import run_user
        from ..usersim.purity import keeps_state
        result.simulator = simulator.name
        with warnings.catch_warnings(record=True) as said:   # e.g. float32 states: onto the page
            warnings.simplefilter("always", UserWarning)
            result.under_test = run_user(simulator, scene)
        result.warnings += [str(w.message) for w in said if issubclass(w.category, UserWarning)]
    result.runs = custom_runs(case)
    result.custom = case.trajectory()   # raises the scene's own divergence
    if simulator is None:
        result.under_test = result.custom
        tested = dict(result.runs)
    else:
        result.keeps_state = keeps_state(simulator, scene, result.under_test.states())
        if result.keeps_state:
            result.warnings.append(result.keeps_state)
        tested = {result.under_test.integrator: result.under_test}
    for run in tested.values():
        if not isinstance(run, str):
            valid_states(scene, run.states())
    return Runs(case, result.under_test, tested, dict(result.runs), simulator, result.keeps_state)


def valid_states(scene: Scene, states: np.ndarray) -> None:
    """The states a check may judge: at least two states of 6 components, every one finite.
    The user's run is held to this where it is read (compare/usersim: its columns, and the
    healthy range, which nothing non-finite passes) and custom_sim's stops where it leaves that
    range; a run that breaks it here is the harness's own fault, never judged."""
    if states.ndim != 2 or states.shape[1] != 6 or len(states) < 2 or not np.all(np.isfinite(states)):
        raise RuntimeError(f"{scene.name}: a run to judge has shape {states.shape} (expected (n >= 2, 6)) "
                           f"or a non-finite state")


def reference_states(case: Case) -> np.ndarray | None:
    """The converged reference's states (steps + 1, 6), for the plots; None without one."""
    from ..oracle.reference import ReferenceFailed
    try:
        return case.reference().states
    except ReferenceFailed:
        return None


def attribution_ladder(case: Case, native: Trajectory) -> list[dict]:
    """Why custom_sim and MuJoCo's own contact differ, cause by cause (attribution.py)."""
    from ..checks.attribution import attribute
    scene = case.scene
    return attribute(scene, native if scene.mujoco.solref == "penalty" else None, case=case)


def energy_balances(result: Result, case: Case) -> dict:
    """The work-energy balance (compare/energy) of each trajectory the scenario holds: the
    simulator under test (W by its integrator's own rule, or the trapezoid rule for an integrator
    the harness does not know or states read from a file), custom_sim beside a user's, MuJoCo's
    native run (from its states), and the converged reference (its work integrated with it).
    Those of custom_sim, MuJoCo and the reference depend on the scene alone: from the cache."""
    from ..energy import balance

    tested = result.under_test
    if tested is result.custom:
        out = {result.simulator: cached(custom_balance)(case)}
    else:
        rule = tested.integrator if tested.integrator in INTEGRATORS and not tested.meta.get("rounding") else None
        out = {result.simulator: balance(case.scene, tested.t, tested.states(), rule),
               CUSTOM: cached(custom_balance)(case)}
    out["mujoco"] = cached(mujoco_balance)(case)
    reference = cached(reference_balance)(case)
    if reference is not None:
        out["reference"] = reference
    return out


def custom_balance(case: Case):
    """The balance of custom_sim's run of the scene, W by its integrator's own rule."""
    from ..energy import balance
    run = case.trajectory()
    return balance(case.scene, run.t, run.states(), run.integrator)


def mujoco_balance(case: Case):
    """The balance of MuJoCo's native run (the scene's own mapping), from its states."""
    from ..energy.mujoco_side import native_from_run
    twin = case.mujoco(case.scene.mujoco.solref)
    return native_from_run(case.scene, twin.t, twin.states(), twin.integrator,
                           twin.meta.get("solref_mapping", "penalty"))


def reference_balance(case: Case):
    """The converged reference's balance, its work integrated with the motion (None without a
    reference, or a reference that carries no work)."""
    from ..energy.balance import Balance
    from ..energy.law import body_of
    from ..energy.terms import energy
    from ..oracle.reference import ReferenceFailed as NoReference
    try:
        ref = case.reference()
    except NoReference:
        return None
    if getattr(ref, "work", None) is None:
        return None
    E = energy(case.scene, body_of(case.scene), ref.states)
    return Balance(ref.t, E, ref.work, E - E[0] + ref.work.sum(axis=1), "integrated with the motion (DOP853, the "
                   "reference's tolerance)", "reference", np.zeros(6))


def stability(scene: Scene) -> tuple[list[str], float, str]:
    """The theory's stable step for the scene's integrator (s; inf: any) with its reason, and
    the line saying which effect's limit the scene's dt exceeds (none when within): scene-only
    work, kept in the cache."""
    from custom_sim.stability import warning

    limit, line = stable_step(scene), warning(scene)
    return ([line] if line else []), float(limit), getattr(limit, "reason", "")
