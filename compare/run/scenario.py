"""One scenario: run the simulator under test, judge every check, measure every difference,
and diagnose a user's run (the walk over compare/checks; its Result is compare/checks/result.py).

The checks (one CheckRow each, row.py; every check module is compare/checks/*_check.py):

    step        each integrator's trajectory, step by step, against one step of the same
                integrator with an independent right-hand side          (all four integrators)
    dynamics    against MuJoCo integrating the same contact law        (semi-implicit Euler, RK4)
    contact     against MuJoCo's own contact, penalty mapping, friction off
    identical   a user's simulator against custom_sim, same integrator and dt
    reference   the error at the scene's dt against the converged reference  (shown, not judged)
    native      MuJoCo's own contact with every effect on (shown; judged only by a [tolerance]
                the scene file sets), with every difference measured and attributed to a named
                cause (attribution.py)

The scenario passes when every judged check passes.
"""
from __future__ import annotations

import dataclasses
import warnings

import numpy as np

from custom_sim import INTEGRATORS, Scene, SimulationDiverged, Trajectory, stable_step
from scene_types.integrators import MUJOCO_TWIN
from scene_types.schema import SOLREF_MAPPINGS

from ..store import cached
from ..checks import metrics
from ..checks.case import Case
from ..checks.native_check import native_row
from ..checks.row import CheckRow
from ..checks.result import CUSTOM, Result
from ..diagnosis import diagnose

# damping families the contact check's variant (friction off, the linear law) can stand for: a
# user's code for compression or linear follows the scene's damping_law; one written for
# Hunt-Crossley or the unclamped law need not
LINEAR_KIN = ("compression", "linear")



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


def unstable_row(name: str, integrator: str, why: str) -> CheckRow:
    return CheckRow(name, "", integrator, reason=f"not judged: {integrator} is unstable at this step ({why})")


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
    """The scenario, check by check (each row's module is named in the module docstring)."""
    scene = result.scene
    warned, result.stable_dt, result.stable_dt_reason = cached(stability)(scene)
    result.warnings = list(warned)
    tested = runs_under_test(result, case, simulator)
    user = simulator is not None
    result.checks = [
        *([identical_row(case, result.under_test)] if user else []),
        *step_rows(result, case, tested),
        *dynamics_rows(scene, tested, result.under_test if user else None),
        contact_row(case, simulator, result.under_test if user else None),
    ]
    rows, result.reference = reference_rows(case, tested, result.runs, own_model=not user)
    result.checks += rows
    native_twins(result, case)
    result.checks.append(native_row(scene, result.metrics))
    result.balances = energy_balances(result, case)
    result.checks += energy_column_rows(result)
    result.attribution = attribution_ladder(case, result.mujoco)
    if scene.scene_contact is not None:
        from ..checks.law_difference import law_differences
        result.law_differences = law_differences(scene, result.under_test.t, result.under_test.states())
    if user:
        tested = result.under_test
        step_row = next((c for c in result.checks if c.name == "step" and c.integrator == tested.integrator), None)
        result.diagnosis = diagnose(simulator, scene, tested, probe=result.keeps_state is None, case=case,
                                              step_row=step_row)


def runs_under_test(result: Result, case: Case, simulator) -> dict:
    """custom_sim's four runs, and the simulator under test's (custom_sim's own, or the user's
    with its warnings and whether its step keeps state): {integrator: Trajectory or divergence}."""
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
        return dict(result.runs)
    result.keeps_state = keeps_state(simulator, scene, result.under_test.states())
    if result.keeps_state:
        result.warnings.append(result.keeps_state)
    return {result.under_test.integrator: result.under_test}


def identical_row(case: Case, run: Trajectory) -> CheckRow:
    """Check identical: the user's run against custom_sim's, same integrator and dt."""
    from ..checks.identical_check import check_identical
    scene = case.scene
    return check_identical(scene, run.states(), run.integrator, scene.dt, run.meta.get("rounding"), case=case)


def step_rows(result: Result, case: Case, tested: dict) -> list[CheckRow]:
    """Check step, for each run under test (its residuals per component and their round-off
    kept for the plots as a StepTrace, in result.residuals, not in the row)."""
    from ..checks.step_check import check_step, step_trace

    scene, rows = case.scene, []
    for name, run in tested.items():
        if isinstance(run, str):
            rows.append(unstable_row("step", name, run))
            continue
        # states read from a text file carry their rounding (fixed decimals or significant digits)
        row = check_step(scene, run.states(), name, scene.dt, rounding=run.meta.get("rounding"),
                         equations=case.equations)
        r, b = row.residual, row.bound
        result.residuals[name] = None if r is None or b is None or not len(r) else step_trace(r, b)
        rows.append(dataclasses.replace(row, residual=None, bound=None))
    return rows


def dynamics_rows(scene: Scene, tested: dict, user_run: Trajectory | None) -> list[CheckRow]:
    """Check dynamics, for each run under test whose integrator MuJoCo has; an integrator the
    harness does not know is shown beside MuJoCo's RK4."""
    from ..checks.dynamics_check import check_dynamics

    rows = []
    for name in MUJOCO_TWIN:
        run = tested.get(name)
        if run is not None:
            rows.append(unstable_row("dynamics", name, run) if isinstance(run, str)
                        else check_dynamics(scene, run.states(), name, scene.dt, run.meta.get("rounding")))
    if user_run is not None and user_run.integrator not in INTEGRATORS:
        rows.append(beside_rk4_dynamics(scene, user_run))
    return rows


def native_twins(result: Result, case: Case) -> None:
    """MuJoCo's own contact with each solref mapping (the scene's first), measured against the
    run under test; the scene's own mapping is the native check's and the report's twin."""
    from mujoco_models import MujocoDiverged

    own_mapping = result.scene.mujoco.solref
    for mapping in (own_mapping,) + tuple(m for m in SOLREF_MAPPINGS if m != own_mapping):
        try:
            twin = case.mujoco(mapping)
        except (SimulationDiverged, MujocoDiverged) as exc:  # shown in the mappings table
            result.by_mapping[mapping] = {"error": str(exc)}
            continue
        row = metrics.compare(result.under_test, twin)
        row["energy_drift_mujoco"] = metrics.energy_drift(twin)
        row["wall_time_mujoco"] = twin.wall_time
        result.by_mapping[mapping] = row
        if mapping == own_mapping:
            result.mujoco, result.metrics = twin, row
    if result.mujoco is None:
        raise RuntimeError(result.by_mapping[own_mapping]["error"])


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
    from ..energy.terms import energy
    from ..energy.law import body_of
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


def energy_column_rows(result: Result) -> list[CheckRow]:
    """Check energy: where the simulator under test reports its own energy (custom_sim; a
    user's 7th column or `energy` column), that it is the energy of its states."""
    from ..energy.column import energy_column_check

    tested = result.under_test
    if tested is not result.custom and tested.meta.get("energy_source") != "user":
        return []
    verdict = energy_column_check(result.scene, tested.states(), tested.energy)
    details = {"energy_difference_max": verdict.difference_max, "energy_tolerance_max": verdict.tolerance_max}
    return [CheckRow("energy", "the simulator's own energy column against the energy of its states "
                               "(kinetic + m g y + sum k d^2 / 2)",
                     passed=verdict.agrees, reason=verdict.text, details=details, reason_at=len(details))]


def beside_rk4_dynamics(scene: Scene, run: Trajectory) -> CheckRow:
    """An integrator the harness does not know, beside MuJoCo's RK4 under the same contact law
    at the same step: shown, not judged (no round-off bound holds between two methods)."""
    from ..checks.dynamics_check import check_dynamics

    row = check_dynamics(scene, run.states(), "rk4", scene.dt, run.meta.get("rounding"))
    return dataclasses.replace(
        row, integrator=run.integrator, tolerance_position=None, tolerance_angle=None, passed=None,
        reason=f"shown, not judged: {run.integrator!r} is not an integrator the harness knows, so it "
               "is shown beside MuJoCo's RK4 under the same contact law at the same step")


def contact_row(case: Case, simulator, under_test: Trajectory | None = None) -> CheckRow:
    """Check contact: the simulator under test on the scene with friction off (and the linear
    law MuJoCo has), against MuJoCo's own contact. A user's simulator is run again on that
    variant, which the harness made up, unless the scene is that variant already (its run
    under_test is then the variant's); where it cannot run it (precomputed trajectories) or
    refuses it (raises, fails), the check is not judged, with the user's message; the rest stand."""
    from ..checks.contact_check import check_contact, contact_scene, not_judged

    scene = case.scene
    if simulator is None:
        return check_contact(scene, case=case)
    integrator = under_test.integrator
    if not simulator.reruns:
        return not_judged(integrator, "needs a run of the scene with friction off, which precomputed trajectories cannot "
                          "give (bring a step function)")
    variant = contact_scene(scene)
    if variant == scene:
        return _told_applied(check_contact(scene, under_test.states(), integrator, case=case), scene,
                             under_test.states())
    if scene.contact.damping_law not in LINEAR_KIN:
        return not_judged(integrator, f"MuJoCo's own contact is a spring-damper that damps both ways and never pulls "
                          f"(the linear law), and this check runs your code on the scene with that law; the law "
                          f"judged here, {scene.contact.damping_law}, has no such form in MuJoCo, and code written "
                          f"for it need not follow the variant: the dynamics check runs your law itself in MuJoCo")
    from ..usersim import SceneSkipped, UserCodeError, UserFault, run_user
    from ..usersim.guard import EndedProcess
    try:
        states = run_user(simulator, variant).states()
    except EndedProcess:
        raise
    except (UserFault, UserCodeError, SceneSkipped) as exc:
        return not_judged(integrator, f"your simulator did not run the variant this check needs (friction and rolling "
                          f"resistance off, the linear damping law): {exc}")
    return _told_applied(check_contact(scene, states, integrator, case=case), variant, states)


def _told_applied(row: CheckRow, variant: Scene, states) -> CheckRow:
    """The contact row, told where the user's run of the friction-off variant changed vx (a
    horizontal force that variant does not have: friction applied though it is off)."""
    from ..checks.contact_check import horizontal_force

    applied = horizontal_force(variant, states)
    if applied is None:
        return row
    return dataclasses.replace(row, reason=f"{applied['text']}. {row.reason}",
                               details={**row.details, "horizontal_force": applied})


def reference_rows(case: Case, tested: dict, runs: dict,
                   own_model: bool = True) -> tuple[list[CheckRow], np.ndarray | None]:
    """The error at the scene's dt against the converged reference, for each trajectory under
    test, beside custom_sim's for the same integrator (shown, not judged); and the reference's
    states. For custom_sim (own_model) the difference is the integrator's error at this dt; for
    another simulator it is model and integration together."""
    from ..oracle.reference import ReferenceFailed

    rows = []
    try:
        ref = case.reference()
    except ReferenceFailed as exc:
        return [CheckRow("reference", "accuracy at this dt", reason=f"no converged reference: {exc}")], None
    for name, run in tested.items():
        if isinstance(run, str):
            continue
        err = reference_error(run, ref.states)
        mine = runs.get(name)
        if own_model:
            isolates = "the integrator's error at this dt against the converged reference"
            reason = "shown, not judged: the numerical error of the integrator at the scene's dt"
        else:
            isolates = "difference to the scene model's converged solution (model and integration together)"
            reason = ("shown, not judged: your run against the scene's model solved to convergence; a difference "
                      "of model and one of integration both show here")
        details = {}
        if mine is not None and not isinstance(mine, str) and mine is not run:
            custom = reference_error(mine, ref.states)["position_error_max"]
            details["custom_sim_position_error_max"] = custom
            reason += f"; custom_sim with the same integrator and dt: {custom:.3g} m"
        rows.append(CheckRow("reference", isolates, name, **err, reason=reason, details=details))
    return rows, ref.states


def reference_error(run: Trajectory, ref_states: np.ndarray) -> dict:
    """position_error_max (m) and angle_error_max (rad) of the run against the reference."""
    s = run.states()
    n = min(len(s), len(ref_states))
    d = s[:n] - ref_states[:n]
    return {"position_error_max": float(np.max(np.hypot(d[:, 0], d[:, 1]))),
            "angle_error_max": float(np.max(np.abs(d[:, 2])))}


def stability(scene: Scene) -> tuple[list[str], float, str]:
    """The theory's stable step for the scene's integrator (s; inf: any) with its reason, and
    the line saying which effect's limit the scene's dt exceeds (none when within): scene-only
    work, kept in the cache."""
    from custom_sim.stability import warning

    limit, line = stable_step(scene), warning(scene)
    return ([line] if line else []), float(limit), getattr(limit, "reason", "")
