"""An outsider's simulator, written in another style than examples/: object-oriented, the state as
a tuple, RK4 through a derivative method, the seed's law. It declares RK4 whatever the scene says,
so the checks must follow the integrator it declares (the contact check's integrator term too)."""
from dataclasses import dataclass
import math

INTEGRATOR = "rk4"


@dataclass
class Body:
    m: float
    inertia: float
    points: list
    rotate: bool


class World:
    def __init__(self, scene):
        mp = scene["mass_properties"]
        self.body = Body(mp["mass"], mp["inertia"], [tuple(p) for p in mp["contact_points"]], mp["points_rotate"])
        self.fx = scene["effects"]
        self.g = scene["g"]
        self.c = scene["contact"]

    def deriv(self, s):
        x, y, th, vx, vy, w = s
        b = self.body
        Fx, Fy, T = 0.0, (-b.m * self.g if "gravity" in self.fx else 0.0), 0.0
        if "contact" in self.fx:
            cs, sn = (math.cos(th), math.sin(th)) if b.rotate else (1.0, 0.0)
            for px, py in b.points:
                rx, ry = cs * px - sn * py, sn * px + cs * py
                depth = -(y + ry)
                if depth <= 0:
                    continue
                vpx, vpy = vx - w * ry, vy + w * rx
                if self.c["damping_law"] == "compression":
                    fn = self.c["k"] * depth + self.c["c"] * max(0.0, -vpy)
                else:
                    fn = max(0.0, self.c["k"] * depth - self.c["c"] * vpy)
                ft = -self.c["mu"] * fn * math.tanh(self.c["alpha"] * vpx) if "friction" in self.fx else 0.0
                Fx += ft; Fy += fn
                T += rx * fn - ry * ft
                if "rolling_friction" in self.fx:
                    T -= self.c["mu_roll"] * fn * math.tanh(self.c["roll_sharpness"] * w)
        return [vx, vy, w, Fx / b.m, Fy / b.m, (T / b.inertia if b.inertia > 0 else 0.0)]


def step(state, scene, dt):
    wd = World(scene)
    s = [float(v) for v in state]
    k1 = wd.deriv(s)
    k2 = wd.deriv([a + 0.5 * dt * b for a, b in zip(s, k1)])
    k3 = wd.deriv([a + 0.5 * dt * b for a, b in zip(s, k2)])
    k4 = wd.deriv([a + dt * b for a, b in zip(s, k3)])
    return tuple(a + dt / 6 * (p + 2 * q + 2 * r + t) for a, p, q, r, t in zip(s, k1, k2, k3, k4))


def simulate(scene):
    import numpy as np
    z = list(scene["state0"])
    rows = [z]
    for _ in range(scene["steps"]):
        z = list(step(z, scene, scene["dt"]))
        rows.append(z)
    return np.array(rows)
