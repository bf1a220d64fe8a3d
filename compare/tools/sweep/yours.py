"""What the sweep says of the user's simulator (--sim): per integrator its fitted order beside the
integrator's and custom_sim's, its largest stable step beside custom_sim's theory (s) and what
stopped it, its time per step (s), the plain sentence where its order is not its integrator's,
and the integrators its code does not do.
"""
from __future__ import annotations

import math

from scene_types.integrators import ORDER

from ...table import markdown
from ..accuracy.orders import mismatch, order_of
from ..accuracy.stability_search import theory
from ..accuracy.workprecision import TARGET_ERROR, qualifying
from .wording import LABELS, mm, ms, num


def per_step(runs) -> tuple[float, float]:
    """(CPU, wall) s per step of the user's code: its longest stable run's over its steps (the
    fixed cost of a call, the fresh import, spread thinnest). CPU first, as for custom_sim's: on a
    shared machine the wall time also counts the time given to other processes."""
    timed = [r for r in runs if r.stable and math.isfinite(r.cpu_time)]
    if not timed:
        return math.nan, math.nan
    longest = max(timed, key=lambda r: r.steps)
    return longest.cpu_time / longest.steps, longest.wall_time / longest.steps


def limit_of(sweep, integrator: str):
    return next((lim for lim in sweep.stability if lim.simulator == "yours" and lim.integrator == integrator), None)


def stable_text(sweep, integrator: str) -> str:
    """'largest stable step 4.75 ms (custom_sim's theory for rk4: 3.1 ms; above it: chatter ...)'."""
    lim = limit_of(sweep, integrator)
    if lim is None:
        return ""
    text = f"largest stable step {lim.text()} s"
    if integrator in ORDER and integrator in LABELS:
        th = theory(sweep.scene, integrator)["combined"]
        text += (f" (custom_sim's theory for {integrator} under this law: "
                 f"{'no limit' if math.isinf(th) else f'{th:.3g} s'}")
        ours = next((x for x in sweep.stability if x.simulator == "custom" and x.integrator == integrator), None)
        text += f"; custom_sim's measured: {ours.text()} s)" if ours else ")"
    why = lim.reason or ("stable up to the largest step tried" if lim.capped else "")
    return text + (f"; above it: {why}" if why else "")


def yours_lines(sweep) -> list[str]:
    """Per integrator the user's code ran: one line of order, stable step and time per step;
    then the mismatch sentences and the integrators it does not do."""
    yours = sweep.yours or {}
    lines = []
    for integ in yours.get("integrators", []):
        runs = sweep.of("yours", integ)
        order, ours = order_of(sweep, "yours", integ), order_of(sweep, "custom", integ)
        parts = [f"yours, {LABELS.get(integ, integ)}: error falls at order {num(order, decimals=2)}"
                 + (f" (custom_sim's: {num(ours, decimals=2)}; {integ}'s: {ORDER[integ]})" if integ in ORDER else "")]
        best = min(qualifying(runs), key=lambda r: r.cpu_time, default=None)
        if best:
            parts.append(f"fastest within 1 mm: dt = {best.dt:g} s, {ms(best.cpu_time)} a run ({mm(best.error_max)})")
        else:
            parts.append(f"no rung within {mm(TARGET_ERROR)}")
        cpu, wall = per_step(runs)
        if math.isfinite(cpu):
            parts.append(f"{cpu * 1e6:.3g} us CPU per step (wall {wall * 1e6:.3g} us)")
        stable = stable_text(sweep, integ)
        if stable:
            parts.append(stable)
        lines.append("; ".join(parts))
        sentence = mismatch(sweep, integ)
        if sentence:
            lines.append(sentence)
    for integ, why in yours.get("skipped", {}).items():
        lines.append(f"yours, {LABELS.get(integ, integ)}: not run, your code does not do it ({why})")
    return lines


def orders_table(sweep) -> list[str]:
    """The fitted orders of every simulator and integrator, the steps (s) they were fitted over."""
    from ..accuracy.orders import orders
    rows = [[e["simulator"], e["integrator"], num(e["order"], decimals=2), ORDER.get(e["integrator"], "-"),
             ", ".join(f"{dt:g}" for dt in e["dts"]) or "-"] for e in orders(sweep)]
    return markdown(["simulator", "integrator", "fitted order", "the integrator's", "fitted over dt (s)"],
                    rows).splitlines()


def yours_section(sweep) -> list[str]:
    """index.md's part of a scene on the user's code (nothing without one)."""
    if not sweep.yours:
        return []
    return ["", f"**Your simulator** (`{sweep.yours['label']}`):", "",
            *[f"- {line}" for line in yours_lines(sweep)], "",
            ("**Orders** (slope of log max error against log dt over the finest rungs whose error stands above "
             "the reference's own; MuJoCo's against its own converged solution):"), "", *orders_table(sweep), ""]
