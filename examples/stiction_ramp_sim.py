"""A student's object-oriented simulator: Coulomb friction with a linear stiction ramp,
Ft = -mu Fn clamp(v / v_stick, -1, 1) with v_stick = 1 / alpha, instead of the seed's tanh.

    python -m compare identify examples/stiction_ramp_sim.py:step box_slide
    python -m compare run --sim examples/stiction_ramp_sim.py:step --law examples/laws/stiction_ramp.toml
    python -m compare run --sim examples/stiction_ramp_sim.py:step --law identified

Below v_stick the friction grows in proportion to the slip (a body "sticks" by creeping at
a speed that balances the load); above it, it is Coulomb's mu Fn. The normal force follows
the scene's damping law. Semi-implicit Euler only, whatever the scene asks, and it says so.
"""
import math

INTEGRATOR = "semi_implicit_euler"   # the integrator this code implements, for the harness


class Ground:
    """The penalty ground y = 0 under the scene's [contact] table."""

    def __init__(self, contact, effects):
        self.k, self.c, self.law = contact["k"], contact["c"], contact["damping_law"]
        self.mu, self.v_stick = contact["mu"], 1.0 / contact["alpha"]
        self.friction = "friction" in effects
        self.mu_roll, self.sharpness = contact["mu_roll"], contact["roll_sharpness"]
        self.rolling = "rolling_friction" in effects

    def normal(self, depth, normal_velocity):
        """N: the spring and its damper at a point pressed in by depth (m)."""
        if self.law == "compression":
            return self.k * depth + self.c * max(0.0, -normal_velocity)
        return max(0.0, self.k * depth - self.c * normal_velocity)

    def friction_force(self, fn, slip):
        """N: the ramp below v_stick, Coulomb's mu Fn beyond it."""
        if not self.friction:
            return 0.0
        return -self.mu * fn * max(-1.0, min(1.0, slip / self.v_stick))


class Body:
    """A rigid body in the plane: its mass, inertia and contact points from the scene."""

    def __init__(self, scene):
        mp = scene["mass_properties"]
        self.mass, self.inertia = mp["mass"], mp["inertia"]
        self.points = [tuple(p) for p in mp["contact_points"]]
        self.turns, self.rotates = mp["points_rotate"], mp["rotates"]
        self.weight = self.mass * scene["g"] if "gravity" in scene["effects"] else 0.0
        self.touches = "contact" in scene["effects"]

    def loads(self, ground, x, y, theta, vx, vy, omega):
        """Total force (N) and torque (N m) on the body."""
        fx, fy, tau = 0.0, -self.weight, 0.0
        if not self.touches:
            return fx, fy, tau
        c, s = (math.cos(theta), math.sin(theta)) if self.turns else (1.0, 0.0)
        for px, py in self.points:
            rx, ry = c * px - s * py, s * px + c * py
            depth = -(y + ry)
            if depth <= 0.0:
                continue
            fn = ground.normal(depth, vy + omega * rx)
            ft = ground.friction_force(fn, vx - omega * ry)
            fx, fy = fx + ft, fy + fn
            tau += rx * fn - ry * ft
            if ground.rolling:
                tau -= ground.mu_roll * fn * math.tanh(ground.sharpness * omega)
        return fx, fy, tau


def step(state, scene, dt):
    """Semi-implicit Euler: velocities first, then positions with the new velocities."""
    body, ground = Body(scene), Ground(scene["contact"], scene["effects"])
    x, y, theta, vx, vy, omega = state
    fx, fy, tau = body.loads(ground, x, y, theta, vx, vy, omega)
    vx += dt * fx / body.mass
    vy += dt * fy / body.mass
    omega += dt * tau / body.inertia if body.rotates else 0.0
    return [x + dt * vx, y + dt * vy, theta + dt * omega, vx, vy, omega]
