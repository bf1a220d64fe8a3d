"""Check `step`: every step of a trajectory against one independent step from the same state.

For each i, one step of the trajectory's integrator from states[i], taken with the reference's
own right-hand side (compare/oracle/force_law.py, geometry from rigid_body.py) and its own
one-step maps (one_step.py), must land on states[i+1] to round-off. Nothing is integrated over
more than one step, so the tumbling motion's sensitivity cannot hide or fake a difference, and
nothing is taken from custom_sim: the check is the same for any simulator.

    check_step(scene, states, integrator, dt) -> CheckRow   (row.residual: the per-step array)
"""
from __future__ import annotations

from dataclasses import dataclass

from typing import Any

import numpy as np

from scene_types.state import STATE_COMPONENTS, STATE_UNITS, UNIT_OF

from compare.oracle.force_law import SEED_LAW, Law, contact_state
from compare.oracle.reference import Equations

from ..oracle.one_step import (FORCE_ULPS, IMPLICIT_SOLVE_TOL, INPUT_ROUNDING_SAFETY, METHODS, NO_UNIQUE_STEP, STATE_ULPS,
                       Rounding, jump_defect, one_step, undecided)
from .row import CheckRow

COMPONENTS, UNITS = STATE_COMPONENTS, STATE_UNITS   # the state's, named once in scene_types/state.py
ISOLATES = "one step of the integrator from each state, against an independent right-hand side"
# Rows per array operation: bounds the memory of a million-step trajectory (a box's 4 points
# make about 20 temporaries of rows x 4 doubles) without costing speed.
CHUNK = 100_000


@dataclass(frozen=True)
class StepResiduals:
    """Per step i (0-based, the step from states[i] to states[i+1]):
    residual (n, 6) |independent step - states[i+1]| per component (m, rad, m/s, rad/s);
    bound (n, 6) its round-off bound; no_root (n,) implicit Euler steps whose equation has no
    root (judged at the jump, see one_step.jump_defect)."""

    residual: np.ndarray
    bound: np.ndarray
    no_root: np.ndarray
    jump_point: np.ndarray
    input_bound: np.ndarray | None = None   # (n, 6) the share of bound the states' own rounding makes
    undecided: np.ndarray | None = None     # (n,) implicit Euler steps a bare sign law leaves without a unique step

    @property
    def over(self) -> np.ndarray:
        """(n, 6) bool: residual above its bound."""
        return self.residual > self.bound

    def ratio(self) -> np.ndarray:
        """residual / bound (n, 6); 0 where both are 0, inf where only the bound is."""
        with np.errstate(divide="ignore", invalid="ignore"):
            r = self.residual / self.bound
        r[(self.residual == 0.0)] = 0.0
        return r


def step_residuals(eq: Equations, states: np.ndarray, integrator: str, dt: float,
                   law: Law = SEED_LAW, input_rtol=0.0, input_atol: float = 0.0) -> StepResiduals:
    """One step of `integrator` (with the force law `law`) from every row of states (T, 6)
    but the last, against the next row; input_rtol, input_atol: the states' own rounding
    beyond double precision, relative and absolute half units (input_rtol may be a Rounding,
    which gives both; see one_step)."""
    states = np.asarray(states, dtype=float)
    if isinstance(input_rtol, Rounding):
        input_rtol, input_atol = input_rtol.rtol, input_rtol.atol
    n = states.shape[0] - 1
    residual = np.empty((n, 6))
    bound = np.empty((n, 6))
    input_bound = np.zeros((n, 6))
    no_root = np.zeros(n, dtype=bool)
    open_steps = np.zeros(n, dtype=bool)
    jump_point = np.full(n, -1)
    for lo in range(0, n, CHUNK):
        hi = min(n, lo + CHUNK)
        Z0, Z1 = states[lo:hi], states[lo + 1:hi + 1]
        mine, b, solved, b_in = one_step(eq, Z0, dt, integrator, law, input_rtol, input_atol, parts=True)
        r = np.abs(mine - Z1)
        unsure = undecided(eq, solved, law)
        if unsure is not None and unsure.any():   # no step is the right one there: residual 0, not judged
            open_steps[lo:hi] = unsure
            r[unsure] = 0.0
            solved = solved | unsure
        if solved is not None and not solved.all():
            rows = np.flatnonzero(~solved)
            defect, point, depth = jump_defect(eq, Z0[rows], Z1[rows], dt, law)
            jump_point[lo + rows] = point
            defect[:, 1] = np.maximum(defect[:, 1], np.abs(depth))  # on the jump: d_j(q1) = 0
            r[rows] = defect
            no_root[lo + rows] = True
        residual[lo:hi], bound[lo:hi], input_bound[lo:hi] = r, b, b_in
    return StepResiduals(residual, bound, no_root, jump_point, input_bound, open_steps)


def _point_name(eq: Equations, i: int | np.integer) -> str:
    lx, ly = (v + 0.0 for v in eq.points[i])   # + 0.0: a -0.0 (a point at the centre) says 0, not -0
    return f"{i} ({lx:+.3g}, {ly:+.3g})"


def phase(eq: Equations, z0, z1=None) -> str:
    """What the body is doing at state z0 (and on the way to z1): flight; touchdown or lift-off
    of a point; which points touch, and whether they slide (|slip| > 1/alpha) or stick; rolling
    or resting for the circle."""
    depth, slip = contact_state(eq, np.atleast_2d(z0))
    touch = depth[0] > 0.0
    words = []
    if z1 is not None:
        depth1, _ = contact_state(eq, np.atleast_2d(z1))
        touch1 = depth1[0] > 0.0
        down = np.flatnonzero(touch1 & ~touch)
        up = np.flatnonzero(touch & ~touch1)
        if down.size:
            words.append("touchdown of point " + ", ".join(_point_name(eq, i) for i in down))
        if up.size:
            words.append("lift-off of point " + ", ".join(_point_name(eq, i) for i in up))
    if not eq.contact or not touch.any():
        return "; ".join(words + ["flight"]) if not words else "; ".join(words) + " (from flight)"
    idx = np.flatnonzero(touch)
    where = "contact at point " + ", ".join(_point_name(eq, i) for i in idx)
    if not eq.friction:
        return "; ".join(words + [where + ", no friction"])
    band = 1.0 / eq.alpha
    s = slip[0, idx]
    fast = np.abs(s) > band
    circle = eq.rotates and not eq.turning
    if circle and not fast.any():
        spin = abs(float(np.atleast_2d(z0)[0, 5])) * abs(eq.points[0][1])
        how = "rolling" if spin > band else "resting"
        text = f"{where}, {how} (|slip| {abs(s[0]):.3g} m/s <= 1/alpha = {band:.3g} m/s)"
    elif fast.all():
        text = f"{where}, sliding (|slip| {np.min(np.abs(s)):.3g} m/s > 1/alpha = {band:.3g} m/s)"
    elif not fast.any():
        text = f"{where}, sticking (|slip| {np.max(np.abs(s)):.3g} m/s <= 1/alpha = {band:.3g} m/s)"
    else:
        text = (f"{where}, sliding at point " + ", ".join(str(i) for i in idx[fast])
                + ", sticking at point " + ", ".join(str(i) for i in idx[~fast])
                + f" (1/alpha = {band:.3g} m/s)")
    return "; ".join(words + [text])


def _first_bad_finite(states: np.ndarray) -> int | None:
    ok = np.all(np.isfinite(states), axis=1)
    return None if ok.all() else int(np.argmin(ok))


# The residual figure samples each component at most this many times: the step of the largest
# residual / round-off in each of TRACE_RUNS equal runs of steps (a step over its bound always
# shows), a few per pixel column of an 800-pixel figure, so drawing costs the same at any length.
TRACE_RUNS = 1000


@dataclass(frozen=True)
class StepTrace:
    """The step check's residuals for the figure, per component (COMPONENTS, in UNITS): at each
    run of steps, the step (1-based) whose residual / round-off is largest, its residual and its
    round-off bound; each (n, 6), n <= TRACE_RUNS."""

    steps: np.ndarray
    residual: np.ndarray
    bound: np.ndarray


def step_trace(residual: np.ndarray, bound: np.ndarray, runs: int = TRACE_RUNS) -> StepTrace:
    """The StepTrace of the residuals (steps, 6) and their bounds (steps, 6)."""
    r, b = np.asarray(residual, dtype=float), np.asarray(bound, dtype=float)
    n = r.shape[0]
    width = max(1, -(-n // runs))
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(r == 0.0, 0.0, r / b)
    ratio = np.nan_to_num(ratio, nan=np.inf)
    starts = np.arange(0, n, width)
    pick = np.empty((len(starts), 6), dtype=int)
    for k, s in enumerate(starts):
        pick[k] = s + np.argmax(ratio[s:s + width], axis=0)
    cols = np.arange(6)
    return StepTrace(pick + 1, r[pick, cols], b[pick, cols])


# A rounding allowance above this fraction of the largest change a component makes in one step
# leaves that component nothing to judge: a mistake changing its step by less would pass.
ROUNDING_JUDGE_FRACTION = 0.1


def _moving(eq: Equations, states: np.ndarray) -> list[int]:
    """The components the body has (a point mass: x, y, vx, vy) that change over the run."""
    change = np.abs(np.diff(states, axis=0)).max(axis=0)
    return [c for c in (range(6) if eq.rotates else (0, 1, 3, 4)) if change[c] > 0.0]


def _swamped(eq: Equations, states: np.ndarray, res: StepResiduals) -> list[str]:
    """The moving components whose rounding allowance exceeds ROUNDING_JUDGE_FRACTION of their
    largest change per step."""
    change = np.abs(np.diff(states, axis=0)).max(axis=0)
    assert res.input_bound is not None   # step_residuals fills it
    allowance = res.input_bound.max(axis=0)
    return [COMPONENTS[c] for c in _moving(eq, states) if allowance[c] > ROUNDING_JUDGE_FRACTION * change[c]]


def _rounding_words(rounding: Rounding | None, input_rtol: float) -> str:
    said = ([rounding.describe()] if rounding else []) + ([f"{input_rtol:g} relative"] if input_rtol else [])
    return "the states' own rounding (" + " and ".join(said) + ")"


def check_step(scene, states, integrator: str | None, dt: float, law: Law = SEED_LAW,
               input_rtol=0.0, rounding: Rounding | None = None, equations: Equations | None = None) -> CheckRow:
    """The `step` check row for the trajectory `states` (steps + 1, 6), row 0 at t = 0, run with
    `integrator` at step `dt` (s); equations: the oracle's, if the caller has them (a Case).
    rounding: how the states were written, for trajectories read
    from text (Rounding: fixed decimals, an absolute half unit, or significant digits, a
    relative one), None for full double precision; input_rtol: a relative rounding given as a
    number instead (10 significant digits: 5e-10), or a Rounding. The rounding is carried
    through the step into the bound (one_step.input_rounding_bound); where it swamps the motion
    (ROUNDING_JUDGE_FRACTION), the row is not judged. Details: first_step, first_time, phase,
    component, residual_max (per component), bound_ratio_max, no_root_steps, steps_checked;
    row.residual: the (steps, 6) per-step residual array (for the plots)."""
    states = np.asarray(states, dtype=float)
    if isinstance(input_rtol, Rounding):
        input_rtol, rounding = 0.0, input_rtol
    rtol = float(input_rtol or 0.0) + (rounding.rtol if rounding else 0.0)
    atol = rounding.atol if rounding else 0.0
    details: dict = {"first_step": None, "first_time": None, "phase": None, "component": None, "residual_max": None}
    if integrator not in METHODS:
        return _unstepped(integrator, details, f"integrator {integrator!r} is not one the harness can step "
                                               f"(known: {', '.join(METHODS)}): not judged")
    if states.ndim != 2 or states.shape[1] != 6 or states.shape[0] < 2:
        return _unstepped(integrator, details, f"expected states of shape (steps + 1, 6) with at least one step, "
                                               f"got {states.shape}: not judged")
    bad = _first_bad_finite(states)
    if bad is not None:
        states = states[:bad]
        details["nonfinite_step"] = bad
        if states.shape[0] < 2:
            return _unstepped(integrator, details, f"state {bad} is not finite, no step before it to check: not judged",
                              passed=False)
    eq = equations or Equations.from_scene(scene)
    res = step_residuals(eq, states, integrator, dt, law, rtol, atol)
    r, b = res.residual, res.bound
    over = res.over
    ratio = res.ratio()
    pos, ang = np.hypot(r[:, 0], r[:, 1]), r[:, 2]
    measured: dict[str, Any] = {"position_error_max": float(pos.max()), "angle_error_max": float(ang.max())}
    tolerance = {"tolerance_position": float(np.hypot(b[:, 0], b[:, 1]).max()), "tolerance_angle": float(b[:, 2].max())}
    details.update(
        residual_max={c: float(v) for c, v in zip(COMPONENTS, r.max(axis=0))},
        bound_ratio_max=float(min(ratio.max(), 1e300)),
        steps_checked=int(r.shape[0]),
        no_root_steps=int(res.no_root.sum()),
    )
    failing = np.flatnonzero(over.any(axis=1))
    passed = failing.size == 0 and bad is None
    solve = (f"; implicit Euler also the Newton tolerance {IMPLICIT_SOLVE_TOL:g} m/s on v1 and "
             f"h times it on q1" if integrator == "implicit_euler" else "")
    jumps = (f"; {int(res.no_root.sum())} touchdown step(s) where the implicit equation has no root "
             f"were judged at the jump (d = 0 and the hull of the jump)" if res.no_root.any() else "")
    reason = (f"round-off of two codes evaluating the same step, per step and component: "
              f"{STATE_ULPS:g} ulps of |z0| + |z1| and {FORCE_ULPS:g} ulps of h times the "
              f"magnitude of the force terms{solve}{jumps}"
              + ("; plus " + _rounding_words(rounding, input_rtol) + ": the next state's half unit, "
                 f"and {INPUT_ROUNDING_SAFETY:g} x how far the half units of the state before move the "
                 "step (stiff contact and sharp friction amplify them)" if rtol or atol else "")
              + "; the tolerances shown are the largest per-step bounds")
    swamped = _swamped(eq, states, res) if (rtol or atol) else []
    # a residual over the (honest) bound is a failure whatever the rounding; only a pass that
    # the rounding could be hiding a mistake in becomes "not judged"
    if swamped and len(swamped) == len(_moving(eq, states)) and passed:
        return CheckRow("step", ISOLATES, integrator, **measured, details=details, reason_at=len(details), residual=r,
                        bound=b,
                        reason="not judged: " + _rounding_words(rounding, input_rtol) + " carried through one step "
                        f"exceeds {ROUNDING_JUDGE_FRACTION:g} of the largest change per step of every component "
                        "that moves (" + ", ".join(swamped) + "), so a mistake could hide in the rounding; "
                        "write more digits (%.17g keeps a double exactly)")
    if swamped:
        reason += ("; the rounding allows " + ", ".join(swamped) + f" more than "
                   f"{ROUNDING_JUDGE_FRACTION:g} of its largest change per step, so these say little")
    reason_at = len(details)
    if failing.size:
        i = int(failing[0])
        comp = int(np.argmax(np.where(over[i], ratio[i], -1.0)))
        where = phase(eq, states[i], states[i + 1])
        if res.no_root[i]:
            where = (f"touchdown of point {_point_name(eq, int(res.jump_point[i]))} where the implicit "
                     f"equation has no root (judged at the jump); before it: {phase(eq, states[i])}")
        details.update(first_step=i + 1, first_time=float((i + 1) * dt), phase=where,
                       component=COMPONENTS[comp],
                       failing_steps=int(failing.size),
                       first_residual=float(r[i, comp]), first_bound=float(b[i, comp]))
    if res.undecided is not None and res.undecided.any():
        details["undecided_steps"] = int(res.undecided.sum())
        reason += f"; {details['undecided_steps']} step(s) not judged: {NO_UNIQUE_STEP}"
    if bad is not None:
        reason += f"; state {bad} is not finite (checked up to it)"
    return CheckRow("step", ISOLATES, integrator, **measured, **tolerance, passed=bool(passed), reason=reason,
                    details=details, reason_at=reason_at, residual=r, bound=b)


def _unstepped(integrator: str | None, details: dict, reason: str, passed: bool | None = None) -> CheckRow:
    """A step row with nothing measured: every detail so far precedes the reason."""
    return CheckRow("step", ISOLATES, integrator, passed=passed, reason=reason, details=details,
                    reason_at=len(details))


def first_failure(row: CheckRow) -> str:
    """Where a step check's row first fails, in one clause: the first step over round-off (its
    time, phase, and the component off, by how much), or the first state that is not finite."""
    from .summary import StepFailure

    failure = StepFailure.of(row)
    if failure is None:
        return f"state {row.details.get('nonfinite_step')} is not finite (every step before it within round-off)"
    return f"first step over round-off: {failure.step} (t = {failure.time:.6g} s), {failure.phase}, {failure.over()}"


def first_over(row: CheckRow) -> str:
    """A failed step row's first component over round-off, in its own unit (a mistake in a
    force moves the velocities first: positions follow a step later)."""
    from .summary import StepFailure
    failure = StepFailure.of(row)
    return failure.over() if failure is not None else ""


def largest_residual(row: CheckRow) -> str:
    """The largest residual over the run of the component a failed step row first failed in."""
    d = row.details
    if d.get("component") is None:
        return f"largest residual {row.position_error_max:.3g} m, {row.angle_error_max:.3g} rad"
    unit = UNIT_OF[d["component"]]
    return f"largest {d['component']} residual {d['residual_max'][d['component']]:.3g} {unit}"
