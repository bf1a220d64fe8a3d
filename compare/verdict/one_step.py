"""One step of each of the four integrators from many states at once, with its round-off bound.

Written here, independently of custom_sim/integrators.py. z = [q, v], q = (x, y, theta),
v = (vx, vy, omega), a(q, v) the force law of compare/accuracy/force_law.py, step h (s):

    explicit Euler        v1 = v0 + h a(q0, v0)        q1 = q0 + h v0
    semi-implicit Euler   v1 = v0 + h a(q0, v0)        q1 = q0 + h v1     (seed Algorithm 1, lines 7-8)
    implicit Euler        v1 = v0 + h a(q0 + h v1, v1)  q1 = q0 + h v1     (Newton on v1)
    RK4                   z1 = z0 + h/6 (k1 + 2 k2 + 2 k3 + k4), k_s = (v, a) at the stages

Every row of Z starts from its own state, so the steps of a whole trajectory are one array
operation.

The round-off bound. Two codes evaluating the same step differ by the rounding of each. An update
z1 = z0 + h a rounds twice per code (the product, the sum): at most STATE_ULPS ulps of |z0| + |z1|
between the two. The acceleration itself is a sum of terms, each a chain of about a dozen
roundings: at most FORCE_ULPS ulps of the sum of the magnitudes of its terms (force_law's scale),
times h. Positions take h times the velocity's bound on top (semi-implicit Euler and RK4 use the
new velocities). Implicit Euler's v1 is the root of an equation a simulator solves only to its
own Newton tolerance: IMPLICIT_SOLVE_TOL on v1 and h IMPLICIT_SOLVE_TOL on q1 are added.
"""
from __future__ import annotations

import numpy as np

from compare.accuracy.force_law import SEED_LAW, Law, accelerations
from compare.accuracy.reference import Equations

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


def _velocity_bound(v0, v1, h, scale, rtol=0.0):
    return ((STATE_ULPS * EPS + 2.0 * rtol) * (np.abs(v0) + np.abs(v1))
            + (FORCE_ULPS * EPS + 2.0 * rtol) * h * scale)


def _position_bound(q0, q1, h, v, rtol=0.0):
    return (STATE_ULPS * EPS + 2.0 * rtol) * (np.abs(q0) + np.abs(q1) + h * np.abs(v))


def explicit_euler(eq: Equations, Z, h, law: Law = SEED_LAW, rtol: float = 0.0):
    q0, v0 = Z[:, :3], Z[:, 3:]
    a, scale = accelerations(eq, Z, law)
    v1 = v0 + h * a
    q1 = q0 + h * v0
    bv = _velocity_bound(v0, v1, h, scale, rtol)
    return np.hstack([q1, v1]), np.hstack([_position_bound(q0, q1, h, v0, rtol), bv]), None


def semi_implicit_euler(eq: Equations, Z, h, law: Law = SEED_LAW, rtol: float = 0.0):
    q0, v0 = Z[:, :3], Z[:, 3:]
    a, scale = accelerations(eq, Z, law)
    v1 = v0 + h * a
    q1 = q0 + h * v1
    bv = _velocity_bound(v0, v1, h, scale, rtol)
    return np.hstack([q1, v1]), np.hstack([_position_bound(q0, q1, h, v1, rtol) + h * bv, bv]), None


def rk4(eq: Equations, Z, h, law: Law = SEED_LAW, rtol: float = 0.0):
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
    bv = _velocity_bound(Z[:, 3:], Z1[:, 3:], h, scale, rtol)
    bq = _position_bound(Z[:, :3], Z1[:, :3], h, speed, rtol) + h * bv
    return Z1, np.hstack([bq, bv]), None


def implicit_residual(eq: Equations, Z, V, h, law: Law = SEED_LAW):
    """G(v1) = v1 - v0 - h a(q0 + h v1, v1) (N, 3) m/s, and the round-off scale of a there."""
    Zi = np.hstack([Z[:, :3] + h * V, V])
    a, scale = accelerations(eq, Zi, law)
    return V - Z[:, 3:] - h * a, scale


def implicit_euler(eq: Equations, Z, h, law: Law = SEED_LAW, rtol: float = 0.0):
    """Damped Newton on G(v1) = 0 for every row at once, from the explicit predictor, with a
    forward-difference Jacobian (the kinks of the law make an analytic one no better). Returns
    (Z1, bound, solved): solved (N,) is False where no root was found, which happens where G
    jumps over zero (a damper engaging with c |vc_y| at touchdown): there is no exact step."""
    v0 = Z[:, 3:]
    a0, _ = accelerations(eq, Z, law)
    V = v0 + h * a0
    G, scale = implicit_residual(eq, Z, V, h, law)
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
            Gp, _ = implicit_residual(eq, Zt, Vp, h, law)
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
            Gtr, str_ = implicit_residual(eq, Zt[idx], Vtr, h, law)
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
    q1 = Z[:, :3] + h * V
    bv = _velocity_bound(v0, V, h, scale, rtol) + IMPLICIT_SOLVE_TOL
    bq = _position_bound(Z[:, :3], q1, h, V, rtol) + h * bv
    return np.hstack([q1, V]), np.hstack([bq, bv]), solved


STEPS = {"explicit_euler": explicit_euler, "semi_implicit_euler": semi_implicit_euler,
         "implicit_euler": implicit_euler, "rk4": rk4}


def one_step(eq: Equations, Z, h: float, method: str, law: Law = SEED_LAW, rtol: float = 0.0):
    """(Z1, bound, solved) for states Z (N, 6): one step of `method` from each row, the
    round-off bound of each component (N, 6), and (implicit Euler) which rows have a root
    (None for the explicit methods). rtol: relative rounding of the given states beyond double
    precision (a CSV of 10 significant digits: 5e-10); it enters the bound as round-off does,
    on the states and, through the force terms' magnitudes, on the accelerations."""
    Z = np.ascontiguousarray(np.atleast_2d(Z), dtype=float)
    return STEPS[method](eq, Z, float(h), law, float(rtol))


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
    from compare.accuracy.force_law import contact_state
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
