"""One step of each of the four integrators from many states at once, with its round-off bound.

Written here, independently of custom_sim/integrators.py; a(q, v) is the force law of
compare/oracle/force_law.py, h the step (s), each row of Z (N, 6) its own state:

    explicit Euler        v1 = v0 + h a(q0, v0)        q1 = q0 + h v0
    semi-implicit Euler   v1 = v0 + h a(q0, v0)        q1 = q0 + h v1     (seed Algorithm 1, lines 7-8)
    implicit Euler        v1 = v0 + h a(q0 + h v1, v1)  q1 = q0 + h v1     (damped Newton on v1)
    RK4                   z1 = z0 + h/6 (k1 + 2 k2 + 2 k3 + k4), k_s = (v, a) at the stages

one_step(eq, Z, h, method) -> (Z1, bound, solved): the bound is STATE_ULPS ulps of the states
plus FORCE_ULPS ulps of h times the force law's scale, plus IMPLICIT_SOLVE_TOL for implicit
Euler, plus the file's rounding carried through the step (input_rounding_bound). Rows where a
bare sign leaves implicit Euler no unique step are `undecided` (NO_UNIQUE_STEP), never judged.
Derivations: docs/step-check.md#the-round-off-bound, docs/oracle-laws.md#one-step-of-each-integrator.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from compare.oracle.force_law import SEED_LAW, Law, accelerations, arms, bare_sign
from compare.oracle.reference import Equations

EPS = np.finfo(float).eps
# Two roundings per state update (h a, then z0 + h a) in each of the two codes.
STATE_ULPS = 4.0
# The force law's terms pass about a dozen roundings each (rotation, depth, damper, tanh, sum,
# product with 1/m); two codes may round every one of them differently.
FORCE_ULPS = 32.0
# The Newton tolerance a simulator's implicit Euler is held to (m/s, rad/s): custom_sim's
# NEWTON_TOL, 1e-10, which its Newton reaches on every built-in scene. A simulator solving
# its implicit equation less tightly than that fails the check (and is told so).
IMPLICIT_SOLVE_TOL = 1e-10
# The independent Newton solve here goes a thousand times below that, to round-off.
OWN_SOLVE_TOL = 1e-13
NEWTON_MAX_ITERATIONS = 60
# Near a root Newton at least halves |G| per iteration; SLOW_PATIENCE iterations in a row that do
# not are a row creeping towards a jump of G (no root there), not towards a root.
SLOW_PROGRESS = 0.5
SLOW_PATIENCE = 8

METHODS = ("explicit_euler", "semi_implicit_euler", "implicit_euler", "rk4")
# On input_rounding_bound's first-order sum: at 1 a correct file's residual reaches 0.98 to 1.00
# of its bound, at 2 at most 0.69 (docs/step-check.md#the-rounding-of-states-read-from-text).
INPUT_ROUNDING_SAFETY = 2.0


@dataclass(frozen=True)
class Rounding:
    """How a file's numbers were rounded when written, found from the file's own text:
    kind "decimals": a fixed number of digits after the point (C's %f, %.6f, %.9f): every
    value is within an absolute half unit 0.5e-digits of what was computed (a vx of 1e-8 is
    written 0.000000); kind "significant": digits significant figures (%.8g, %.10g, a
    shortest repr stopped short): within a relative half unit 0.5e(1-digits) of each value."""

    kind: str
    digits: int

    def __post_init__(self):
        if self.kind not in ("decimals", "significant"):
            raise ValueError(f"Rounding kind {self.kind!r}: expected 'decimals' or 'significant'")

    @property
    def atol(self) -> float:
        """The absolute half unit (decimals), 0 otherwise."""
        return 0.5 * 10.0 ** -self.digits if self.kind == "decimals" else 0.0

    @property
    def rtol(self) -> float:
        """The relative half unit (significant digits), 0 otherwise."""
        return 0.5 * 10.0 ** (1 - self.digits) if self.kind == "significant" else 0.0

    def half_unit(self, values) -> np.ndarray:
        """The largest rounding of each written value (same shape): atol + rtol |value|."""
        return self.atol + self.rtol * np.abs(np.asarray(values, dtype=float))

    def describe(self) -> str:
        if self.kind == "decimals":
            return f"{self.digits} decimals (%.{self.digits}f: {self.atol:.1g} absolute)"
        return f"{self.digits} significant digits (%.{self.digits}g: {self.rtol:.1g} relative)"


def _velocity_bound(v0, v1, h, scale):
    return STATE_ULPS * EPS * (np.abs(v0) + np.abs(v1)) + FORCE_ULPS * EPS * h * scale


def _position_bound(q0, q1, h, v):
    return STATE_ULPS * EPS * (np.abs(q0) + np.abs(q1) + h * np.abs(v))


def explicit_euler(eq: Equations, Z, h, law: Law = SEED_LAW):
    q0, v0 = Z[:, :3], Z[:, 3:]
    a, scale = accelerations(eq, Z, law)
    v1 = v0 + h * a
    q1 = q0 + h * v0
    bv = _velocity_bound(v0, v1, h, scale)
    return np.hstack([q1, v1]), np.hstack([_position_bound(q0, q1, h, v0), bv]), None


def semi_implicit_euler(eq: Equations, Z, h, law: Law = SEED_LAW):
    q0, v0 = Z[:, :3], Z[:, 3:]
    a, scale = accelerations(eq, Z, law)
    v1 = v0 + h * a
    q1 = q0 + h * v1
    bv = _velocity_bound(v0, v1, h, scale)
    return np.hstack([q1, v1]), np.hstack([_position_bound(q0, q1, h, v1) + h * bv, bv]), None


def rk4(eq: Equations, Z, h, law: Law = SEED_LAW):
    weights = (1.0, 2.0, 2.0, 1.0)
    nodes = (0.5, 0.5, 1.0)
    total = np.zeros_like(Z)
    stage = Z
    scale = np.zeros((Z.shape[0], 3))
    speed = np.zeros((Z.shape[0], 3))
    for s in range(4):
        a, sc = accelerations(eq, stage, law)
        k = np.hstack([stage[:, 3:], a])
        total += weights[s] * k
        scale = np.maximum(scale, sc)
        speed = np.maximum(speed, np.abs(stage[:, 3:]))
        if s < 3:
            stage = Z + nodes[s] * h * k
    Z1 = Z + h / 6.0 * total
    bv = _velocity_bound(Z[:, 3:], Z1[:, 3:], h, scale)
    bq = _position_bound(Z[:, :3], Z1[:, :3], h, speed) + h * bv
    return Z1, np.hstack([bq, bv]), None


def implicit_residual(eq: Equations, Z, V, h, law: Law = SEED_LAW, jumps: bool = True):
    """G(v1) = v1 - v0 - h a(q0 + h v1, v1) (N, 3) m/s, and the round-off scale of a there
    (jumps False: without a bare sign's undecided jump, force_law.accelerations)."""
    Zi = np.hstack([Z[:, :3] + h * V, V])
    a, scale = accelerations(eq, Zi, law, jumps=jumps)
    return V - Z[:, 3:] - h * a, scale


def implicit_euler(eq: Equations, Z, h, law: Law = SEED_LAW):
    """Damped Newton on G(v1) = 0 for every row at once, from the explicit predictor, with a
    forward-difference Jacobian (the kinks of the law make an analytic one no better). Returns
    (Z1, bound, solved): solved (N,) is False where no root was found, which happens where G
    jumps over zero (a damper engaging with c |vc_y| at touchdown, judged by jump_defect; a
    bare sign's jump at zero slip or spin, not judged: see undecided): there is no exact step.
    A root is |G| within G's own round-off, which leaves out a bare sign's jump (jumps=False):
    a Newton that ends on the jump, a slip within rounding of zero, is left |G| up to the jump's
    2 h mu Fn / m there, and that is no root whichever side rounding takes. The bound keeps the
    jump: two codes may take either side of it."""
    v0 = Z[:, 3:]
    a0, _ = accelerations(eq, Z, law)
    V = v0 + h * a0
    G, scale = implicit_residual(eq, Z, V, h, law, jumps=False)
    size = np.max(np.abs(G), axis=1)
    solved = np.zeros(Z.shape[0], dtype=bool)
    stuck = np.zeros(Z.shape[0], dtype=bool)   # no step lowers |G|: at a jump, or at round-off
    slow = np.zeros(Z.shape[0], dtype=int)     # iterations in a row that did not halve |G|
    eye = np.eye(3)
    for _ in range(NEWTON_MAX_ITERATIONS):
        floor = 4.0 * EPS * np.max(np.abs(V) + h * scale, axis=1)
        solved = size <= np.maximum(OWN_SOLVE_TOL, floor)
        todo = np.flatnonzero(~solved & ~stuck)
        if todo.size == 0:
            break
        Zt, Vt, Gt = Z[todo], V[todo], G[todo]
        jac = np.empty((todo.size, 3, 3))
        for j in range(3):
            step = 1e-7 * (1.0 + np.abs(Vt[:, j]))
            Vp = Vt.copy()
            Vp[:, j] += step
            Gp, _ = implicit_residual(eq, Zt, Vp, h, law, jumps=False)
            jac[:, :, j] = (Gp - Gt) / step[:, None]
        jac[~np.isfinite(jac)] = 0.0
        singular = np.abs(np.linalg.det(jac)) < 1e-300
        jac[singular] = eye
        dv = -np.linalg.solve(jac, Gt[:, :, None])[:, :, 0]
        # backtracking: halve the step until max |G| falls (Armijo), per row
        t = np.ones(todo.size)
        best_V, best_G, best_size, best_scale = Vt, Gt, size[todo], scale[todo]
        pending = np.ones(todo.size, dtype=bool)
        for _ in range(30):
            idx = np.flatnonzero(pending)
            Vtr = Vt[idx] + t[idx, None] * dv[idx]
            Gtr, str_ = implicit_residual(eq, Zt[idx], Vtr, h, law, jumps=False)
            s_tr = np.max(np.abs(Gtr), axis=1)
            ok = s_tr <= (1.0 - 1e-4 * t[idx]) * size[todo][idx]
            good = idx[ok]
            best_V[good], best_G[good], best_size[good], best_scale[good] = Vtr[ok], Gtr[ok], s_tr[ok], str_[ok]
            pending[good] = False
            t[idx[~ok]] *= 0.5
            if not pending.any():
                break
        slow[todo] = np.where(best_size > SLOW_PROGRESS * size[todo], slow[todo] + 1, 0)
        V[todo], G[todo], size[todo], scale[todo] = best_V, best_G, best_size, best_scale
        stuck[todo[pending]] = True
        stuck[todo[slow[todo] >= SLOW_PATIENCE]] = True
    floor = 4.0 * EPS * np.max(np.abs(V) + h * scale, axis=1)
    solved = size <= np.maximum(OWN_SOLVE_TOL, floor)
    _, scale = implicit_residual(eq, Z, V, h, law)   # with the jump, for the bound
    q1 = Z[:, :3] + h * V
    bv = _velocity_bound(v0, V, h, scale) + IMPLICIT_SOLVE_TOL
    bq = _position_bound(Z[:, :3], q1, h, V) + h * bv
    return np.hstack([q1, V]), np.hstack([bq, bv]), solved


NO_UNIQUE_STEP = ("implicit Euler under a bare sign law (friction or rolling 'sign'): the step's equation "
                  "jumps where a slip or omega crosses zero, and where it has no root (the solve ends on "
                  "the jump) the step means the set-valued law (the sign anywhere in [-1, 1]), which need "
                  "not have a unique solution and which the oracle's Newton does not solve, so it has no "
                  "step there to compare with: not judged")


def undecided(eq: Equations, solved, law: Law = SEED_LAW) -> np.ndarray | None:
    """(N,) bool: the implicit Euler rows that cannot be judged, those without a root under a
    law with a bare sign (NO_UNIQUE_STEP); None for the explicit methods (solved None). Rows
    without a root under the other laws are touchdown jumps, judged by jump_defect."""
    if solved is None:
        return None
    solved = np.asarray(solved, dtype=bool)
    return ~solved if bare_sign(eq, law) else np.zeros_like(solved)


STEPS = {"explicit_euler": explicit_euler, "semi_implicit_euler": semi_implicit_euler,
         "implicit_euler": implicit_euler, "rk4": rk4}


def input_rounding_bound(eq: Equations, Z, Z1, h: float, method: str, law: Law = SEED_LAW,
                         rtol: float = 0.0, atol: float = 0.0) -> np.ndarray:
    """How far the states' own rounding can move the residual |step(z0) - z1| (N, 6), for
    states written with a half unit of atol + rtol |z| per value (Rounding.half_unit): each
    component of z0 moved by its half unit both ways, the larger change of step(z0) kept, summed
    over the six components, times INPUT_ROUNDING_SAFETY, plus z1's own half unit. A secant, not
    a derivative, so a contact switch within the rounding is reached; y also moves by
    |r_x| u(theta) (the depth's rounding). Why: docs/step-check.md#the-rounding-of-states-read-from-text."""
    Z = np.ascontiguousarray(np.atleast_2d(Z), dtype=float)
    Z1 = np.atleast_2d(Z1)
    u0 = atol + rtol * np.abs(Z)
    if eq.contact and eq.turning:
        rx, _, _ = arms(eq, Z[:, 2], law)
        u0[:, 1] = u0[:, 1] + np.max(np.abs(rx), axis=1) * u0[:, 2]
    step = STEPS[method]
    spread = np.zeros_like(Z)
    for j in range(6):
        if not np.any(u0[:, j]):
            continue
        worst = np.zeros_like(Z)
        for sign in (1.0, -1.0):
            Zp = Z.copy()
            Zp[:, j] += sign * u0[:, j]
            moved = np.abs(step(eq, Zp, h, law)[0] - Z1)
            worst = np.maximum(worst, np.where(np.isfinite(moved), moved, np.inf))
        spread += worst
    return INPUT_ROUNDING_SAFETY * spread + atol + rtol * np.abs(Z1)


def one_step(eq: Equations, Z, h: float, method: str, law: Law = SEED_LAW, rtol=0.0, atol: float = 0.0,
             parts: bool = False):
    """(Z1, bound, solved) for states Z (N, 6): one step of `method` from each row, the
    round-off bound of each component (N, 6), and (implicit Euler) which rows have a root
    (None for the explicit methods).

    rtol, atol: the given states' own rounding beyond double precision, a half unit of
    atol + rtol |z| per value (a CSV at 10 significant digits: rtol 5e-10; at 6 decimals,
    %.6f: atol 5e-7); rtol may be a Rounding, which gives both. Its effect through the step
    (input_rounding_bound) is added to the bound. parts: return (Z1, bound, solved,
    input_part), input_part (N, 6) the share of the bound the rounding makes (zeros without)."""
    Z = np.ascontiguousarray(np.atleast_2d(Z), dtype=float)
    if isinstance(rtol, Rounding):
        rtol, atol = rtol.rtol, rtol.atol
    rtol, atol, h = float(rtol or 0.0), float(atol or 0.0), float(h)
    Z1, bound, solved = STEPS[method](eq, Z, h, law)
    extra = (input_rounding_bound(eq, Z, Z1, h, method, law, rtol, atol) if rtol or atol
             else np.zeros_like(Z1))
    bound = bound + extra
    return (Z1, bound, solved, extra) if parts else (Z1, bound, solved)


def jump_defect(eq: Equations, Z, Z1, h: float, law: Law = SEED_LAW):
    """How far a simulator's implicit Euler step Z -> Z1 is from solving the implicit equation
    where it has no root (rows of Z, Z1: (N, 6)).

    Where a point j touches down, G(v1) jumps by h times its contact force (c |vc_y| from the
    damper at d = 0) and may jump over zero: no v1 solves G = 0. A solver then ends at the jump,
    and the step it returns is exact in the sense of the jump's convex hull (Filippov):
    d_j(q1) = 0 and G_out + lam (G_in - G_out) = 0 for some lam in [0, 1], G_in and G_out
    being G at v1 with point j counted as touching and as not. Returns (defect (N, 6), point j
    (N,), depth d_j(q1) (N,) m): the velocity part of defect is that hull residual (m/s, rad/s),
    the position part |q1 - q0 - h v1| (m, rad)."""
    from compare.oracle.force_law import contact_state
    Z, Z1 = np.atleast_2d(Z), np.atleast_2d(Z1)
    V = Z1[:, 3:]
    Zi = np.hstack([Z[:, :3] + h * V, V])
    depth, _ = contact_state(eq, Z1)
    j = np.argmin(np.abs(depth), axis=1)
    rows = np.arange(Z.shape[0])
    base = depth > 0.0
    inside, outside = base.copy(), base.copy()
    inside[rows, j], outside[rows, j] = True, False
    a_in, _ = accelerations(eq, Zi, law, touching=inside)
    a_out, _ = accelerations(eq, Zi, law, touching=outside)
    g_out = V - Z[:, 3:] - h * a_out
    jump = h * (a_out - a_in)                      # G_in - G_out
    norm2 = np.sum(jump * jump, axis=1)
    lam = np.clip(-np.sum(g_out * jump, axis=1) / np.where(norm2 > 0, norm2, 1.0), 0.0, 1.0)
    hull = np.abs(g_out + lam[:, None] * jump)
    positions = np.abs(Z1[:, :3] - (Z[:, :3] + h * V))
    return np.hstack([positions, hull]), j, depth[rows, j]
