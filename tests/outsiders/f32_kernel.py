"""An outsider's simulator shaped like a port of a GPU or embedded kernel: every number a
numpy float32, the contact points as one (n, 2) array handled without a Python loop, masks
instead of branches, semi-implicit Euler. It computes in single precision and hands float64
back (astype), so every number it returns is exactly a float32 value. The law is the scene's
linear spring-damper and tanh friction, with tau = r x F."""
import numpy as np

INTEGRATOR = "semi_implicit_euler"
F32 = np.float32


def step(state, scene, dt):
    s = np.asarray(state, dtype=F32)
    mp, ct = scene["mass_properties"], scene["contact"]
    m, inertia, h = F32(mp["mass"]), F32(mp["inertia"]), F32(dt)
    on = set(scene["effects"])
    pts = np.asarray(mp["contact_points"], dtype=F32)
    c, sn = np.cos(s[2]), np.sin(s[2])
    rx = c * pts[:, 0] - sn * pts[:, 1]
    ry = sn * pts[:, 0] + c * pts[:, 1]
    depth = -(s[1] + ry)
    touch = (depth > 0) & ("contact" in on)
    vn = s[4] + s[5] * rx
    vt = s[3] - s[5] * ry
    if ct["damping_law"] == "linear":
        fn = np.maximum(F32(0), F32(ct["k"]) * depth - F32(ct["c"]) * vn)
    else:
        fn = F32(ct["k"]) * depth + F32(ct["c"]) * np.maximum(F32(0), -vn)
    fn = np.where(touch, fn, F32(0))
    ft = np.zeros_like(fn)
    if "friction" in on:
        ft = np.where(touch, -F32(ct["mu"]) * fn * np.tanh(F32(ct["alpha"]) * vt), F32(0))
    g = F32(scene["g"]) if "gravity" in on else F32(0)
    fx, fy = ft.sum(dtype=F32), fn.sum(dtype=F32) - m * g
    tq = (rx * fn - ry * ft).sum(dtype=F32)
    v = s[3:] + h * np.array([fx / m, fy / m, tq / inertia if mp["rotates"] else F32(0)], dtype=F32)
    q = s[:3] + h * v
    return np.concatenate([q, v]).astype(np.float64)


def simulate(scene):
    z = np.array(scene["state0"], dtype=float)
    out = [z]
    for _ in range(scene["steps"]):
        z = step(z, scene, scene["dt"])
        out.append(z)
    return np.array(out)
