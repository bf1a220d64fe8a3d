"""The ball: a size-5 football as the project's rolling circle (seed Algorithm 4) on grass.

The scene is built in code with `custom_sim.parse_scene`, so the game reads the same schema
as every scenario file. Ground contact: spring-damper with damping on compression only,
sliding friction (tanh) and rolling resistance. Units SI; y up; the ground is y = 0.
"""
from __future__ import annotations

import math

from custom_sim import Scene, parse_scene

MASS = 0.43        # kg, FIFA size 5: 410-450 g
RADIUS = 0.11      # m, circumference 68-70 cm
DT = 5e-4          # s, the game's fixed physics step (2000 steps per second)

# Ground: wn = sqrt(k / m) = 216 rad/s, so semi-implicit Euler needs h wn < 2: h wn = 0.11.
GROUND_K = 2e4     # N/m: a 0.43 kg ball rests 0.2 mm deep
# zeta = c / (2 sqrt(k m)) = 0.3: with damping on compression only the restitution is
# e = exp(-zeta / sqrt(1 - zeta^2) * atan(sqrt(1 - zeta^2) / zeta)) = 0.67, a ball on grass.
GROUND_ZETA = 0.3
GROUND_C = 2.0 * GROUND_ZETA * math.sqrt(GROUND_K * MASS)   # N s/m
MU = 0.5           # sliding friction, ball on grass
# tanh sharpness: the friction rate at rest 3 mu g alpha = 1.5e3 1/s (m_t = m / 3 for a disk)
# keeps h * rate = 0.74 < 2 (custom_sim/stability.py).
ALPHA = 100.0      # s/m
# Rolling resistance: a rolling disk slows at 2 mu_roll g / (3 R) = 0.89 m/s^2, a pass on grass.
MU_ROLL = 0.015    # m


def ball_scene(dt: float = DT, position=(0.0, RADIUS), velocity=(0.0, 0.0),
               angular_velocity: float = 0.0) -> Scene:
    """The ball's scene: circle, gravity, contact, friction, rolling friction, semi-implicit
    Euler at `dt` (s). Duration is nominal: the game advances a Stepper round by round."""
    return parse_scene({
        "name": "football",
        "description": "A size-5 football on grass, pushed by the player (W A S D)",
        "duration": 60.0,
        "dt": dt,
        "integrator": "semi_implicit_euler",
        "effects": ["gravity", "contact", "friction", "rolling_friction"],
        "body": {"shape": "circle", "mass": MASS, "radius": RADIUS},
        "contact": {"k": GROUND_K, "c": GROUND_C, "damping_law": "compression",
                    "mu": MU, "alpha": ALPHA, "mu_roll": MU_ROLL},
        "initial": {"position": list(position), "velocity": list(velocity),
                    "angular_velocity": angular_velocity},
    }, file="compare/tools/game/ball.py", default_name="football")


def resting_height(scene: Scene) -> float:
    """Centre height (m) of the ball at rest on the ground: R - m g / k."""
    return scene.body.radius - scene.body.mass * scene.g / scene.contact.k
