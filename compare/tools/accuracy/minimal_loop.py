"""The least a compiled step of the seed's law can cost: one numba loop, semi-implicit Euler, the
scene's points, nothing recorded, no guard, no other law. `bench` shows it beside custom_sim's
step, so custom_sim's cost over this floor is a number.

    v += h (F(q, v) / m);  q += h v            (F: gravity, and per touching point
                                               Fn = k d + c max(0, -v_n) or max(0, k d - c v_n),
                                               Ft = -mu Fn tanh(alpha v_t), rolling -mu_roll Fn tanh(S omega))
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from scene_types import Scene

from ...oracle.rigid_body import rigid_body


@njit(cache=True)
def _advance(z, n, h, points, turning, inv_m, inv_i, g, k, c, linear, mu, alpha, mu_roll, sharp):
    x, y, th, vx, vy, om = z[0], z[1], z[2], z[3], z[4], z[5]
    for _ in range(n):
        fx, fy, tau = 0.0, -g / inv_m, 0.0
        cs, sn = (math.cos(th), math.sin(th)) if turning else (1.0, 0.0)
        for i in range(points.shape[0]):
            rx = cs * points[i, 0] - sn * points[i, 1]
            ry = sn * points[i, 0] + cs * points[i, 1]
            d = -(y + ry)
            if d <= 0.0:
                continue
            vn = vy + om * rx
            fn = max(0.0, k * d - c * vn) if linear else k * d + c * max(0.0, -vn)
            ft = -mu * fn * math.tanh(alpha * (vx - om * ry)) if mu != 0.0 else 0.0
            fx += ft
            fy += fn
            tau += rx * fn - ry * ft
            if mu_roll != 0.0:
                tau -= mu_roll * fn * math.tanh(sharp * om)
        vx += h * fx * inv_m
        vy += h * fy * inv_m
        om += h * tau * inv_i
        x, y, th = x + h * vx, y + h * vy, th + h * om
    z[0], z[1], z[2], z[3], z[4], z[5] = x, y, th, vx, vy, om


def applies(scene: Scene) -> bool:
    """The floor is written for semi-implicit Euler under the seed's tanh laws."""
    ct = scene.contact
    return (scene.integrator == "semi_implicit_euler" and ct.friction_law == "tanh" and ct.roll_law == "tanh"
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
    i = scene.initial

    def run():
        z = np.array([*i.position, i.angle, *i.velocity, i.angular_velocity], dtype=float)
        _advance(z, *args)
        return z
    return run
