"""The sweep's plain answer for one scene: the cheapest run within 1 mm (TARGET_ERROR, m) in each
simulator, or the closest one and why none is within, with CPU times (s) only as far as their
spread tells them apart. The ranking itself is compare/tools/accuracy/workprecision.py's.
"""
from __future__ import annotations

import math

from ..accuracy.workprecision import TARGET_ERROR, best_error, clearly_faster, fastest, ranking
from .wording import cost, mm, name, timing


def time_verdict(win, others) -> str:
    """What the CPU times say about win against others, only as far as their spread allows."""
    if not others:
        return ""
    quickest, ties = fastest([win, *others])
    if quickest is win:
        return "; also the fastest in CPU time" + (
            f" (within the timing spread of {', '.join(name(r) for r in ties)})" if ties else ", beyond the timing spread")
    if win in ties:
        return f"; by CPU time {name(quickest)} ({timing(quickest)}) cannot be told from it"
    return f"; by CPU time {name(quickest)} at dt = {quickest.dt:g} s is faster beyond the spread ({timing(quickest)})"


def answer(sweep) -> str:
    """'What is the cheapest way to reach 1 mm here?' in a few plain sentences: the run with the
    fewest force evaluations (counted, so the same on every rerun), its time beside it, and what
    the times say only where they differ by more than their measured spread."""
    ours = [r for r in sweep.runs if r.simulator == "custom"]
    theirs = [r for r in sweep.runs if r.simulator == "mujoco"]
    parts = []
    ranked = ranking(ours)
    win = ranked[0] if ranked else None
    if win:
        text = (f"ours: {name(win)} at dt = {win.dt:g} s, {cost(win)}, {timing(win)} for the "
                f"{sweep.scene.duration:g} s run, max error {mm(win.error_max)}")
        if len(ranked) > 1:
            nxt = ranked[1]
            text += f"; next {name(nxt)} at dt = {nxt.dt:g} s, {nxt.force_evals} force evaluations, {timing(nxt)}"
        parts.append(text + time_verdict(win, ranked[1:]) + ".")
    else:
        best = best_error(ours)
        why = ""
        amp = sweep.reference.get("amplification", 1.0)
        if amp > 100:
            why = (f" The motion amplifies a small error about {amp:.0f}-fold (a tumbling landing), "
                   f"so 1 mm at the end needs about {mm(TARGET_ERROR / amp)} before it.")
        parts.append(f"ours: no step on the ladder reaches 1 mm; the best is {name(best)} at "
                     f"dt = {best.dt:g} s ({mm(best.error_max)}, {timing(best)}).{why}"
                     if best else "ours: no stable run.")
    if theirs:
        own_ranked = ranking(theirs, self_error=True)
        own = own_ranked[0] if own_ranked else None
        if own:
            if win and clearly_faster(win, own):
                versus = f", {own.cpu_time / win.cpu_time:.0f}x the time of our cheapest"
            elif win:
                versus = ", not distinguishable in time from our cheapest"
            else:
                versus = ""
            parts.append(f"MuJoCo: {own.integrator} at dt = {own.dt:g} s, {cost(own)}, {timing(own)}, stays "
                         f"within 1 mm of its own converged solution ({mm(own.error_max_self)}){versus}.")
        else:
            best = best_error(theirs, self_error=True)
            if best:
                parts.append(f"MuJoCo: no step on its ladder reaches 1 mm of its own converged solution "
                             f"(best {best.integrator} at dt = {best.dt:g} s: {mm(best.error_max_self)}).")
        floor = sweep.mujoco_converged.get("change_at_double_step", 0.0)
        if floor > 0.1 * TARGET_ERROR:
            parts.append(f"(MuJoCo's converged solution itself moves {mm(floor)} when its step doubles, so "
                         f"its own error is known only to about that.)")
        model = sweep.mujoco_converged.get("error_max", math.nan)
        vs_ref = ranking(theirs)
        if vs_ref:
            parts.append(f"Against our reference MuJoCo reaches 1 mm with {vs_ref[0].integrator} at "
                         f"dt = {vs_ref[0].dt:g} s: {cost(vs_ref[0])}, {timing(vs_ref[0])}.")
        elif math.isfinite(model):
            parts.append(f"Against our reference it cannot: its converged solution itself is {mm(model)} "
                         f"from ours (model difference, not step size).")
    return " ".join(parts)
