"""A plain-Python seed-style box simulator (Algorithm 2, semi-implicit Euler), written for the
tests with switches that put one known mistake in at a time. It shares no code with the
harness: the step check must catch its mistakes on its own."""
from __future__ import annotations

import math

import numpy as np


def box_step(z, scene, dt, *, friction_at_com=False, torque_sign=1.0, damping_in_air=False,
             inertia_factor=1.0, position_with_old_velocity=False):
    """One step of a box scene (linear or compression law, tanh friction) from z = [x, y,
    theta, vx, vy, omega]."""
    x, y, th, vx, vy, om = (float(v) for v in z)
    w, h = scene.body.size
    m = scene.body.mass
    inertia = inertia_factor * m * (w * w + h * h) / 12.0
    ct = scene.contact
    fx, fy, tau = 0.0, -m * scene.g, 0.0
    cs, sn = math.cos(th), math.sin(th)
    for lx, ly in ((-w / 2, -h / 2), (w / 2, -h / 2), (w / 2, h / 2), (-w / 2, h / 2)):
        rx, ry = cs * lx - sn * ly, sn * lx + cs * ly
        d = -(y + ry)
        vix, viy = vx - om * ry, vy + om * rx
        if d > 0.0:
            if ct.damping_law == "compression":
                fn = ct.k * d + ct.c * max(0.0, -viy)
            else:
                fn = max(0.0, ct.k * d - ct.c * viy)
        elif damping_in_air:
            fn = ct.c * max(0.0, -viy)
        else:
            continue
        slip = vx if friction_at_com else vix
        ft = -ct.mu * fn * math.tanh(ct.alpha * slip)
        fx += ft
        fy += fn
        tau += torque_sign * (rx * fn - ry * ft)
    nvx, nvy, nom = vx + dt * fx / m, vy + dt * fy / m, om + dt * tau / inertia
    if position_with_old_velocity:
        return np.array([x + dt * vx, y + dt * vy, th + dt * om, nvx, nvy, nom])
    return np.array([x + dt * nvx, y + dt * nvy, th + dt * nom, nvx, nvy, nom])


def run(scene, z0, steps, **mistake):
    out = np.empty((steps + 1, 6))
    out[0] = z0
    for i in range(steps):
        out[i + 1] = box_step(out[i], scene, scene.dt, **mistake)
    return out
