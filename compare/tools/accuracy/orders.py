"""The order at which each integrator's error falls with its step, fitted over the sweep's ladder.

    fitted_order(runs, floor) -> (order, dts)       slope of log(max error) against log dt (s)
    orders(sweep) -> [{"simulator", "integrator", "order", "dts"}]   one per simulator and integrator
    mismatch(sweep, integrator) -> str              the plain sentence where the user's order is not
                                                    its integrator's

Errors (m): custom_sim's and the user's against the reference, MuJoCo's against its own
converged solution (its numerical error, not the model difference).
"""
from __future__ import annotations

import math

import numpy as np

from scene_types.integrators import ORDER

ORDER_POINTS = 3      # the finest rungs above the floor: the asymptotic regime, where the order shows
# An error within FLOOR_REFERENCE times the reference's own (its change at a 100-fold tighter
# tolerance; MuJoCo: its converged solution's change at twice the step) measures that, not the
# integrator; nor does one within FLOOR_ROUNDOFF eps of the motion's size (round-off of positions).
FLOOR_REFERENCE = 10.0
FLOOR_ROUNDOFF = 100.0
EPS = float(np.finfo(float).eps)
# A fitted order this far from another is a different order (the residual's slack, residual.py):
# away from contact events a method's fit lands within 0.05 (tests/compare/tools/test_workprecision.py).
ORDER_SLACK = 0.3


def fitted_order(runs, floor: float, self_error: bool = False) -> tuple[float, list[float]]:
    """(slope of log error against log dt, the steps it was fitted over (s)) over the
    ORDER_POINTS finest stable runs whose error stands above floor (m); (nan, []) with fewer
    than two."""
    pts = sorted((r.dt, r.error_max_self if self_error else r.error_max) for r in runs if r.stable)
    pts = [(dt, e) for dt, e in pts if math.isfinite(e) and e > floor][:ORDER_POINTS]
    if len(pts) < 2:
        return math.nan, []
    dts = [dt for dt, _ in pts]
    slope = np.polyfit(np.log(dts), np.log([e for _, e in pts]), 1)[0]
    return float(slope), sorted(dts, reverse=True)


def floors(sweep) -> dict:
    """m: below these an error is not the integrator's (per simulator)."""
    ref = sweep.reference
    size = float(np.max(np.abs(ref["states"][:, :2]))) if "states" in ref else 1.0
    ours = max(FLOOR_REFERENCE * ref.get("change_at_tighter_tolerance", 0.0), FLOOR_ROUNDOFF * EPS * size)
    conv = sweep.mujoco_converged or {}
    theirs = max(FLOOR_REFERENCE * conv.get("change_at_double_step", 0.0), FLOOR_ROUNDOFF * EPS * size)
    return {"custom": ours, "yours": ours, "mujoco": theirs}


def orders(sweep) -> list[dict]:
    """One entry per simulator and integrator of the sweep's runs: the fitted order (None when
    fewer than two rungs stand above the floor) and the steps (s) it was fitted over."""
    floor = floors(sweep)
    out = []
    for sim, integ in dict.fromkeys((r.simulator, r.integrator) for r in sweep.runs):
        order, dts = fitted_order(sweep.of(sim, integ), floor[sim], self_error=sim == "mujoco")
        out.append({"simulator": sim, "integrator": integ, "order": order if math.isfinite(order) else None,
                    "dts": dts})
    return out


def order_of(sweep, simulator: str, integrator: str) -> float:
    """The fitted order of one simulator's integrator on the sweep's scene (nan: not fitted)."""
    for entry in orders(sweep):
        if (entry["simulator"], entry["integrator"]) == (simulator, integrator) and entry["order"] is not None:
            return entry["order"]
    return math.nan


def mismatch(sweep, integrator: str) -> str:
    """"you declare rk4; your error falls at order 1.0" where the user's fitted order is not the
    integrator's (ORDER), beyond ORDER_SLACK, nor what custom_sim's same integrator shows on this
    scene (contact events lower both alike); "" otherwise. `integrator`: the one it was run as."""
    yours = order_of(sweep, "yours", integrator)
    expected = ORDER.get(integrator)
    if not math.isfinite(yours) or expected is None or abs(yours - expected) <= ORDER_SLACK:
        return ""
    ours = order_of(sweep, "custom", integrator)
    if math.isfinite(ours) and abs(yours - ours) <= ORDER_SLACK:
        return ""
    said = "you declare" if (sweep.yours or {}).get("declared") else "your code is handed"
    text = f"{said} {integrator}; your error falls at order {yours:.1f}"
    if math.isfinite(ours):
        text += f" (custom_sim's {integrator} here: {ours:.1f}; {integrator}'s order is {expected})"
    return text
