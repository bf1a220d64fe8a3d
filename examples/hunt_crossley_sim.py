"""A simulator with a Hunt-Crossley contact: the normal force k d (1 - h v_n) of Drake's
compliant contact, with its own dissipation h = 2 s/m, instead of the seed's spring-damper.

    python -m compare identify examples/hunt_crossley_sim.py:step box_drop
    python -m compare run --sim examples/hunt_crossley_sim.py:step --law examples/laws/hunt_crossley.toml
    python -m compare run --sim examples/hunt_crossley_sim.py:step --law identified

It is written the way many vectorised codes are: every contact point at once as numpy
arrays, the generalised force assembled with the points' Jacobians. Friction (tanh) and
rolling resistance follow the scene. Integrators: semi-implicit Euler and RK4.
"""
import numpy as np

DISSIPATION = 2.0   # s/m: Hunt-Crossley's h; no damping force at touchdown (d = 0)


def generalised_force(q, v, scene):
    """(Fx, Fy, tau) in N and N m at positions q = (x, y, theta), velocities v."""
    mp, ct, on = scene["mass_properties"], scene["contact"], set(scene["effects"])
    force = np.array([0.0, -mp["mass"] * scene["g"] if "gravity" in on else 0.0, 0.0])
    if "contact" not in on:
        return force
    local = np.asarray(mp["contact_points"], dtype=float)
    angle = q[2] if mp["points_rotate"] else 0.0
    turn = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    arms = local @ turn.T                                   # (n, 2) world-frame arms
    depth = -(q[1] + arms[:, 1])
    touching = depth > 0.0
    if not touching.any():
        return force
    arms, depth = arms[touching], depth[touching]
    slip = v[0] - v[2] * arms[:, 1]
    normal_velocity = v[1] + v[2] * arms[:, 0]
    fn = np.maximum(0.0, ct["k"] * depth * (1.0 - DISSIPATION * normal_velocity))
    ft = -ct["mu"] * fn * np.tanh(ct["alpha"] * slip) if "friction" in on else np.zeros_like(fn)
    force[0] += ft.sum()
    force[1] += fn.sum()
    force[2] += (arms[:, 0] * fn - arms[:, 1] * ft).sum()
    if "rolling_friction" in on:
        force[2] -= ct["mu_roll"] * fn.sum() * np.tanh(ct["roll_sharpness"] * v[2])
    return force


def acceleration(q, v, scene):
    mp = scene["mass_properties"]
    f = generalised_force(q, v, scene)
    inverse_mass = np.array([1.0 / mp["mass"], 1.0 / mp["mass"],
                             1.0 / mp["inertia"] if mp["rotates"] else 0.0])
    return f * inverse_mass


def step(state, scene, dt):
    """One step of the scene's integrator: state [x, y, theta, vx, vy, omega] -> the next."""
    q, v = np.asarray(state[:3], dtype=float), np.asarray(state[3:], dtype=float)
    if scene["integrator"] == "semi_implicit_euler":
        v = v + dt * acceleration(q, v, scene)
        return np.concatenate([q + dt * v, v])
    if scene["integrator"] == "rk4":
        def f(z):
            return np.concatenate([z[3:], acceleration(z[:3], z[3:], scene)])
        z = np.concatenate([q, v])
        k1 = f(z)
        k2 = f(z + dt / 2 * k1)
        k3 = f(z + dt / 2 * k2)
        k4 = f(z + dt * k3)
        return z + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    raise NotImplementedError(f"integrator {scene['integrator']!r} is not written in this example")
