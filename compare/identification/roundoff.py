"""How closely a step can reproduce a law: the named round-off tolerances and the bounds they give."""
from __future__ import annotations

import contextvars

import numpy as np

from .integrators import evaluated_at, rk4_step
from .model import Law, accelerations, force_terms

EPS = float(np.finfo(float).eps)
# v1 = fl(v0 + fl(h a)) rounds twice in the user's step, and v1 - v0 is read back here: a few
# ulps of |v0| + |v1|, divided by h when turned into a force.
STATE_ULPS = 4.0
# A force term passes about a dozen roundings (the arm's rotation, the depth, the damper, tanh,
# the sum over points, the product with 1/m) in each of two codes that may round every one
# differently: 32 ulps of the sum of the terms' magnitudes (model.force_terms).
FORCE_ULPS = 32.0
# An implicit Euler step is the root of an equation solved to a tolerance, not to round-off:
# the harness holds a simulator's implicit Euler to custom_sim's Newton tolerance (m/s, rad/s,
# compare/oracle/one_step.py), so its v1, and the state the force is read at, may be this far
# from the exact root.
IMPLICIT_SOLVE_TOL = 1e-10
# A contact point found where contact begins (bisection on the height) is off by the rounding of
# the user's r = R(theta) l and of d = -(y + r_y): a few ulps of |y| + |l|.
POINT_ULPS = 8.0
# A state read from a file carries the file's rounding into the force through the law's slopes;
# the first-order (secant) estimate is doubled, as the harness's step check does (one_step.py).
INPUT_ROUNDING_SAFETY = 2.0


# A step that computes in float32 and hands back float64 (astype, float()) rounds every
# operation to 24 bits: each ulp count above is then in single precision's eps (1.2e-7
# relative, not 2.2e-16), and the state it is given is itself rounded to float32 on the way in
# (half an ulp, 6e-8 relative), which the law carries like a file's rounding.
FLOAT32_EPS = float(np.finfo(np.float32).eps)
# Returned numbers that must differ from the state given before "every number a float32
# value" says anything: a float64 step returns such numbers only where nothing moved.
FLOAT32_MIN_CHANGED = 8
# float32 arithmetic found in the step under identification (set_single_precision): a context
# variable, so that one scene's setting ends with its own identification (in_own_context)
_SINGLE: contextvars.ContextVar[bool] = contextvars.ContextVar("single_precision", default=False)


class SinglePrecision:
    """The rounding of a state read in float32: half an ulp of each value (Rounding's interface)."""

    def half_unit(self, values) -> np.ndarray:
        return 0.5 * FLOAT32_EPS * np.abs(np.asarray(values, dtype=float))

    def describe(self) -> str:
        return "float32 arithmetic (6e-8 relative)"


SINGLE = SinglePrecision()


def is_float32(Z0: np.ndarray, Z1: np.ndarray) -> bool:
    """Whether every number a step returned (Z1, from Z0) is exactly a float32 value, over
    enough numbers that moved for that to be its arithmetic and not chance."""
    Z0, Z1 = np.asarray(Z0, dtype=float), np.asarray(Z1, dtype=float)
    with np.errstate(over="ignore"):
        exact = np.all(Z1.astype(np.float32).astype(float) == Z1)
    return bool(exact and np.count_nonzero(Z1 != Z0) >= FLOAT32_MIN_CHANGED)


def set_single_precision(on: bool) -> None:
    """Hold every bound below to float32 (on) or float64 round-off, for the rest of the current
    context (one identification, run by in_own_context)."""
    _SINGLE.set(bool(on))


def single_precision() -> bool:
    return _SINGLE.get()


def in_own_context(run):
    """run() in a copy of the current context: the precision it sets ends with it."""
    return contextvars.copy_context().run(run)


def eps() -> float:
    """The unit round-off the step's arithmetic carries: float64's, or float32's."""
    return FLOAT32_EPS if _SINGLE.get() else EPS


def inertias(law: Law) -> np.ndarray:
    """(m, m, I): what turns each channel's acceleration into a force (N) or torque (N m); the
    point mass's angular channel is scaled by 1 (it must not turn at all)."""
    return np.array([law.mass, law.mass, law.inertia if law.geometry.rotates else 1.0])


def _sensitivity(rate, Z: np.ndarray, dz: np.ndarray) -> np.ndarray:
    """sum_j |rate(z + dz_j e_j) - rate(z - dz_j e_j)| / 2 (n, 3): the change of a step's
    velocity change over h across an uncertainty dz (n, 6) of the state it starts from (a secant,
    so kinks count, and for RK4 a contact switch crossed by any of its stages)."""
    out = np.zeros((Z.shape[0], 3))
    for j in range(6):
        if not np.any(dz[:, j]):
            continue
        e = np.zeros(6)
        e[j] = 1.0
        step = dz[:, j:j + 1] * e
        out += 0.5 * np.abs(rate(Z + step) - rate(Z - step))
    return out


def rate_bound(law: Law, integrator: str, Z0: np.ndarray, Z1: np.ndarray, H: np.ndarray,
               rounding=None, sensitivity: bool = True) -> np.ndarray:
    """The round-off bound (n, 3) in N, N, N m on m (v1 - v0)/h - m a_law for each row: the
    velocity change read back, the law's terms, implicit Euler's solve tolerance, and a file's
    rounding (compare.oracle.one_step.Rounding, or None for full precision). sensitivity
    False leaves out how the law carries the state's uncertainty (twelve evaluations of the
    law: a caller with many candidate laws takes it once, from one law)."""
    H = np.asarray(H, dtype=float)[:, None]
    M = inertias(law)
    unit = eps()
    if rounding is None and single_precision():
        rounding = SINGLE
    v0, v1 = np.abs(Z0[:, 3:]), np.abs(Z1[:, 3:])
    rate = STATE_ULPS * unit * (v0 + v1) / H
    Ze = evaluated_at(integrator, Z0, Z1)
    terms = force_terms(law, Ze) if Ze is not None else np.maximum(force_terms(law, Z0), force_terms(law, Z1))
    bound = M * rate + FORCE_ULPS * unit * terms
    at = Z1 if integrator == "implicit_euler" else Z0
    box = np.zeros_like(Z0)   # how far the state the step starts from (or ends at) may be off
    if integrator == "implicit_euler":
        bound += M * IMPLICIT_SOLVE_TOL / H
        box += np.hstack([H * IMPLICIT_SOLVE_TOL * np.ones((len(Z0), 3)), IMPLICIT_SOLVE_TOL * np.ones((len(Z0), 3))])
    if rounding is not None:
        bound += M * (rounding.half_unit(Z0[:, 3:]) + rounding.half_unit(Z1[:, 3:])) / H
        box += rounding.half_unit(at)
    if sensitivity and np.any(box):
        if integrator == "rk4":
            def step_rate(Z):
                return (rk4_step(law, Z, H[:, 0])[:, 3:] - Z[:, 3:]) / H
        else:
            def step_rate(Z):
                return accelerations(law, Z)
        # each component's secant (the law's slopes), plus the jump of a contact switching on
        # inside the box along the diagonal that presses a point in (which the secants halve)
        bound += M * (_sensitivity(step_rate, at, INPUT_ROUNDING_SAFETY * box) + _deepening(law, step_rate, at, box))
    return bound


def _deepening(law: Law, rate, Z: np.ndarray, box: np.ndarray) -> np.ndarray:
    """Per contact point, the whole change between the corner of the uncertainty box (n, 6) that
    presses that point in deepest and fastest and the one that lifts it (n, 3): a contact that
    switches on inside the box (a corner a few half units above the ground, at an angle also
    rounded; for RK4 at any stage) is a jump, and the true state and the written one may lie on
    either side of it: the whole jump, where a secant counts half."""
    rx, _ = law.geometry.arms(Z[:, 2])
    out = np.zeros((Z.shape[0], 3))
    for p in range(rx.shape[1]):
        # d = -(y + r_y): deeper with y down and theta turning the point down (d r_y / d theta = r_x)
        sign = np.column_stack([np.zeros(len(Z)), -np.ones(len(Z)), -np.sign(rx[:, p]),
                                np.zeros(len(Z)), -np.ones(len(Z)), -np.sign(rx[:, p])])
        step = sign * box
        out = np.maximum(out, np.abs(rate(Z + step) - rate(Z - step)))
    return out


def position_bound(integrator: str, Z0: np.ndarray, Z1: np.ndarray, H: np.ndarray, rounding=None) -> np.ndarray:
    """The round-off bound (n, 3) in m and rad on q1 - (q0 + h v): the update's roundings, the
    implicit solve's tolerance carried by h, and a file's rounding of q0, q1, v0 and v1."""
    H = np.asarray(H, dtype=float)[:, None]
    if rounding is None and single_precision():
        rounding = SINGLE
    q0, q1, v0, v1 = (np.abs(a) for a in (Z0[:, :3], Z1[:, :3], Z0[:, 3:], Z1[:, 3:]))
    bound = STATE_ULPS * eps() * (q0 + q1 + H * (v0 + v1))
    if integrator == "implicit_euler":
        bound = bound + H * IMPLICIT_SOLVE_TOL
    if rounding is not None:
        bound = bound + rounding.half_unit(Z0[:, :3]) + rounding.half_unit(Z1[:, :3]) + H * (
            rounding.half_unit(Z0[:, 3:]) + rounding.half_unit(Z1[:, 3:]))
    return bound
