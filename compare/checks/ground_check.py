"""Check ground: no body falls through the ground. custom_sim's healthy range (integrators.
is_healthy) bounds the kinetic and gravitational energy only, and a body sinking through the
floor loses gravitational energy: it stays "healthy". Counting the energy its contact springs
store (sum k d^2 / 2 over the points under the ground) closes that gap: a passive scene's total
energy never exceeds what it started with (more by the integrator's error), so a run whose
total passes the healthy budget has pushed a spring deeper than the scene's energy could.

    Ground          the unit (check.py protocol): one row, the run under test's
    ground_row      the row of one run's states
"""
from __future__ import annotations

import numpy as np

from custom_sim import Scene, mass_properties
from custom_sim.energy import energy_parts
from custom_sim.runner import ENERGY_GROWTH_LIMIT, blowup_guard

from .check import Runs
from .row import CheckRow

ISOLATES = "the run's total energy with its contact springs' (sum k d^2 / 2) against the healthy budget"


def ground_row(scene: Scene, states: np.ndarray, integrator: str | None) -> CheckRow:
    """The ground row of a run's states (steps + 1, 6): judged on a scene with gravity and
    contact; passes while the total energy above the lowest pose (J), springs included, stays
    within custom_sim's budget (ENERGY_GROWTH_LIMIT times the start, at least its floor)."""
    if not (scene.has("contact") and scene.has("gravity")):
        return CheckRow("ground", ISOLATES, integrator, reason="not judged: the scene has no ground to fall through")
    props = mass_properties(scene.body)
    _, _, _, _, budget, _, _ = blowup_guard(scene, props, states[0], applied_input=False)
    y_low = -float(np.max(np.hypot(props.points[:, 0], props.points[:, 1])))   # COM on its lowest pose
    kinetic, gravity, springs = energy_parts(scene, props, states)
    total = kinetic + gravity - props.mass * scene.g * y_low + springs   # J, above the lowest pose
    over = np.flatnonzero(total > budget)
    details = {"energy_max": float(np.max(total)), "energy_budget": float(budget)}
    if over.size:
        n = int(over[0])
        details["first_step"] = n
        reason = (f"the body sank through the ground: at step {n} (t = {n * scene.dt:.6g} s) its energy with the "
                  f"contact springs' is {total[n]:.4g} J, over the budget of {budget:.4g} J "
                  f"({ENERGY_GROWTH_LIMIT:g} times its start): a contact force too weak, missing or of the wrong sign")
        return CheckRow("ground", ISOLATES, integrator, passed=False, reason=reason, details=details,
                        reason_at=len(details))
    reason = (f"energy with the contact springs' at most {details['energy_max']:.4g} J, within the budget of "
              f"{budget:.4g} J ({ENERGY_GROWTH_LIMIT:g} times its start)")
    return CheckRow("ground", ISOLATES, integrator, passed=True, reason=reason, details=details,
                    reason_at=len(details))


class Ground:
    """No body falls through the ground (module docstring): the run under test's row."""

    name, needs = "ground", frozenset[str]()

    def applies(self, runs: Runs) -> bool:
        return runs.scene.has("contact") and runs.scene.has("gravity")

    def judge(self, runs: Runs) -> list[CheckRow]:
        tested = runs.under_test
        return [ground_row(runs.scene, tested.states(), tested.integrator)]
