"""A small simulator of the seed's Algorithms 1-4, in plain Python and numpy: the worked example.

    python -m compare run --sim examples/seed_sim.py:step

`step(state, scene, dt)` takes the state [x, y, theta, vx, vy, omega] of the centre of mass
and returns the state one step dt later. `scene` is the resolved scene (the dict
`python -m compare scene SCENE --json` prints). It reads the mass properties from it, the
contact points relative to the centre of mass and the force law, and steps with the scene's
integrator (explicit, semi-implicit Euler or RK4; implicit Euler is not written here).
"""
import math

import numpy as np


def accelerations(z, scene):
    """(ax, ay, angular acceleration) at z: gravity, then each contact point (Algorithm 2)."""
    x, y, theta, vx, vy, om = (float(v) for v in z)
    mp, ct, on = scene["mass_properties"], scene["contact"], scene["effects"]
    m, inertia = mp["mass"], mp["inertia"]
    fx, fy, tau = 0.0, 0.0, 0.0
    if "gravity" in on:
        fy -= m * scene["g"]                                  # F <- [0, -m g]
    if "contact" in on:
        c, s = (math.cos(theta), math.sin(theta)) if mp["points_rotate"] else (1.0, 0.0)
        for lx, ly in mp["contact_points"]:
            rx, ry = c * lx - s * ly, s * lx + c * ly         # r_i <- R(theta) c_i^local
            d = -(y + ry)                                     # depth below the ground y = 0
            if d <= 0.0:
                continue                                      # no force in the air
            vcx, vcy = vx - om * ry, vy + om * rx             # v_i <- v + omega [-r_y, r_x]
            if ct["damping_law"] == "compression":
                fn = ct["k"] * d + ct["c"] * max(0.0, -vcy)   # Algorithm 1, line 4
            else:
                fn = max(0.0, ct["k"] * d - ct["c"] * vcy)    # Kelvin-Voigt, never pulls
            ft = -ct["mu"] * fn * math.tanh(ct["alpha"] * vcx) if "friction" in on else 0.0
            fx += ft
            fy += fn
            tau += rx * fn - ry * ft                          # tau <- tau + r_i x F_i
            if "rolling_friction" in on:                      # Algorithm 4, line 9
                tau -= ct["mu_roll"] * fn * math.tanh(ct["roll_sharpness"] * om)
    alpha = tau / inertia if mp["rotates"] else 0.0
    return fx / m, fy / m, alpha


def derivative(z, scene):
    ax, ay, aw = accelerations(z, scene)
    return np.array([z[3], z[4], z[5], ax, ay, aw])


def step(state, scene, dt):
    """One step of the scene's integrator (the seed's Numerical Integration slide)."""
    method = scene["integrator"]
    if method == "semi_implicit_euler":                       # v <- v + a dt, then p <- p + v dt
        x, y, theta, vx, vy, om = state
        ax, ay, aw = accelerations(state, scene)
        vx, vy, om = vx + dt * ax, vy + dt * ay, om + dt * aw
        return np.array([x + dt * vx, y + dt * vy, theta + dt * om, vx, vy, om])
    z = np.asarray(state, dtype=float)
    if method == "explicit_euler":                            # p <- p + v dt with the old v
        return z + dt * derivative(z, scene)
    if method == "rk4":
        k1 = derivative(z, scene)
        k2 = derivative(z + 0.5 * dt * k1, scene)
        k3 = derivative(z + 0.5 * dt * k2, scene)
        k4 = derivative(z + dt * k3, scene)
        return z + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
    raise NotImplementedError(f"integrator {method!r} is not written in this example")
