"""An outsider's box-only simulator, written as a class: the box's corners taken from its size
(not from the harness's contact points), the forces as methods, semi-implicit Euler. Any other
body raises NotImplementedError, the harness's sign for "my code does not do this scene"."""
import math

INTEGRATOR = "semi_implicit_euler"


class BoxWorld:
    """One box on the ground y = 0; `scene` is the dict `compare scene --json` prints."""

    def __init__(self, scene):
        body = scene["body"]
        if body["shape"] != "box":
            raise NotImplementedError(f"BoxWorld does boxes only, not a {body['shape']}")
        w, h = body["size"]
        self.corners = [(-w / 2, -h / 2), (w / 2, -h / 2), (w / 2, h / 2), (-w / 2, h / 2)]
        self.m = scene["mass_properties"]["mass"]
        self.inertia = self.m * (w * w + h * h) / 12.0
        self.law = scene["contact"]
        self.on = set(scene["effects"])
        self.g = scene["g"] if "gravity" in self.on else 0.0

    def normal(self, depth, vy):
        k, c = self.law["k"], self.law["c"]
        if self.law["damping_law"] == "compression":
            return k * depth + c * max(0.0, -vy)
        if self.law["damping_law"] == "linear":
            return max(0.0, k * depth - c * vy)
        raise NotImplementedError(f"BoxWorld has no {self.law['damping_law']} damping law")

    def tangential(self, fn, vx):
        if "friction" not in self.on:
            return 0.0
        if self.law["friction_law"] != "tanh":
            raise NotImplementedError(f"BoxWorld has no {self.law['friction_law']} friction law")
        return -self.law["mu"] * fn * math.tanh(self.law["alpha"] * vx)

    def wrench(self, x, y, th, vx, vy, om):
        fx, fy, tau = 0.0, -self.m * self.g, 0.0
        if "contact" not in self.on:
            return fx, fy, tau
        cos, sin = math.cos(th), math.sin(th)
        for cx, cy in self.corners:
            rx, ry = cos * cx - sin * cy, sin * cx + cos * cy
            depth = -(y + ry)
            if depth <= 0.0:
                continue
            fn = self.normal(depth, vy + om * rx)
            ft = self.tangential(fn, vx - om * ry)
            fx, fy, tau = fx + ft, fy + fn, tau + rx * fn - ry * ft
        return fx, fy, tau

    def advance(self, state, dt):
        x, y, th, vx, vy, om = state
        fx, fy, tau = self.wrench(x, y, th, vx, vy, om)
        vx, vy, om = vx + dt * fx / self.m, vy + dt * fy / self.m, om + dt * tau / self.inertia
        return [x + dt * vx, y + dt * vy, th + dt * om, vx, vy, om]


def step(state, scene, dt):
    return BoxWorld(scene).advance([float(v) for v in state], dt)
