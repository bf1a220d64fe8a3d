"""The energy residual R(end) (J) of each run, E(end) - E(0) + W (docs/energy-balance.md): the
order at which it falls with dt (s), against the integrator's, and the table of it per scene,
naming the contact events where they lower that order.
"""
from __future__ import annotations

import math

import numpy as np

from scene_types.integrators import ORDER

from ...table import DASH, markdown
from .wording import SIMULATOR, num

# R(end) shrinks with dt at the integrator's order (ORDER), away from contact events
ORDER_SLACK = 0.3   # a fitted slope this far below the order means something lowers it
ORDER_POINTS = 3    # the finest steps: the asymptotic regime, where the order shows
ROUNDOFF_ULPS = 10  # each step's energy sum rounds by a few eps of the energy: below 10 eps a step, R is round-off
EPS = float(np.finfo(float).eps)


def residual_order(runs, floor: float = 0.0) -> float:
    """The slope of log |R(end)| against log dt over the ORDER_POINTS finest stable runs whose
    |R(end)| stands above `floor` (J, the round-off of summing the energy over the run's
    steps); nan with fewer than two."""
    pts = [(r.dt, abs(r.residual_end)) for r in runs
           if r.stable and math.isfinite(r.residual_end) and abs(r.residual_end) > floor * r.steps]
    pts = sorted(pts)[:ORDER_POINTS]
    if len(pts) < 2:
        return math.nan
    dts, rs = np.log([p[0] for p in pts]), np.log([p[1] for p in pts])
    return float(np.polyfit(dts, rs, 1)[0])


def roundoff_floor(sweep) -> float:
    """J per step: the round-off of the energy sums, ROUNDOFF_ULPS eps of the run's energy scale."""
    return ROUNDOFF_ULPS * EPS * float(sweep.reference.get("energy_scale", 1.0))


def residual_rows(sweep) -> list[str]:
    """Per integrator: R(end) at each dt, its measured order against the expected one, and
    the contact events when they lower it."""
    switches = ", ".join(f"{v} {k}" for k, v in sweep.reference["switches"].items() if v)
    rows = []
    for sim, integ in dict.fromkeys((r.simulator, r.integrator) for r in sweep.runs):
        runs = sweep.of(sim, integ)
        order, expected = residual_order(runs, roundoff_floor(sweep)), ORDER.get(integ)
        values = ", ".join(f"{r.residual_end:.2g} ({r.dt:g} s)" for r in runs
                           if r.stable and math.isfinite(r.residual_end))
        note = ""
        if sim == "mujoco" and integ == "RK4":
            note = ("not measured: the work of MuJoCo's RK4 needs its four stages' constraint forces, which its states "
                    "do not carry (compare.energy.mujoco_side.native_balance steps it row by row)")
        elif math.isfinite(order) and expected and order < expected - ORDER_SLACK:
            note = (f"lowered by the contact events ({switches} switches of the reference): a step across a switch "
                    "integrates the force's jump or kink at first or second order" if switches else
                    "lower than expected without a contact event")
        rows.append([SIMULATOR[sim], integ, values or DASH, num(order, decimals=2),
                     expected or DASH, note])
    return markdown(["simulator", "integrator", "R(end) at each dt (J)", "measured order", "expected", "note"],
                    rows).splitlines() + [""]

