"""The seven built-in checks as units of the Check protocol (check.py), in the order of the
registry (registry.py); each measures and judges in its own module (*_check.py) and says here
only when it applies and which runs it takes."""
from __future__ import annotations

import dataclasses

import numpy as np

from custom_sim import INTEGRATORS, Scene, Trajectory
from scene_types.integrators import MUJOCO_TWIN

from .check import Runs
from .row import CheckRow

# damping families the contact check's variant (friction off, the linear law) can stand for: a
# user's code for compression or linear follows the scene's damping_law; one written for
# Hunt-Crossley or the unclamped law need not
LINEAR_KIN = ("compression", "linear")


def unstable_row(name: str, integrator: str, why: str) -> CheckRow:
    return CheckRow(name, "", integrator, reason=f"not judged: {integrator} is unstable at this step ({why})")


class Identical:
    """A user's run against custom_sim's, same integrator and dt (identical_check.py)."""

    name, needs = "identical", frozenset[str]()

    def applies(self, runs: Runs) -> bool:
        return runs.user

    def judge(self, runs: Runs) -> list[CheckRow]:
        from .identical_check import check_identical
        scene, run = runs.scene, runs.under_test
        return [check_identical(scene, run.states(), run.integrator, scene.dt, run.meta.get("rounding"),
                                case=runs.case)]


class Step:
    """Each run under test, step by step, against one independent step (step_check.py); its
    rows carry the per-step residuals and bounds for the plots."""

    name, needs = "step", frozenset[str]()

    def applies(self, runs: Runs) -> bool:
        return True

    def judge(self, runs: Runs) -> list[CheckRow]:
        from .step_check import check_step

        scene, rows = runs.scene, []
        for name, run in runs.tested.items():
            if isinstance(run, str):
                rows.append(unstable_row("step", name, run))
                continue
            # states read from a text file carry their rounding (fixed decimals or significant digits)
            rows.append(check_step(scene, run.states(), name, scene.dt, rounding=run.meta.get("rounding"),
                                   equations=runs.case.equations))
        return rows


class Dynamics:
    """Against MuJoCo integrating the same contact law (dynamics_check.py), for each run under
    test whose integrator MuJoCo has; an integrator the harness does not know is shown beside
    MuJoCo's RK4."""

    name, needs = "dynamics", frozenset({"mujoco"})

    def applies(self, runs: Runs) -> bool:
        return True

    def judge(self, runs: Runs) -> list[CheckRow]:
        from .dynamics_check import check_dynamics

        scene, rows = runs.scene, []
        for name in MUJOCO_TWIN:
            run = runs.tested.get(name)
            if run is not None:
                rows.append(unstable_row("dynamics", name, run) if isinstance(run, str)
                            else check_dynamics(scene, run.states(), name, scene.dt, run.meta.get("rounding")))
        tested = runs.under_test
        if runs.user and tested.integrator not in INTEGRATORS:
            rows.append(beside_rk4_dynamics(scene, tested))
        return rows


def beside_rk4_dynamics(scene: Scene, run: Trajectory) -> CheckRow:
    """An integrator the harness does not know, beside MuJoCo's RK4 under the same contact law
    at the same step: shown, not judged (no round-off bound holds between two methods)."""
    from .dynamics_check import check_dynamics

    row = check_dynamics(scene, run.states(), "rk4", scene.dt, run.meta.get("rounding"))
    return dataclasses.replace(
        row, integrator=run.integrator, tolerance_position=None, tolerance_angle=None, passed=None,
        reason=f"shown, not judged: {run.integrator!r} is not an integrator the harness knows, so it "
               "is shown beside MuJoCo's RK4 under the same contact law at the same step")


class Contact:
    """The run under test on the scene with friction off (and the linear law MuJoCo has),
    against MuJoCo's own contact (contact_check.py). A user's simulator is run again on that
    variant, which the harness made up, unless the scene is that variant already (its run under
    test is then the variant's); where it cannot run it (precomputed trajectories) or refuses it
    (raises, fails), the check is not judged, with the user's message; the rest stand."""

    name, needs = "contact", frozenset({"mujoco"})

    def applies(self, runs: Runs) -> bool:
        return True

    def judge(self, runs: Runs) -> list[CheckRow]:
        return [contact_row(runs)]


def contact_row(runs: Runs) -> CheckRow:
    from .contact_check import check_contact, contact_scene, not_judged

    scene, case, simulator = runs.scene, runs.case, runs.simulator
    if simulator is None:
        return check_contact(scene, case=case)
    under_test = runs.under_test
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
    from .contact_check import horizontal_force

    applied = horizontal_force(variant, states)
    if applied is None:
        return row
    return dataclasses.replace(row, reason=f"{applied['text']}. {row.reason}",
                               details={**row.details, "horizontal_force": applied})


class Reference:
    """The error at the scene's dt against the converged reference, for each run under test,
    beside custom_sim's for the same integrator (shown, not judged). For custom_sim the
    difference is the integrator's error at this dt; for another simulator it is model and
    integration together."""

    name, needs = "reference", frozenset({"reference"})

    def applies(self, runs: Runs) -> bool:
        return True

    def judge(self, runs: Runs) -> list[CheckRow]:
        from ..oracle.reference import ReferenceFailed

        rows = []
        try:
            ref = runs.case.reference()
        except ReferenceFailed as exc:
            return [CheckRow("reference", "accuracy at this dt", reason=f"no converged reference: {exc}")]
        for name, run in runs.tested.items():
            if isinstance(run, str):
                continue
            err = reference_error(run, ref.states)
            mine = runs.custom.get(name)
            if not runs.user:
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
        return rows


def reference_error(run: Trajectory, ref_states: np.ndarray) -> dict:
    """position_error_max (m) and angle_error_max (rad) of the run against the reference."""
    s = run.states()
    n = min(len(s), len(ref_states))
    d = s[:n] - ref_states[:n]
    return {"position_error_max": float(np.max(np.hypot(d[:, 0], d[:, 1]))),
            "angle_error_max": float(np.max(np.abs(d[:, 2])))}


class Native:
    """MuJoCo's own contact with every effect on: shown; judged only by a [tolerance] the scene
    file sets (native_check.py)."""

    name, needs = "native", frozenset({"mujoco"})

    def applies(self, runs: Runs) -> bool:
        return True

    def judge(self, runs: Runs) -> list[CheckRow]:
        from .native_check import native_row
        return [native_row(runs.scene, runs.twins.metrics)]


class Energy:
    """Where the simulator under test reports its own energy (custom_sim; a user's 7th column or
    `energy` column), that it is the energy of its states (compare/energy/column.py)."""

    name, needs = "energy", frozenset[str]()

    def applies(self, runs: Runs) -> bool:
        return not runs.user or runs.under_test.meta.get("energy_source") == "user"

    def judge(self, runs: Runs) -> list[CheckRow]:
        from ..energy.column import energy_column_check

        tested = runs.under_test
        verdict = energy_column_check(runs.scene, tested.states(), tested.energy)
        details = {"energy_difference_max": verdict.difference_max, "energy_tolerance_max": verdict.tolerance_max}
        return [CheckRow("energy", "the simulator's own energy column against the energy of its states "
                                   "(kinetic + m g y + sum k d^2 / 2)",
                         passed=verdict.agrees, reason=verdict.text, details=details, reason_at=len(details))]
