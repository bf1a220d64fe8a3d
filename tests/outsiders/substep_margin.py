"""An outsider's simulator in a game engine's style: fixed substeps that move positions first with
the force held from the start of the frame, a collision margin (contacts begin SKIN above each
point, in the world frame), a clamped spring-damper and tanh friction from the scene's table."""
import math

SKIN = 0.003          # m: contact margin, world frame (the "slop" of a collision pipeline)
SUBSTEPS = 8          # position-first substeps per frame: beta = (8 - 1) / 16 = 0.4375


def _frame_forces(s, scene):
    mp, ct, on = scene["mass_properties"], scene["contact"], scene["effects"]
    _, y, th, vx, vy, w = s
    F = [0.0, -mp["mass"] * scene["g"] if "gravity" in on else 0.0, 0.0]
    if "contact" not in on:
        return F
    cs, sn = (math.cos(th), math.sin(th)) if mp["points_rotate"] else (1.0, 0.0)
    for px, py in mp["contact_points"]:
        rx, ry = cs * px - sn * py, sn * px + cs * py
        pen = SKIN - (y + ry)
        if pen <= 0.0:
            continue
        vn, vt = vy + w * rx, vx - w * ry
        fn = max(0.0, ct["k"] * pen - ct["c"] * vn)
        ft = -ct["mu"] * fn * math.tanh(ct["alpha"] * vt) if "friction" in on else 0.0
        F[0] += ft
        F[1] += fn
        F[2] += rx * fn - ry * ft
    return F


def step(state, scene, dt):
    mp = scene["mass_properties"]
    F = _frame_forces([float(v) for v in state], scene)
    acc = (F[0] / mp["mass"], F[1] / mp["mass"], F[2] / mp["inertia"] if mp["rotates"] else 0.0)
    q, v = [float(a) for a in state[:3]], [float(a) for a in state[3:]]
    h = dt / SUBSTEPS
    for _ in range(SUBSTEPS):
        q = [qi + h * vi for qi, vi in zip(q, v)]
        v = [vi + h * ai for vi, ai in zip(v, acc)]
    return q + v


def simulate(scene):
    import numpy as np
    z = list(scene["state0"])
    rows = [z]
    for _ in range(scene["steps"]):
        z = step(z, scene, scene["dt"])
        rows.append(z)
    return np.array(rows)
