"""A newcomer's box: the seed's step (examples/seed_sim.py) with a Hunt-Crossley normal force
k d (1 + dissipation max(0, -v_n))... written as k d (1 - dissipation v_n) clamped at zero, and
smooth Coulomb friction -mu Fn v / sqrt(v^2 + 1/alpha^2). FRICTION_TORQUE_SIGN = -1 is the bug
the newcomer made: the friction's torque -r_y Ft entered with the wrong sign (r x Fn is right).
Semi-implicit Euler. `step` is the buggy step, `step_fixed` the bug-free copy."""
import math

import numpy as np


def _accelerations(z, scene, friction_torque_sign):
    x, y, theta, vx, vy, om = (float(v) for v in z)
    mp, ct, on = scene["mass_properties"], scene["contact"], scene["effects"]
    m, inertia = mp["mass"], mp["inertia"]
    fx, fy, tau = 0.0, -m * scene["g"] if "gravity" in on else 0.0, 0.0
    if "contact" in on:
        c, s = math.cos(theta), math.sin(theta)
        for lx, ly in mp["contact_points"]:
            rx, ry = c * lx - s * ly, s * lx + c * ly
            d = -(y + ry)
            if d <= 0.0:
                continue
            vcx, vcy = vx - om * ry, vy + om * rx
            fn = max(0.0, ct["k"] * d * (1.0 - ct["dissipation"] * vcy))
            ft = 0.0
            if "friction" in on:
                ft = -ct["mu"] * fn * vcx / math.sqrt(vcx * vcx + 1.0 / ct["alpha"] ** 2)
            fx += ft
            fy += fn
            tau += rx * fn - friction_torque_sign * ry * ft
    return fx / m, fy / m, (tau / inertia if mp["rotates"] else 0.0)


def _step(state, scene, dt, sign):
    x, y, theta, vx, vy, om = state
    ax, ay, aw = _accelerations(state, scene, sign)
    vx, vy, om = vx + dt * ax, vy + dt * ay, om + dt * aw
    return np.array([x + dt * vx, y + dt * vy, theta + dt * om, vx, vy, om])


def step(state, scene, dt):
    """The newcomer's step: the friction torque's sign flipped."""
    return _step(state, scene, dt, -1.0)


def step_fixed(state, scene, dt):
    """The same step with the bug fixed."""
    return _step(state, scene, dt, 1.0)
