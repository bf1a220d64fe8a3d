"""Implicit Euler's step where its equation has no root: on the jump of a touchdown (Filippov).

Where a touching-down point's damper makes G(v1) = v1 - v0 - h a(q0 + h v1, v1) jump over zero,
the step is taken on the jump: the point on the ground, d_j(q0 + h v1) = 0 (m), and
v1 - v0 - h (a_out + lam f_j) = 0 with 0 <= lam <= 1 (a_out the acceleration without point j,
f_j its own; forces.held_share). jump_step solves these four equations for v1 (m/s, rad/s) and
lam by Newton, with two 3x3 solves per iteration. The step is accepted when it converges with
the point on the ground and lam in [0, 1]; otherwise the caller keeps its own.
Derivation: docs/implicit-euler.md#the-jump-steps-newton-iteration.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from .forces import loaded_acceleration_jacobian, point_load, rotation
from .implicit_residual import residual
from .linear3 import solve3

JUMP_MAX_ITERATIONS = 20


@njit(cache=True, inline="always")
def nearest_point(model, points, z):
    """The contact point closest to the ground at z (|d| smallest): the one on the jump."""
    cs, sn = rotation(model, z[2])
    best, best_d = 0, 1e300
    for i in range(points.shape[0]):
        d = abs(z[1] + sn * points[i, 0] + cs * points[i, 1])
        if d < best_d:
            best, best_d = i, d
    return best


@njit(cache=True)
def jump_step(model, points, z0, zi, h, fx, fy, tau, counters, work, step_tol, residual_tol):
    """From zi (velocities near the jump, positions q0 + h v1), Newton on the two conditions of
    docs/implicit-euler.md for the point nearest the ground. Returns (accepted, iterations); on
    acceptance zi holds (q1, v1) on the jump, otherwise zi is garbage (the caller restores it).
    Scratch: work rows 2-4 (Jacobian), 5-7 and 11-13 (the Newton matrix twice), 8-9, 14-16."""
    jac = work[2:5]
    mat = work[11:14]
    mat2 = work[5:8]
    rhs_p, p = work[8, :3], work[8, 3:]
    rhs_w, w = work[9, :3], work[9, 3:]
    g = work[16, :3]
    held = np.int64(nearest_point(model, points, zi))  # int64, never a literal type (forces.no_point)
    rot = 1.0 if model.points_rotate else 0.0
    lam = 0.5
    res = residual(model, points, z0, zi, h, fx, fy, tau, held, lam, g, counters)
    it = 0
    settled = False
    while it < JUMP_MAX_ITERATIONS:
        it += 1
        cs, sn = rotation(model, zi[2])
        lx, ly = points[held, 0], points[held, 1]
        rx, ry = cs * lx - sn * ly, sn * lx + cs * ly
        depth = -(zi[1] + ry)
        # f_j: the held point's whole load as accelerations, at its depth (0 on the jump)
        ft, fn, roll = point_load(model, rx, ry, depth, zi[3], zi[4], zi[5])
        rhs_w[0] = h * ft * model.inv_mass
        rhs_w[1] = h * fn * model.inv_mass
        rhs_w[2] = h * (rx * fn - ry * ft - roll) * model.inv_inertia
        loaded_acceleration_jacobian(model, points, zi, jac, held, lam)
        for r in range(3):
            rhs_p[r] = -g[r]
            for j in range(3):
                mat[r, j] = (1.0 if r == j else 0.0) - h * (h * jac[r, j] + jac[r, 3 + j])
                mat2[r, j] = mat[r, j]
        if not solve3(mat, rhs_p, p) or not solve3(mat2, rhs_w, w):
            return False, it   # singular: lam has run far off (1e12 seen), no jump point this way
        # h grad_q d_j . x  for x = p, w: grad_q d_j = (0, -1, -rot r_x)
        gp = -h * (p[1] + rot * rx * p[2])
        gw = -h * (w[1] + rot * rx * w[2])
        if gw == 0.0:
            return False, it
        dlam = -(depth + gp) / gw
        size = 0.0
        for j in range(3):
            dv = p[j] + dlam * w[j]
            zi[3 + j] += dv
            size = max(size, abs(dv))
        lam += dlam
        res = residual(model, points, z0, zi, h, fx, fy, tau, held, lam, g, counters)
        if size <= step_tol:
            settled = True
            break
    if not settled or res > residual_tol or lam < 0.0 or lam > 1.0:
        return False, it
    cs, sn = rotation(model, zi[2])
    depth = -(zi[1] + sn * points[held, 0] + cs * points[held, 1])
    return abs(depth) <= h * step_tol, it
