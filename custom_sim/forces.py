"""Forces from the ground, gravity and the applied input, and their analytic Jacobian.

State z = [x, y, theta, vx, vy, omega]; the ground is the line y = 0 with normal (0, 1).
For a contact point at r from the COM (world frame):

    c  = p + r                      position; depth d = -c_y, touching while d > 0
    vc = v + omega x r = (vx - omega r_y, vy + omega r_x)
    Fn = k d + c max(0, -vc_y)      damping_law "compression" (seed Algorithm 1)
    Fn = max(0, k d - c vc_y)       damping_law "linear" (Kelvin-Voigt, never pulls)
    Ft = -mu Fn tanh(alpha vc_x)    friction on the slip velocity of the contact point
    tau += r x F = r_x Fn - r_y Ft  and, rolling resistance, -mu_roll Fn sign(omega)

sign(omega) is regularised as tanh(ROLL_SHARPNESS omega), as the sliding law regularises its
sign: with a bare sign a disk that rolling resistance has stopped flips omega every step and
creeps (15 um/s measured), and implicit Euler finds no root.
"""
from __future__ import annotations

import math

from numba import njit

from .model import COMPRESSION

ROLL_SHARPNESS = 100.0  # s/rad: full rolling resistance above |omega| ~ 0.03 rad/s (v = 3 mm/s at R = 0.1 m)


@njit(cache=True, inline="always")
def rotation(model, theta):
    """(cos, sin) of the angle contact points turn by: theta, or 0 for points that stay below."""
    if model.points_rotate:
        return math.cos(theta), math.sin(theta)
    return 1.0, 0.0


@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
def normal_force(model, d, vcy):
    """Ground normal force (N) at depth d > 0 (m) and normal velocity vcy (m/s)."""
    if model.damping_law == COMPRESSION:
        return model.k * d + model.c * max(0.0, -vcy)
    return max(0.0, model.k * d - model.c * vcy)


@njit(cache=True, inline="always")
def accelerations(model, points, z, fx, fy, tau):
    """(ax, ay, alpha_theta) in m/s^2 and rad/s^2 at state z, with (fx N, fy N, tau N m) applied."""
    theta, vx, vy, om = z[2], z[3], z[4], z[5]
    if model.gravity:
        fy -= model.g / model.inv_mass
    if model.contact:
        cs, sn = rotation(model, theta)
        for i in range(points.shape[0]):
            lx, ly = points[i, 0], points[i, 1]
            rx, ry = cs * lx - sn * ly, sn * lx + cs * ly  # r = R(theta) l
            d = -(z[1] + ry)
            if d <= 0.0:
                continue  # free flight: no force, no damping in the air
            fn = normal_force(model, d, vy + om * rx)
            ft = 0.0
            if model.friction:
                ft = -model.mu * fn * tanh(model.alpha * (vx - om * ry))
            fx += ft
            fy += fn
            tau += rx * fn - ry * ft
            if model.rolling:
                tau -= model.mu_roll * fn * tanh(ROLL_SHARPNESS * om)
    return fx * model.inv_mass, fy * model.inv_mass, tau * model.inv_inertia


@njit(cache=True)
def acceleration_jacobian(model, points, z, jac, work):
    """d(ax, ay, alpha_theta)/dz into jac (3, 6), analytic; work is scratch of shape (6, 6).
    At the kinks of max() and of the contact switch it takes the active branch's derivative."""
    jac[:, :] = 0.0
    if not model.contact:
        return
    theta, vx, vy, om = z[2], z[3], z[4], z[5]
    rot = 1.0 if model.points_rotate else 0.0
    dd, dvx, dvy, dfn, dft, dtau = work[0], work[1], work[2], work[3], work[4], work[5]
    cs, sn = rotation(model, theta)
    for i in range(points.shape[0]):
        lx, ly = points[i, 0], points[i, 1]
        rx, ry = cs * lx - sn * ly, sn * lx + cs * ly
        d = -(z[1] + ry)
        if d <= 0.0:
            continue
        vcx, vcy = vx - om * ry, vy + om * rx
        # d/dz of d, vc_x, vc_y; dr/dtheta = (-r_y, r_x) for points that turn
        dd[:] = 0.0
        dd[1], dd[2] = -1.0, -rot * rx
        dvx[:] = 0.0
        dvx[2], dvx[3], dvx[5] = -rot * om * rx, 1.0, -ry
        dvy[:] = 0.0
        dvy[2], dvy[4], dvy[5] = -rot * om * ry, 1.0, rx
        fn = normal_force(model, d, vcy)
        if model.damping_law == COMPRESSION:
            dfn[:] = model.k * dd
            if vcy < 0.0:
                dfn[:] -= model.c * dvy
        elif model.k * d - model.c * vcy > 0.0:
            dfn[:] = model.k * dd - model.c * dvy
        else:
            dfn[:] = 0.0
        ft = 0.0
        dft[:] = 0.0
        if model.friction:
            th = tanh(model.alpha * vcx)
            ft = -model.mu * fn * th
            dft[:] = -model.mu * (dfn * th + fn * model.alpha * (1.0 - th * th) * dvx)
        jac[0, :] += dft * model.inv_mass
        jac[1, :] += dfn * model.inv_mass
        # tau = r_x Fn - r_y Ft:  dtau = dr_x Fn + r_x dFn - dr_y Ft - r_y dFt
        dtau[:] = rx * dfn - ry * dft
        dtau[2] += rot * (-ry * fn - rx * ft)
        if model.rolling:
            th_r = tanh(ROLL_SHARPNESS * om)
            dtau -= model.mu_roll * th_r * dfn
            dtau[5] -= model.mu_roll * fn * ROLL_SHARPNESS * (1.0 - th_r * th_r)
        jac[2, :] += dtau * model.inv_inertia
