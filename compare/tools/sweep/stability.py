"""The stability table: per scene and integrator, the largest stable step h_max (s) found by
search beside the linear theory's limits (s) of custom_sim/stability.py, with the note on
reading it.
"""
from __future__ import annotations

import math

from ...table import markdown
from ..accuracy.stability_search import theory
from .wording import LABELS, num

STABILITY_HEADERS = [
    "scene", "integrator", "measured h_max (s)", "first threshold, before the scans (s)",
    "theory: contact spring, effective mass (s)", "theory: contact spring, point mass (s)",
    "theory: tanh friction (s)", "stable_step (the smaller) (s)", "measured / spring theory",
    "what failed just above h_max",
]


def stability_rows(sweep) -> list[list[str]]:
    """One row per limit the sweep measured on the scene (STABILITY_HEADERS)."""
    rows = []
    for lim in sweep.stability:
        if lim.simulator in ("custom", "yours"):
            if lim.integrator not in LABELS:   # "other:NAME": no theory of the harness's
                th = dict.fromkeys(("spring", "spring_point", "friction", "combined"), math.nan)
            else:
                th = theory(sweep.scene, lim.integrator)
        else:  # MuJoCo's Euler is semi-implicit; implicit(fast) integrate contact explicitly too
            th = theory(sweep.scene, "rk4" if lim.integrator == "RK4" else "semi_implicit_euler")
        spring = th["spring"]
        ratio = lim.h_max / spring if math.isfinite(spring) and spring > 0 else math.nan
        name = (LABELS.get(lim.integrator, lim.integrator) if lim.simulator == "custom" else
                f"yours: {LABELS.get(lim.integrator, lim.integrator)}" if lim.simulator == "yours" else
                f"MuJoCo {lim.integrator}")
        why = lim.reason or ("stable up to the largest step tried" if lim.capped else "")
        rows.append([sweep.scene.name, name, lim.text(), *map(num, (lim.first_threshold, spring, th["spring_point"],
                                                                    th["friction"], th["combined"])),
                     num(ratio, decimals=2), why])
    return rows


def stability_section(results) -> list[str]:
    """index.md's "Stability limits": how the limits were found, the table of every scene, the notes."""
    lines = ["", "## Stability limits", "",
             "Largest stable step found by bisection (to 1 %) and checked by a scan of 20 steps 2 % apart "
             "below it (stable and unstable steps interleave near the limit when a bouncing body spends only "
             "a few steps in each contact), beside the linear theory of "
             "custom_sim/stability.py split by what sets it: the contact spring-damper with the smallest "
             "effective mass at a contact point (a box corner: 1/m_eff = 1/m + r^2/I), the same with the "
             "whole mass at the point, and the tanh friction's stiff rate; `stable_step` is the smaller. "
             "`>=`: stable up to the largest step tried. MuJoCo rows use the semi-implicit theory (MuJoCo's "
             "Euler is semi-implicit, and all its integrators treat contact forces explicitly) or RK4's.", ""]
    lines += markdown(STABILITY_HEADERS, [row for sweep in results for row in stability_rows(sweep)]).splitlines()
    lines += ["", STABILITY_NOTES, ""]
    return lines


STABILITY_NOTES = """Reading the table:

- The theory is for a linear oscillator: a resting contact. Most scenes use the compression law,
  which damps only while a point moves into the ground, and explicit Euler's stability rests on
  damping alone; undamped (elastic_bounce) it has no stable step at all, and the figure is the
  step at which a 3 s run has gained 10 % (3 contacts, each multiplying the energy by about
  exp(pi h wn)).
- Where custom_sim's `stable_step` is set by the tanh friction (h lambda_f < 2, lambda_f =
  mu alpha Fn / m_t at the largest load Fn a point carries, an impact's peak), going past it makes
  the slip velocity flip sign every step around zero; tanh saturates, so this chatter stays
  bounded and gains no energy, but custom_sim's run stops on it (SimulationChattered) and the
  search counts it as unstable. docs/stability.md tables theory against measured.
- A bouncing body spends only a few steps in each contact near the limit, and what a bounce
  does to the energy then depends on where the touchdown falls inside a step: stable and
  unstable steps interleave, and the scan below the first threshold can move h_max far down
  (elastic_bounce: a symplectic Euler bounce changes the energy by O(h wn), so at a few ms one
  bounce already gains 10 %; the resting-contact theory does not apply).
- Implicit Euler has no linear limit, but its Newton solve meets the contact switch and the
  max() kink inside a step: at large steps on the tumbling bodies it can fail and diverge.
- MuJoCo's implicit and implicitfast equal its Euler here: they differ only in how joint damping
  and actuators are treated, and these twins have neither."""
