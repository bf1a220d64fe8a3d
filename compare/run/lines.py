"""What `run` prints: one line per scenario that ran (pass, FAIL with each failed check's
component and value in m, rad or per step, or not judged), at most LINE_LIMIT characters (the
rest is on the scene's page), and one line on the cache."""
from __future__ import annotations

from pathlib import Path

from ..checks.summary import StepFailure, read_summary


def _number(value, unit: str) -> str:
    return "–" if value is None else f"{value:.3e} {unit}"


# characters: a verdict line at most this long; what it cannot hold is on the scene's page
LINE_LIMIT = 160
SEE = " (see the page)"


def failure_parts(check) -> list[str]:
    """What a failed check (a CheckRow) measured, clause by clause: each quantity that left its
    tolerance, where it first did, and what else the check found."""
    d = check.details
    failure = StepFailure.of(check)
    if failure is not None:   # step: per component, per step
        return [failure.describe()]
    parts = []
    pos, tol_p = check.position_error_max, check.tolerance_position
    ang, tol_a = check.angle_error_max, check.tolerance_angle
    if pos is not None and tol_p is not None and pos > tol_p:
        parts.append(f"position {pos:.3e} m (tolerance {tol_p:.3e} m)")
    if ang is not None and tol_a is not None and ang > tol_a:
        parts.append(f"angle {ang:.3e} rad (tolerance {tol_a:.3e} rad)")
    if d.get("component_first_over") and d.get("first_step_over") is not None:
        parts.append(f"first at step {d['first_step_over']}, in {d['component_first_over']}")
    if d.get("horizontal_force"):
        parts.append(f"your step applied a horizontal force with friction off (step {d['horizontal_force']['step']})")
    if not parts:   # failed on something else (a non-finite state, ...): its reason says what
        parts.append(check.reason or f"position {_number(pos, 'm')}, angle {_number(ang, 'rad')}")
    return parts


def failure_text(check) -> str:
    """What a failed check (a CheckRow) measured: the component and value that left the tolerance."""
    return f"{check.label}: " + ", ".join(failure_parts(check))


def short_failure(check) -> str:
    """A failed check in a few words: its first clause (a step failure without its phase)."""
    failure = StepFailure.of(check)
    first = (f"{failure.over()} at step {failure.step} (t = {failure.time:.6g} s)" if failure is not None
             else failure_parts(check)[0])
    return f"{check.label}: {first}"


def fail_line(head: str, failed: list) -> str:
    """head, then the failed checks in at most LINE_LIMIT characters: each in full where all
    fit; else the first in a few words and the others named; else their names alone."""
    full = head + "; ".join(failure_text(c) for c in failed)
    if len(full) <= LINE_LIMIT:
        return full
    first, others = short_failure(failed[0]), failed[1:]
    for tail in ((f"; also {', '.join(c.name for c in others)}{SEE}" if others else SEE),
                 f"; {len(others)} more{SEE}"):
        if len(head + first + tail) <= LINE_LIMIT:
            return head + first + tail
    names = head + ", ".join(c.label for c in failed)
    return (names if len(names) + len(SEE) <= LINE_LIMIT else names[:LINE_LIMIT - len(SEE) - 3] + "...") + SEE


def verdict_line(summary) -> str:
    """The line `run` prints for a scenario that ran (its Summary, or its metrics.json dict):
    pass (with what was not judged), FAIL (each failed check's component and value), or not
    judged."""
    from ..checks.law_difference import judged_law_words

    s = read_summary(summary)
    name = s.name
    law = judged_law_words(s.law)
    under = f" under {law} (see the page)" if law else ""
    skipped = s.not_judged
    note = f"; not judged: {', '.join(skipped)} (see the page)" if skipped else ""
    if not s.judged:
        return f"{name:<20} not judged{under}: no check could be judged ({', '.join(skipped) or 'none'}; see the page)"
    if s.passed:
        return (f"{name:<20} pass{under}" if law else
                f"{name:<20} pass  {len(s.judged)} checks within tolerance{note}")
    return fail_line(f"{name:<20} FAIL{under}  ", [c for c in s.checks if c.passed is False])


def law_line(text: str) -> str:
    """A law sentence of a scenario's diagnosis, under its verdict line."""
    return f"{'':<20} law   {text}"


def no_verdict_line(name: str, status: str, why: str) -> str:
    """The line of a scenario that reached no verdict (error, unstable, timeout; skipped: a scene
    the code under test does not do): its status and why."""
    return f"{name:<20} skipped  {why}" if status == "skipped" else f"{name:<20} {status}: {why}"


def cache_line(rows, where: Path | None) -> str:
    """What came from the cache of scene-only work (compare/store.py) in the folder `where`
    (None: off), in one line; rows: the scenarios' Summaries (or metrics.json dicts)."""
    if where is None:
        return "cache: off (scene-only work computed)"
    counted = [s for s in map(read_summary, rows) if s.cache_hits is not None]
    hits = sum(s.cache_hits for s in counted)
    misses = sum(s.cache_misses for s in counted)
    whole = sum(1 for s in counted if s.cache_hits and not s.cache_misses)
    return (f"cache: {hits} of {hits + misses} scene-only runs from {where} ({whole} of {len(rows)} scenarios "
            f"wholly; --no-cache recomputes)")
