"""The least a compiled step of the seed's law can cost: one numba loop, semi-implicit Euler or
RK4, the scene's points, nothing recorded, no guard, no other law. `bench` shows it beside
custom_sim's step, so custom_sim's cost over this floor is a number.

    v += h (F(q, v) / m);  q += h v            (F: gravity, and per touching point
                                               Fn = k d + c max(0, -v_n) or max(0, k d - c v_n),
                                               Ft = -mu Fn tanh(alpha v_t), rolling -mu_roll Fn tanh(S omega))
    RK4: the classical four stages on z' = (v, F(q, v) / m)

tanh is custom_sim's (forces.tanh: the library's to round-off, without the library call for
small and large arguments): with math.tanh the floor paid an expm1 per touching point at rest
that custom_sim does not, and stood above custom_sim on box_slide and point_drop.

Where the scene's body spends most steps in the air (elastic_bounce: 98 % of its steps) the
floor's step is a few additions; that is its real cost, not a loop the compiler emptied (the
run ends where custom_sim's does, tests/test_bench.py).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from custom_sim.forces import tanh
from scene_types import Scene

from ...oracle.rigid_body import rigid_body


@njit(cache=True, inline="always")
def _forces(y, th, vx, vy, om, points, turning, g_weight, k, c, linear, mu, alpha, mu_roll, sharp):
    """(Fx N, Fy N, tau N m) on the body: its weight and every touching point's load."""
    fx, fy, tau = 0.0, -g_weight, 0.0
    cs, sn = (math.cos(th), math.sin(th)) if turning else (1.0, 0.0)
    for i in range(points.shape[0]):
        rx = cs * points[i, 0] - sn * points[i, 1]
        ry = sn * points[i, 0] + cs * points[i, 1]
        d = -(y + ry)
        if d <= 0.0:
            continue
        vn = vy + om * rx
        fn = max(0.0, k * d - c * vn) if linear else k * d + c * max(0.0, -vn)
        ft = -mu * fn * tanh(alpha * (vx - om * ry)) if mu != 0.0 else 0.0
        fx += ft
        fy += fn
        tau += rx * fn - ry * ft
        if mu_roll != 0.0:
            tau -= mu_roll * fn * tanh(sharp * om)
    return fx, fy, tau


@njit(cache=True)
def _advance(z, n, h, points, turning, inv_m, inv_i, g, k, c, linear, mu, alpha, mu_roll, sharp):
    """n steps of semi-implicit Euler from z, in place."""
    x, y, th, vx, vy, om = z[0], z[1], z[2], z[3], z[4], z[5]
    g_weight = g / inv_m
    for _ in range(n):
        fx, fy, tau = _forces(y, th, vx, vy, om, points, turning, g_weight, k, c, linear, mu, alpha,
                              mu_roll, sharp)
        vx += h * fx * inv_m
        vy += h * fy * inv_m
        om += h * tau * inv_i
        x, y, th = x + h * vx, y + h * vy, th + h * om
    z[0], z[1], z[2], z[3], z[4], z[5] = x, y, th, vx, vy, om


@njit(cache=True)
def _advance_rk4(z, n, h, points, turning, inv_m, inv_i, g, k, c, linear, mu, alpha, mu_roll, sharp):
    """n steps of classical RK4 from z, in place: z1 = z0 + h/6 (k1 + 2 k2 + 2 k3 + k4)."""
    x, y, th, vx, vy, om = z[0], z[1], z[2], z[3], z[4], z[5]
    g_weight = g / inv_m
    half, sixth = 0.5 * h, h / 6.0
    for _ in range(n):
        f1x, f1y, t1 = _forces(y, th, vx, vy, om, points, turning, g_weight, k, c, linear, mu, alpha,
                               mu_roll, sharp)
        a1x, a1y, a1w = f1x * inv_m, f1y * inv_m, t1 * inv_i
        y2, th2 = y + half * vy, th + half * om           # x: no force depends on it
        vx2, vy2, om2 = vx + half * a1x, vy + half * a1y, om + half * a1w
        f2x, f2y, t2 = _forces(y2, th2, vx2, vy2, om2, points, turning, g_weight, k, c, linear, mu,
                               alpha, mu_roll, sharp)
        a2x, a2y, a2w = f2x * inv_m, f2y * inv_m, t2 * inv_i
        y3, th3 = y + half * vy2, th + half * om2
        vx3, vy3, om3 = vx + half * a2x, vy + half * a2y, om + half * a2w
        f3x, f3y, t3 = _forces(y3, th3, vx3, vy3, om3, points, turning, g_weight, k, c, linear, mu,
                               alpha, mu_roll, sharp)
        a3x, a3y, a3w = f3x * inv_m, f3y * inv_m, t3 * inv_i
        y4, th4 = y + h * vy3, th + h * om3
        vx4, vy4, om4 = vx + h * a3x, vy + h * a3y, om + h * a3w
        f4x, f4y, t4 = _forces(y4, th4, vx4, vy4, om4, points, turning, g_weight, k, c, linear, mu,
                               alpha, mu_roll, sharp)
        a4x, a4y, a4w = f4x * inv_m, f4y * inv_m, t4 * inv_i
        x += sixth * (vx + 2.0 * vx2 + 2.0 * vx3 + vx4)
        y += sixth * (vy + 2.0 * vy2 + 2.0 * vy3 + vy4)
        th += sixth * (om + 2.0 * om2 + 2.0 * om3 + om4)
        vx += sixth * (a1x + 2.0 * a2x + 2.0 * a3x + a4x)
        vy += sixth * (a1y + 2.0 * a2y + 2.0 * a3y + a4y)
        om += sixth * (a1w + 2.0 * a2w + 2.0 * a3w + a4w)
    z[0], z[1], z[2], z[3], z[4], z[5] = x, y, th, vx, vy, om


LOOPS = {"semi_implicit_euler": _advance, "rk4": _advance_rk4}


def applies(scene: Scene) -> bool:
    """The floor is written for semi-implicit Euler and RK4 under the seed's tanh laws."""
    ct = scene.contact
    return (scene.integrator in LOOPS and ct.friction_law == "tanh" and ct.roll_law == "tanh"
            and ct.damping_law in ("compression", "linear"))


def runner(scene: Scene, steps: int | None = None):
    """A callable taking the scene's steps (or `steps`) from its initial state; returns the state."""
    rb = rigid_body(scene.body)
    ct = scene.contact
    on = scene.has
    points = np.asarray(rb.points, dtype=float).reshape(-1, 2) if on("contact") else np.zeros((0, 2))
    args = (scene.steps if steps is None else steps, scene.dt, points, rb.turning, 1.0 / rb.mass,
            1.0 / rb.inertia if rb.rotates else 0.0, scene.g if on("gravity") else 0.0, ct.k, ct.c,
            ct.damping_law == "linear", ct.mu if on("friction") else 0.0, ct.alpha,
            ct.mu_roll if on("rolling_friction") else 0.0, ct.roll_sharpness or 0.0)
    loop = LOOPS[scene.integrator]
    i = scene.initial

    def run():
        z = np.array([*i.position, i.angle, *i.velocity, i.angular_velocity], dtype=float)
        loop(z, *args)
        return z
    return run
