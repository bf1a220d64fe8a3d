"""Energy as a symptom: a user's run that gains energy where custom_sim, under the same law and
integrator, loses it (docs/energy-balance.md): some force of the user's does positive work."""
from __future__ import annotations

import numpy as np

from custom_sim import INTEGRATORS, Scene, SimulationDiverged

from ..checks.case import as_case


def energy_gain(scene: Scene, states, integrator: str, rounding=None, case=None) -> dict | None:
    """{user, custom, margin, text} (J) where the user's run (states (steps + 1, 6)) ends its
    work-energy balance R = E - E(0) + W above zero by more than `margin`, while custom_sim's
    run of the same scene, law and integrator ends it below zero; else None. R of the exact
    motion is zero; custom_sim's own |R| over its run (plus each balance's quadrature bound)
    is what the integrator itself makes at this dt, so a gain beyond it is no integration error."""
    from ..energy import balance

    if integrator not in INTEGRATORS:
        return None
    states = np.asarray(states, dtype=float)
    if not np.all(np.isfinite(states)):
        return None
    case = as_case(scene, case)
    try:
        ours = case.trajectory(integrator)
    except SimulationDiverged:
        return None
    rule = None if rounding else integrator
    mine = balance(case.variant(integrator), np.arange(len(states)) * scene.dt, states, rule)
    theirs = balance(case.variant(integrator), ours.t, ours.states(), ours.integrator)
    user, custom = float(mine.R[-1]), float(theirs.R[-1])
    margin = float(np.max(np.abs(theirs.R))) + mine.quadrature_bound + theirs.quadrature_bound
    if not (user > margin and custom < 0.0):
        return None
    return {"user": user, "custom": custom, "margin": margin,
            "text": (f"your run gains {user:.3g} J against the scene's law (work-energy balance E - E(0) + W at the "
                     f"end), where custom_sim under the same law and {integrator} loses {-custom:.3g} J: a force of "
                     "yours does positive work, or dissipates less than the scene's law")}
