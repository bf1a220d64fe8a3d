"""Forces from the ground, gravity and the applied input, and their analytic Jacobian.

State z = [x, y, theta, vx, vy, omega]; the ground is the line y = 0 with normal (0, 1).
For a contact point at r from the COM (world frame), in the seed's law:

    c  = p + r                      position; depth d = -c_y, touching while d > 0
    vc = v + omega x r = (vx - omega r_y, vy + omega r_x)
    Fn = k d + c max(0, -vc_y)      damping_law "compression" (seed Algorithm 1)
    Ft = -mu Fn tanh(alpha vc_x)    friction on the slip velocity of the contact point
    tau += r x F = r_x Fn - r_y Ft  and, rolling resistance, -mu_roll Fn tanh(S omega)

and the scene's other families (scene_types.laws; docs/contact-laws.md):

    Fn = max(0, k d - c vc_y)                   "linear" (Kelvin-Voigt, never pulls)
    Fn = k d - c vc_y                           "unclamped" (pulls while separating fast)
    Fn = max(0, k d (1 - dissipation vc_y))     "hunt_crossley" (no damping at d = 0)
    Ft = -mu Fn clamp(alpha vc_x, -1, 1)        friction "ramp"
    Ft = -mu Fn vc_x / sqrt(vc_x^2 + 1/alpha^2) friction "smooth_coulomb"
    Ft = -mu Fn sign(vc_x)                      friction "sign" (bare Coulomb)
    tau_roll = -mu_roll Fn sign(omega)          roll_law "sign"

Fn enters friction and rolling resistance as it is, negative too (the unclamped law's pull).
S is the scene's roll_sharpness (s/rad): the tanh regularises the rolling law's sign as alpha
does the sliding one's (with a bare sign a disk that rolling resistance has stopped flips omega
every step, and implicit Euler finds no root). Each law is chosen by an integer code of the
model (model.py), one predictable branch per point: the seed's law is always the first.

Compiling: the functions of scalars (rotation, tanh, normal_force, the laws' signs) are plain
compiled functions, which LLVM inlines into their callers: numba compiles each once, instead of
once per call site as with inline="always" (a quarter of the first run's compile). point_load
is inlined by numba (inline="always"): with every law's branch it outgrew LLVM's inlining
threshold. Arrays cost where they are passed: numba counts a reference to each array argument
(an atomic increment and decrement, some 5 ns the pair) unless its pruner proves the pair
useless, which it does only where the array's use has one way out: no `return` or `break`
inside a loop (the explicit loop and chatter.py stop by a loop condition instead), and no call
that stays a call in between. accelerations_at is inlined (inline="always") into the explicit
step, whose loop counts no reference at all (it counted 16 a step, a third of box_drop's
step, when its parts broke out of loops); the implicit step still counts some 66 a step, its
Newton loop exiting from inside. The laws that divide compile with error_model="numpy":
Python's check of a zero divisor adds a raise to the loop.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from .model import COMPRESSION, LINEAR, RAMP, ROLL_TANH, SMOOTH_COULOMB, TANH, UNCLAMPED


@njit(cache=True, inline="always")
def no_point():
    """-1, the `held` of no contact point, typed int64: a compiled function called with a
    constant is compiled again for that constant (numba's literal types), and those copies
    were a tenth of the first run's compile."""
    return np.int64(-1)


@njit(cache=True)
def rotation(model, theta):
    """(cos, sin) of the angle contact points turn by: theta, or 0 for points that stay below."""
    if model.points_rotate:
        return math.cos(theta), math.sin(theta)
    return 1.0, 0.0


@njit(cache=True)
def tanh(x):
    """math.tanh(x), without the library call for small and large x: below |x| = 2^-10 by its
    series x - x^3/3 + 2 x^5/15, whose first omitted term 17 x^7/315 is below 2^-63 |x|, a
    tenth of an ulp, so the result is the library's to round-off; above |x| = 22 exactly +-1,
    as the library returns. At rest and while rolling the slip velocities put almost every
    friction call in the first range, a spinning disk's rolling resistance in the second, and
    the library call was a third of the step."""
    if abs(x) < 0.0009765625:
        x2 = x * x
        return x - x * x2 * (1.0 / 3.0 - x2 * (2.0 / 15.0))
    if abs(x) > 22.0:  # 1 - |tanh x| < 2 e^-44, far below half an ulp of 1: exactly +-1
        return math.copysign(1.0, x)
    return math.tanh(x)


@njit(cache=True)
def sign(x):
    """-1, 0 or 1 as x is negative, zero or positive (sign(0) = 0: no force at exact rest)."""
    if x > 0.0:
        return 1.0
    if x < 0.0:
        return -1.0
    return 0.0


@njit(cache=True)
def normal_force(model, d, vcy):
    """Ground normal force (N) at depth d > 0 (m) and normal velocity vcy (m/s), by damping_law."""
    law = model.damping_law
    if law == COMPRESSION:
        return model.k * d + model.c * max(0.0, -vcy)
    if law == LINEAR:
        return max(0.0, model.k * d - model.c * vcy)
    if law == UNCLAMPED:
        return model.k * d - model.c * vcy
    return max(0.0, model.k * d * (1.0 - model.dissipation * vcy))   # HUNT_CROSSLEY


@njit(cache=True, error_model="numpy")
def slip_sign(model, v):
    """The friction law's smoothed sign s(v) of the slip v (m/s), in [-1, 1]: Ft = -mu Fn s(v)."""
    law = model.friction_law
    if law == TANH:
        return tanh(model.alpha * v)
    if law == RAMP:
        return min(1.0, max(-1.0, model.alpha * v))
    if law == SMOOTH_COULOMB:   # v / sqrt(v^2 + 1/alpha^2), as x / sqrt(1 + x^2) with x = alpha v
        x = model.alpha * v
        return x / math.sqrt(1.0 + x * x)
    return sign(v)              # SIGN


@njit(cache=True, error_model="numpy")
def slip_sign_slope(model, v):
    """ds/dv (s/m) of slip_sign, the friction law's stiffness per unit mu Fn: alpha at v = 0
    for the three regularised laws. The ramp takes its saturated side's 0 at |alpha v| = 1
    exactly; the sign law is flat on both sides of its jump (0), which no derivative spans."""
    law = model.friction_law
    x = model.alpha * v
    if law == TANH:
        th = tanh(x)
        return model.alpha * (1.0 - th * th)
    if law == RAMP:
        return model.alpha if abs(x) < 1.0 else 0.0
    if law == SMOOTH_COULOMB:
        q = 1.0 / (1.0 + x * x)
        return model.alpha * q * math.sqrt(q)
    return 0.0                  # SIGN


@njit(cache=True)
def roll_sign(model, om):
    """The rolling law's smoothed sign of omega (rad/s): tau_roll = -mu_roll Fn roll_sign."""
    if model.roll_law == ROLL_TANH:
        return tanh(model.roll_sharpness * om)
    return sign(om)             # ROLL_SIGN


@njit(cache=True, inline="always")
def point_load(model, rx, ry, d, vx, vy, om):
    """(Ft N, Fn N, rolling torque N m) of one contact point at arm (rx, ry) and depth d (m),
    counted as touching whatever the sign of d (the caller decides: d > 0, or the touchdown
    point held on the ground by the jump step, filippov.py)."""
    fn = normal_force(model, d, vy + om * rx)
    ft = 0.0
    if model.friction:
        ft = -model.mu * fn * slip_sign(model, vx - om * ry)
    roll = 0.0
    if model.rolling:
        roll = model.mu_roll * fn * roll_sign(model, om)
    return ft, fn, roll


@njit(cache=True)
def normal_force_slopes(model, d, vcy):
    """(dFn/dd N/m, dFn/dvc_y N s/m) of normal_force, on the active branch of its max(): at a
    kink (the compression damper's vc_y = 0, a clamp at Fn = 0) the branch the strict test picks."""
    law = model.damping_law
    if law == COMPRESSION:
        return model.k, (-model.c if vcy < 0.0 else 0.0)
    if law == LINEAR:
        if model.k * d - model.c * vcy > 0.0:
            return model.k, -model.c
        return 0.0, 0.0
    if law == UNCLAMPED:
        return model.k, -model.c
    lever = 1.0 - model.dissipation * vcy   # HUNT_CROSSLEY: Fn = k d lever while positive
    if model.k * d * lever > 0.0:
        return model.k * lever, -model.k * d * model.dissipation
    return 0.0, 0.0


@njit(cache=True, inline="always")
def accelerations(model, points, z, fx, fy, tau):
    """(ax, ay, alpha_theta) in m/s^2 and rad/s^2 at state z, with (fx N, fy N, tau N m) applied."""
    cs, sn = rotation(model, z[2])
    return accelerations_at(model, points, z, cs, sn, fx, fy, tau)


@njit(cache=True, error_model="numpy", inline="always")
def accelerations_at(model, points, z, cs, sn, fx, fy, tau):
    """accelerations() with the contact points' turn (cs, sn) = rotation(model, z[2]) given: the
    explicit loop computes it once per state, for this and for the chatter check. z: the state
    as an array or a tuple."""
    vx, vy, om = z[3], z[4], z[5]
    if model.gravity:
        fy -= model.g / model.inv_mass
    if model.contact:
        # the rolling law's sign depends on omega alone: taken once here, and only where the
        # scene has rolling resistance (left in the loop, the compiler computed it before the
        # loop at every evaluation, touching or not, rolling or not)
        turn = roll_sign(model, om) if model.rolling else 0.0
        for i in range(points.shape[0]):
            lx, ly = points[i, 0], points[i, 1]
            rx, ry = cs * lx - sn * ly, sn * lx + cs * ly  # r = R(theta) l
            d = -(z[1] + ry)
            if d <= 0.0:
                continue  # free flight: no force, no damping in the air
            ft, fn, _ = point_load(model, rx, ry, d, vx, vy, om)
            roll = model.mu_roll * fn * turn if model.rolling else 0.0   # point_load's rolling torque
            fx += ft
            fy += fn
            tau += rx * fn - ry * ft
            if model.rolling:
                tau -= roll
    return fx * model.inv_mass, fy * model.inv_mass, tau * model.inv_inertia


@njit(cache=True, inline="always")
def held_share(model, points, z, held, share, fx, fy, tau):
    """The applied load (fx N, fy N, tau N m) plus (share - touching) L, L the load of contact
    point `held` at state z whatever its depth, touching = 1 where it is below the ground: with
    it, accelerations() counts share L of that point's load whether it touches or not (the
    jump step's lambda, filippov.py). Its loop adds L where the point touches."""
    cs, sn = rotation(model, z[2])
    lx, ly = points[held, 0], points[held, 1]
    rx, ry = cs * lx - sn * ly, sn * lx + cs * ly
    d = -(z[1] + ry)
    extra = share - (1.0 if d > 0.0 else 0.0)
    ft, fn, roll = point_load(model, rx, ry, d, z[3], z[4], z[5])
    tau += extra * (rx * fn - ry * ft)
    if model.rolling:
        tau -= extra * roll
    return fx + extra * ft, fy + extra * fn, tau


@njit(cache=True)
def add_gradient(row, scale, c_d, c_x, c_y, rx, ry, om, rot):
    """row (6,) += scale (c_d grad d + c_x grad vc_x + c_y grad vc_y), the gradients over
    z = (x, y, theta, vx, vy, omega) of a contact point's depth d = -(y + r_y) and slip
    vc = (vx - omega r_y, vy + omega r_x); r turns with theta (dr/dtheta = (-r_y, r_x)) when
    rot = 1, so
        grad d    = (0, -1, -rot r_x,       0, 0,  0)
        grad vc_x = (0,  0, -rot omega r_x, 1, 0, -r_y)
        grad vc_y = (0,  0, -rot omega r_y, 0, 1,  r_x)
    Written out component by component: no array is built. row: one row of the Jacobian."""
    row[1] -= scale * c_d
    row[2] -= scale * rot * (c_d * rx + om * (c_x * rx + c_y * ry))
    row[3] += scale * c_x
    row[4] += scale * c_y
    row[5] += scale * (c_y * rx - c_x * ry)


@njit(cache=True, inline="always")
def acceleration_jacobian(model, points, z, jac):
    """d(ax, ay, alpha_theta)/dz into jac (3, 6), analytic and allocation-free. At the kinks of
    max() and of the contact switch it takes the active branch's derivative.

    Per touching point every force is a function of (d, vc_x, vc_y), so each gradient is a
    combination of the three gradients of add_gradient:
        dFn  = fn_d grad d + fn_v grad vc_y              (normal_force_slopes)
        dFt  = -mu s dFn - mu Fn s' grad vc_x,   s = slip_sign(vc_x), s' = slip_sign_slope
        dtau = r_x dFn - r_y dFt + rot (-r_y Fn - r_x Ft) e_theta   (tau = r_x Fn - r_y Ft)
               - mu_roll th_r dFn - mu_roll Fn S (1 - th_r^2) e_omega,  th_r = tanh(S omega)
    The sign laws' jumps have no derivative: each side's (0) is taken, and implicit Euler's
    Newton solve stalls at the jump (docs/contact-laws.md says what it lands on).
    """
    loaded_acceleration_jacobian(model, points, z, jac, no_point(), 1.0)


@njit(cache=True)
def loaded_acceleration_jacobian(model, points, z, jac, held, share_held):
    """acceleration_jacobian() of the accelerations with held_share() applied: point `held`
    (-1: none) acts whatever its depth, its terms scaled by share_held. Every term of the held
    point carries the factor share once (share = 1 multiplies exactly: with held = -1 this is
    the plain Jacobian to the bit). One compiled body for both: a copy specialised to held = -1
    was two seconds of a first run's compile, for a few compares per Newton iteration."""
    for r in range(3):
        for j in range(6):
            jac[r, j] = 0.0
    if not model.contact:
        return
    theta, vx, vy, om = z[2], z[3], z[4], z[5]
    rot = 1.0 if model.points_rotate else 0.0
    cs, sn = rotation(model, theta)
    for i in range(points.shape[0]):
        lx, ly = points[i, 0], points[i, 1]
        rx, ry = cs * lx - sn * ly, sn * lx + cs * ly
        d = -(z[1] + ry)
        if i != held and d <= 0.0:
            continue
        share = share_held if i == held else 1.0
        vcx, vcy = vx - om * ry, vy + om * rx
        fn = normal_force(model, d, vcy)
        fn_d, fn_v = normal_force_slopes(model, d, vcy)
        # dFt = ft_n dFn + ft_x grad vc_x
        ft, ft_n, ft_x = 0.0, 0.0, 0.0
        if model.friction:
            if model.friction_law == TANH:   # the seed's, written out: s' = alpha (1 - th^2)
                th = tanh(model.alpha * vcx)
                ft = -model.mu * fn * th
                ft_n = -model.mu * th
                ft_x = -model.mu * fn * model.alpha * (1.0 - th * th)
            else:
                s = slip_sign(model, vcx)
                ft = -model.mu * fn * s
                ft_n = -model.mu * s
                ft_x = -model.mu * fn * slip_sign_slope(model, vcx)
        # Fn and Ft on (grad d, grad vc_x, grad vc_y)
        n_d, n_x, n_y = fn_d, 0.0, fn_v
        t_d, t_x, t_y = ft_n * fn_d, ft_x, ft_n * fn_v
        add_gradient(jac[0], share * model.inv_mass, t_d, t_x, t_y, rx, ry, om, rot)
        add_gradient(jac[1], share * model.inv_mass, n_d, n_x, n_y, rx, ry, om, rot)
        # tau: r_x Fn - r_y Ft (- mu_roll th_r Fn), and the lever arms' own turn with theta
        lever_n = rx
        if model.rolling:
            th_r = roll_sign(model, om)
            lever_n -= model.mu_roll * th_r
            if model.roll_law == ROLL_TANH:   # the sign law is flat on both sides of omega = 0
                jac[2, 5] -= (model.mu_roll * fn * model.roll_sharpness * (1.0 - th_r * th_r)
                              * model.inv_inertia * share)
        add_gradient(jac[2], share * model.inv_inertia, lever_n * n_d - ry * t_d, lever_n * n_x - ry * t_x,
                     lever_n * n_y - ry * t_y, rx, ry, om, rot)
        jac[2, 2] += rot * (-ry * fn - rx * ft) * model.inv_inertia * share
