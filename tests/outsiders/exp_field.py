"""An outsider's simulator in a tutorial's numpy style: every contact point floats on a smooth
repulsive field A exp(-z / LENGTH) (1 - DAMP v_n) that reaches centimetres above the ground (no
contact point ever touches y = 0), Coulomb friction smoothed by a velocity scale, explicit Euler."""
from dataclasses import dataclass

import numpy as np

LENGTH = 0.004        # m: decay length of the field
STRENGTH = 2000.0     # times m g: the field's push at z = 0
DAMP = 1.0            # s/m
V_SMOOTH = 0.01       # m/s


@dataclass(frozen=True)
class Body:
    m: float
    inertia: float
    pts: np.ndarray
    turns: bool
    spins: bool


def _body(scene):
    mp = scene["mass_properties"]
    return Body(mp["mass"], mp["inertia"], np.asarray(mp["contact_points"], float).reshape(-1, 2),
                mp["points_rotate"], mp["rotates"])


def accel(z, scene):
    b, on = _body(scene), scene["effects"]
    g = scene["g"] if "gravity" in on else 0.0
    th = z[2] if b.turns else 0.0
    R = np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
    r = b.pts @ R.T
    f = np.zeros((len(r), 2))
    if "contact" in on:
        height = z[1] + r[:, 1]
        vn = z[4] + z[5] * r[:, 0]
        vt = z[3] - z[5] * r[:, 1]
        fn = STRENGTH * b.m * g * np.exp(-height / LENGTH) * np.maximum(0.0, 1.0 - DAMP * vn)
        mu = scene["contact"]["mu"] if "friction" in on else 0.0
        f[:, 0] = -mu * fn * vt / np.sqrt(vt * vt + V_SMOOTH ** 2)
        f[:, 1] = fn
    tau = np.sum(r[:, 0] * f[:, 1] - r[:, 1] * f[:, 0])
    return np.array([f[:, 0].sum() / b.m, f[:, 1].sum() / b.m - g, tau / b.inertia if b.spins else 0.0])


def step(state, scene, dt):
    z = np.asarray(state, dtype=float)
    return np.concatenate([z[:3] + dt * z[3:], z[3:] + dt * accel(z, scene)])


def simulate(scene):
    z = np.asarray(scene["state0"], dtype=float)
    out = [z]
    for _ in range(scene["steps"]):
        z = step(z, scene, scene["dt"])
        out.append(z)
    return np.array(out)
