"""The four time integrators, by name, each one compiled step of z = [q, v], q = (x, y, theta).

    explicit Euler        v1 = v0 + h a(q0, v0)       q1 = q0 + h v0
    semi-implicit Euler   v1 = v0 + h a(q0, v0)       q1 = q0 + h v1
    implicit Euler        v1 = v0 + h a(q1, v1)       q1 = q0 + h v1   (Newton, analytic Jacobian)
    RK4                   classical 4-stage Runge-Kutta on z' = (v, a(q, v))

counters: [force evaluations, Newton iterations, most Newton iterations in one step,
           steps whose Newton solve did not converge]
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from .chatter import chattering_point_at, clear_height, idle
from .filippov import jump_step
from .forces import acceleration_jacobian, accelerations, accelerations_at, no_point, rotation
from .implicit_residual import residual
from .linear3 import solve3

EXPLICIT_EULER, SEMI_IMPLICIT_EULER, IMPLICIT_EULER, RK4 = 0, 1, 2, 3

# Newton stops when the velocity update is below this (m/s or rad/s): far below the
# O(h |a'|) truncation error of implicit Euler at any step we run, and above the round-off
# of h k d / m for the stiffest scene (k = 1e7 N/m on 0.01 kg), so it is always reachable.
NEWTON_TOL = 1e-10
NEWTON_MAX_ITERATIONS = 50
# ...and only where max |G| is below this too (m/s, rad/s): a small step alone is also what a
# search stalled on a jump of G takes (|G| = 5.7e-5 rad/s was once called converged). Set to
# the step tolerance: dv = -M^-1 G with M = I - h (h da/dq + da/dv), and contact only adds
# stiffness and damping to M (|M^-1| <~ 1), so |G| <= NEWTON_TOL keeps v1 within about
# NEWTON_TOL of the root; the round-off of G, eps (|v| + h |force terms| / m), is below 1e-13
# on every scene, so a real root always passes.
RESIDUAL_TOL = 1e-10

FORCE_EVALS, NEWTON_ITERS, NEWTON_MAX, NEWTON_FAILS = 0, 1, 2, 3


@dataclass(frozen=True)
class Integrator:
    name: str
    code: int
    order: int        # global order of accuracy on smooth problems
    implicit: bool
    evals_per_step: int | None  # force evaluations per step; None: Newton decides


INTEGRATORS = {
    "explicit_euler": Integrator("explicit_euler", EXPLICIT_EULER, 1, False, 1),
    "semi_implicit_euler": Integrator("semi_implicit_euler", SEMI_IMPLICIT_EULER, 1, False, 1),
    "implicit_euler": Integrator("implicit_euler", IMPLICIT_EULER, 1, True, None),
    "rk4": Integrator("rk4", RK4, 4, False, 4),
}


@njit(cache=True, error_model="numpy", inline="always")
def euler_state(model, points, z, cs, sn, h, fx, fy, tau, semi):
    """One step of explicit Euler (semi False) or semi-implicit Euler (semi True) from the state
    tuple z, its contact points turned by (cs, sn) = rotation(model, z[2]); returns the new
    state. Both take the acceleration at the start of the step; they differ only in which update
    comes first, so one body serves both (one inlined copy of the force law instead of two).
    The updates are the seed's lines, which compare/tools/mutation edits."""
    x, y, theta, vx, vy, om = z
    ax, ay, aw = accelerations_at(model, points, z, cs, sn, fx, fy, tau)
    if semi:
        # seed Algorithm 1, lines 7-8: v <- v + (F/m) dt, then p <- p + v dt
        vx += h * ax
        vy += h * ay
        om += h * aw
        x += h * vx
        y += h * vy
        theta += h * om
    else:
        # p <- p + v dt with the old velocity, then v <- v + (F/m) dt
        x += h * vx
        y += h * vy
        theta += h * om
        vx += h * ax
        vy += h * ay
        om += h * aw
    return (x, y, theta, vx, vy, om)


@njit(cache=True)
def euler_step(model, points, z, h, fx, fy, tau, counters, semi):
    """euler_state() on the array z, in place; counts its force evaluation."""
    cs, sn = rotation(model, z[2])
    store(z, euler_state(model, points, as_state(z), cs, sn, h, fx, fy, tau, semi))
    counters[FORCE_EVALS] += 1


@njit(cache=True)
def as_state(z):
    """The array z (6,) as the tuple (x, y, theta, vx, vy, omega) the explicit steps take."""
    return (z[0], z[1], z[2], z[3], z[4], z[5])


@njit(cache=True)
def store(row, state):
    """row (6,) <- the state tuple."""
    row[0], row[1], row[2], row[3], row[4], row[5] = state


@njit(cache=True)
def implicit_euler_step(model, points, z, h, fx, fy, tau, counters, work):
    """Solve G(v1) = v1 - v0 - h a(q0 + h v1, v1) = 0 by damped Newton, started from the
    semi-implicit Euler predictor: dv = -(dG/dv1)^-1 G with dG/dv1 = I - h (h da/dq + da/dv),
    then v1 += t dv with t = 1, 1/2, 1/4, ... until max |G| falls (Armijo). Plain Newton
    (t = 1 always) cycles where G has kinks: the contact switch, max(0, -vc_y), the tanh of a
    sharp friction law and the ramp's corners. Converged: a step below NEWTON_TOL with max |G|
    below RESIDUAL_TOL.

    A bare sign law (friction or rolling) jumps by 2 h mu Fn / m at zero slip: where the step
    should stick, G has no root there either. Its Jacobian is 0 on both sides, the line search
    closes in on the jump, and the step ends near zero slip (a stick, the set-valued law's
    answer: 2e-7 m/s on a box at h = 1e-3 s) after NEWTON_MAX_ITERATIONS (some 500 force
    evaluations), counted as not converged.

    Where G jumps over zero (a damper that engages with force c |vc_y| at touchdown) no root
    exists, and the line search stalls on the jump (no t with t |dv| > NEWTON_TOL lowers |G|).
    The step is then the jump's own point, d_j(q1) = 0 with the convex hull of the two sides
    solving G (Filippov; filippov.jump_step, derived there), tried once at the first stall and,
    failing that, once more when the iterations run out; if neither lands, the Newton end point
    is kept and the step counted as unconverged. Iterations on the jump count as Newton
    iterations. Every step that converges without a stall is the plain damped Newton's, to the
    bit."""
    # views into the caller's scratch, all C-contiguous (whole rows): no allocation, and one
    # compiled variant of acceleration_jacobian and solve3
    z0 = work[0]
    zi = work[1]
    for j in range(6):
        z0[j] = z[j]
    jac = work[2:5]      # (3, 6)
    mat = work[11:14]    # (3, 6), the 3x3 Newton matrix in its first three columns
    rhs = work[14, :3]
    dv = work[15, :3]
    g = work[16, :3]
    v_start = work[17, :3]
    keep = work[10]      # the Newton state while the jump step is tried
    none = no_point()    # residual() with no point held: G(v1)
    ax, ay, aw = accelerations(model, points, z0, fx, fy, tau)
    counters[FORCE_EVALS] += 1
    zi[3], zi[4], zi[5] = z0[3] + h * ax, z0[4] + h * ay, z0[5] + h * aw
    res = residual(model, points, z0, zi, h, fx, fy, tau, none, 1.0, g, counters)
    converged = False
    tried_jump = False
    it = 0
    while it < NEWTON_MAX_ITERATIONS:
        it += 1
        acceleration_jacobian(model, points, zi, jac)
        for r in range(3):
            rhs[r] = -g[r]
            for j in range(3):
                mat[r, j] = (1.0 if r == j else 0.0) - h * (h * jac[r, j] + jac[r, 3 + j])
        if not solve3(mat, rhs, dv):
            break   # a singular Newton matrix gives no direction: the jump step below, else unconverged
        size = max(abs(dv[0]), abs(dv[1]), abs(dv[2]))
        for j in range(3):
            v_start[j] = zi[3 + j]
        t = 1.0
        while True:
            for j in range(3):
                zi[3 + j] = v_start[j] + t * dv[j]
            trial = residual(model, points, z0, zi, h, fx, fy, tau, none, 1.0, g, counters)
            if trial <= (1.0 - 1e-4 * t) * res:
                break
            if t * size <= NEWTON_TOL:
                if size > NEWTON_TOL and not tried_jump:
                    # stalled: no step along dv lowers |G|; try the jump's point
                    tried_jump = True
                    landed, extra = jump_attempt(model, points, z0, zi, h, fx, fy, tau, counters, work, keep)
                    it += extra
                    if landed:
                        converged = True
                    else:
                        trial = residual(model, points, z0, zi, h, fx, fy, tau, none, 1.0, g, counters)
                break
            t *= 0.5
        if converged:
            break
        res = trial
        if size <= NEWTON_TOL:
            if res <= RESIDUAL_TOL:
                converged = True
                break
            if not tried_jump:
                # a step too small to move but |G| still large: stopped on a jump, not a root
                tried_jump = True
                landed, extra = jump_attempt(model, points, z0, zi, h, fx, fy, tau, counters, work, keep)
                it += extra
                if landed:
                    converged = True
                    break
    if not converged and not tried_jump:
        landed, extra = jump_attempt(model, points, z0, zi, h, fx, fy, tau, counters, work, keep)
        it += extra
        converged = landed
    counters[NEWTON_ITERS] += it
    counters[NEWTON_MAX] = max(counters[NEWTON_MAX], it)
    if not converged:
        counters[NEWTON_FAILS] += 1
    for j in range(3):
        z[3 + j] = zi[3 + j]
        z[j] = z0[j] + h * zi[3 + j]


@njit(cache=True)
def jump_attempt(model, points, z0, zi, h, fx, fy, tau, counters, work, keep):
    """filippov.jump_step from zi; on failure zi is put back as it was. Returns (landed,
    iterations)."""
    for j in range(6):
        keep[j] = zi[j]
    landed, extra = jump_step(model, points, z0, zi, h, fx, fy, tau, counters, work,
                              NEWTON_TOL, RESIDUAL_TOL)
    if not landed:
        for j in range(6):
            zi[j] = keep[j]
    return landed, extra


@njit(cache=True, error_model="numpy")
def rk4_state(model, points, z, cs, sn, h, fx, fy, tau):
    """z1 = z0 + h/6 (k1 + 2 k2 + 2 k3 + k4), k_s = f(z_s), f(z) = (v, a(z)), with the stage
    states z_1 = z0, z_s = z0 + c_s h k_{s-1}, c = (1/2, 1/2, 1). z0: a tuple, its contact points
    turned by (cs, sn) = rotation(model, z0[2]); returns z1."""
    x0, y0, th0, vx0, vy0, om0 = z
    x, y, th, vx, vy, om = z                           # the stage state z_s
    k_x = k_y = k_th = k_vx = k_vy = k_om = 0.0        # k1 + 2 k2 + 2 k3 + k4, summed stage by stage
    for s in range(4):
        if s > 0:
            cs, sn = rotation(model, th)
        ax, ay, aw = accelerations_at(model, points, (x, y, th, vx, vy, om), cs, sn, fx, fy, tau)
        weight = 1.0 if s == 0 or s == 3 else 2.0
        k_x += weight * vx
        k_y += weight * vy
        k_th += weight * om
        k_vx += weight * ax
        k_vy += weight * ay
        k_om += weight * aw
        if s < 3:
            ch = (1.0 if s == 2 else 0.5) * h
            # next stage: positions from this stage's velocities, then velocities from its a
            x, y, th = x0 + ch * vx, y0 + ch * vy, th0 + ch * om
            vx, vy, om = vx0 + ch * ax, vy0 + ch * ay, om0 + ch * aw
    w = h / 6.0
    return (x0 + w * k_x, y0 + w * k_y, th0 + w * k_th, vx0 + w * k_vx, vy0 + w * k_vy, om0 + w * k_om)


@njit(cache=True)
def rk4_step(model, points, z, h, fx, fy, tau, counters, work):
    """rk4_state() on the array z, in place; counts its four force evaluations. work: unused
    (kept for one signature with implicit_euler_step)."""
    cs, sn = rotation(model, z[2])
    store(z, rk4_state(model, points, as_state(z), cs, sn, h, fx, fy, tau))
    counters[FORCE_EVALS] += 4


@njit(cache=True, error_model="numpy")
def is_healthy(z, guard):
    """False once the state z (an array or a tuple) has blown up: non-finite, beyond the position
    or speed limit, or with more energy than the scene could ever have. guard = (mass kg,
    inertia kg m^2, g m/s^2, lowest COM height m, energy limit J, position limit m, speed limit m/s).

    The limits are finite (blowup_guard's), so a NaN or infinite position or velocity fails its
    limit's comparison: only theta has no limit to fail. With no energy limit (inf: under applied
    input) the energy of a state within the limits is finite, and below it."""
    x, y, theta, vx, vy, om = z[0], z[1], z[2], z[3], z[4], z[5]
    mass, inertia, g, y_low, energy_limit, position_limit, speed_limit = guard
    if not (abs(x) <= position_limit and abs(y) <= position_limit and abs(vx) <= speed_limit
            and abs(vy) <= speed_limit and abs(om) <= speed_limit and np.isfinite(theta)):
        return False
    if energy_limit == np.inf:
        return True
    # kinetic + gravitational energy above the lowest pose: never above its start without input
    energy = 0.5 * mass * (vx * vx + vy * vy) + 0.5 * inertia * om * om + mass * g * (y - y_low)
    return energy <= energy_limit


@njit(cache=True)
def first_unhealthy(states, guard):
    """Index of the first row of states (T, 6) that is_healthy rejects, or -1 (for a
    trajectory computed elsewhere: the MuJoCo twin's)."""
    for i in range(states.shape[0]):
        if not is_healthy(states[i], guard):
            return i
    return -1


# The explicit loop takes its steps in blocks of this many (integrate_explicit): a block's own
# cost (its bounds' test, the watch's idle test) is spread over its steps, and a block that
# must be taken again step by step (a landing, the end of a diverging run) repeats at most
# this many steps: 64 keeps both below 1 % of a step of the cheapest scene (elastic_bounce).
BLOCK_STEPS = 64

# The bounds of no state, in the form widen keeps: (max of |x| and |y| m, min y m,
# max of |vx| and |vy| m/s, max |omega| rad/s).
NO_BOUNDS = (0.0, np.inf, 0.0, 0.0)


@njit(cache=True)
def widen(bounds, z):
    """bounds (NO_BOUNDS's form) grown to hold the state z (an array or a tuple)."""
    position, y_low, speed, spin = bounds
    return (max(position, max(abs(z[0]), abs(z[1]))), min(y_low, z[1]),
            max(speed, max(abs(z[3]), abs(z[4]))), max(spin, abs(z[5])))


@njit(cache=True, error_model="numpy")
def bounds_healthy(bounds, guard):
    """True when is_healthy passes every state within bounds (NO_BOUNDS's form), theta aside:
    it passes the worst of them, |x| = |y| = y = position, |vx| = |vy| = speed, |omega| = spin
    (y = the lowest for g < 0). Each limit holds at the bound, and the energy is_healthy
    computes, rounded operation by operation, never falls as a speed grows, nor as y does for
    g >= 0 (rounding is monotone). It can be twice a state's kinetic energy (vx and vy both at
    the larger): a block whose energy nears half the limit is taken again step by step."""
    position, y_low, speed, spin = bounds
    y = position if guard[0] * guard[2] >= 0.0 else y_low
    return is_healthy((position, y, 0.0, speed, speed, spin), guard)


def integrate(model, points, z, h, n, method, ext, out, counters, guard, watch) -> int:
    """Advance z by n steps of size h (s), writing the state after step i to out[i] when
    out has n rows (out with 0 rows records nothing). ext: (1, 3) constant or (n, 3) per
    step applied (Fx, Fy, tau). watch: the chatter tracker (contact points, WATCH_COLUMNS),
    carried from call to call (0 rows: chatter is not watched). Returns -1, or the 1-based
    step at which the state left the healthy range (see is_healthy) or a contact point
    started to chatter (chatter.py; that point's row of watch is flagged), with z left at
    that state.

    Two compiled loops, one per kind of method: implicit Euler's Newton solve is most of the
    compiled code, and apart the two compile at the same time on a first run (compile_cache)."""
    loop = integrate_implicit if method == IMPLICIT_EULER else integrate_explicit
    return loop(model, points, z, h, n, method, ext, out, counters, guard, watch)


@njit(cache=True)
def applied(ext, i):
    """(Fx N, Fy N, tau N m) applied during step i: ext's row i, or its one row if constant."""
    row = i if ext.shape[0] > 1 else 0
    return ext[row, 0], ext[row, 1], ext[row, 2]


@njit(cache=True, error_model="numpy")
def integrate_explicit(model, points, z, h, n, method, ext, out, counters, guard, watch):
    """integrate() for the methods that solve nothing: explicit and semi-implicit Euler, RK4.

    The steps go in blocks of BLOCK_STEPS. Where the chatter watch has nothing to do (no contact
    watched, or the body above chatter.clear_height with every point's row cleared, chatter.idle),
    a block first runs without the checks after each step, keeping the bounds of its states
    (widen). It stands if every step would have passed both checks: its bounds are healthy
    (bounds_healthy), so is its last state (for theta: a non-finite component stays non-finite,
    each update adds to it), and no state came below clear_height, so no point touched and the
    watch would have left every row as it was. Otherwise the block is taken again from its start
    with both checks after every step, and stops at the first bad one: the run stops at the same
    step, state and watch as if every step had been checked.

    The state is carried as a tuple of six numbers (kept in registers; the steps and the
    checks read it). The contact points' turn (cos, sin) is computed once per state, for the
    chatter check after a step and the forces of the next. Both loops are written out here: a
    function holding a loop, inlined, would count references to the arrays it is given (see
    forces.py), and they end by their condition, not by a `break` or `return` inside them. Even
    one step of them as an inlined function of its own took elastic_bounce's step from 4.3 to
    15 ns (`python -m compare bench elastic_bounce --against REV`)."""
    record = out.shape[0] == n
    watching = watch.shape[0] == points.shape[0] and model.contact
    clear = clear_height(points)     # m: no point touches at a COM height at or above this
    semi = method == SEMI_IMPLICIT_EULER
    per_step = ext.shape[0] > 1
    fx = fy = tau = 0.0
    if ext.shape[0] == 1:              # constant: the applied load is read once
        fx, fy, tau = applied(ext, 0)
    state = as_state(z)
    cs, sn = rotation(model, state[2])
    stopped = -1
    i = 0
    while i < n and stopped < 0:
        end = min(i + BLOCK_STEPS, n)
        start, start_cs, start_sn = state, cs, sn
        passed = False
        if not watching or (idle(watch) and state[1] >= clear):
            # unchecked, its states' bounds kept
            bounds = NO_BOUNDS
            j = i
            while j < end:
                if per_step:
                    fx, fy, tau = applied(ext, j)
                if method == RK4:
                    state = rk4_state(model, points, state, cs, sn, h, fx, fy, tau)
                else:
                    state = euler_state(model, points, state, cs, sn, h, fx, fy, tau, semi)
                cs, sn = rotation(model, state[2])
                if record:
                    store(out[j], state)
                bounds = widen(bounds, state)
                j += 1
            passed = (bounds_healthy(bounds, guard) and is_healthy(state, guard)
                      and (not watching or bounds[1] >= clear))
        if not passed:
            # from the block's start again, each step checked
            state, cs, sn = start, start_cs, start_sn
            j = i
            while j < end and stopped < 0:
                if per_step:
                    fx, fy, tau = applied(ext, j)
                if method == RK4:
                    state = rk4_state(model, points, state, cs, sn, h, fx, fy, tau)
                else:
                    state = euler_state(model, points, state, cs, sn, h, fx, fy, tau, semi)
                cs, sn = rotation(model, state[2])
                if record:
                    store(out[j], state)
                j += 1
                if not is_healthy(state, guard):
                    stopped = j
                elif watching and chattering_point_at(model, points, state, cs, sn, watch) >= 0:
                    stopped = j
        i = end
    store(z, state)
    counters[FORCE_EVALS] += (n if stopped < 0 else stopped) * (4 if method == RK4 else 1)
    return stopped


@njit(cache=True)
def integrate_implicit(model, points, z, h, n, method, ext, out, counters, guard, watch):
    """integrate() for implicit Euler (method is IMPLICIT_EULER; kept for one signature)."""
    work = np.zeros((18, 6))
    record = out.shape[0] == n
    watching = watch.shape[0] == points.shape[0] and model.contact
    stopped = -1
    i = 0
    while i < n and stopped < 0:
        fx, fy, tau = applied(ext, i)
        implicit_euler_step(model, points, z, h, fx, fy, tau, counters, work)
        cs, sn = rotation(model, z[2])
        if record:
            store(out[i], as_state(z))
        if not is_healthy(z, guard):
            stopped = i + 1
        elif watching and chattering_point_at(model, points, z, cs, sn, watch) >= 0:
            stopped = i + 1
        i += 1
    return stopped
