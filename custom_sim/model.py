"""The numeric model the compiled loop reads: a scene flattened to numbers, law codes and effect switches.

An effect the scene does not list is switched off, and its parameters are set to NaN: if
its term were ever evaluated, the NaN would reach the state and stop the run, so a finite
trajectory is a proof that the term was never evaluated. A parameter the chosen law does not
take is NaN the same way (c under hunt_crossley, dissipation under the others, alpha under the
sign friction, roll_sharpness under the sign rolling law).
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .bodies import MassProperties, mass_properties
from .compile_cache import fresh_cache
from scene_types.schema import Scene

# Law codes (scene_types.laws names the families; forces.py writes their formulas). Code 0 is
# the seed's law of each effect.
COMPRESSION, LINEAR, UNCLAMPED, HUNT_CROSSLEY = 0, 1, 2, 3     # damping_law
TANH, RAMP, SMOOTH_COULOMB, SIGN = 0, 1, 2, 3                   # friction_law
ROLL_TANH, ROLL_SIGN = 0, 1                                     # roll_law
DAMPING_CODES = {"compression": COMPRESSION, "linear": LINEAR, "unclamped": UNCLAMPED,
                 "hunt_crossley": HUNT_CROSSLEY}
FRICTION_CODES = {"tanh": TANH, "ramp": RAMP, "smooth_coulomb": SMOOTH_COULOMB, "sign": SIGN}
ROLL_CODES = {"tanh": ROLL_TANH, "sign": ROLL_SIGN}


class Model(NamedTuple):
    inv_mass: float        # 1/kg
    inv_inertia: float     # 1/(kg m^2); 0 for the point mass (never turns)
    g: float               # m/s^2, NaN without gravity
    k: float               # N/m
    c: float               # N s/m, NaN under hunt_crossley
    dissipation: float     # s/m, NaN unless hunt_crossley
    mu: float              # -, NaN without friction
    alpha: float           # s/m, NaN without friction or under the sign law
    mu_roll: float         # m, NaN without rolling friction
    roll_sharpness: float  # s/rad, NaN without rolling friction or under the sign law
    damping_law: int       # COMPRESSION, LINEAR, UNCLAMPED or HUNT_CROSSLEY
    friction_law: int      # TANH, RAMP, SMOOTH_COULOMB or SIGN
    roll_law: int          # ROLL_TANH or ROLL_SIGN
    gravity: bool
    contact: bool
    friction: bool
    rolling: bool
    points_rotate: bool    # contact points turn with the body


def _taken(value, on: bool) -> float:
    """value where its effect is on and its law takes it (not None), else NaN."""
    return float(value) if on and value is not None else float("nan")


def build_model(scene: Scene, props: MassProperties | None = None) -> tuple[Model, np.ndarray]:
    """The compiled loop's model and the contact points (n, 2) relative to the COM (m). Every
    compiled run starts from one, so numba's cache is checked against the sources here."""
    fresh_cache()
    props = props or mass_properties(scene.body)
    ct = scene.contact
    on = scene.has
    damping = DAMPING_CODES[ct.damping_law]
    model = Model(
        inv_mass=1.0 / props.mass,
        inv_inertia=1.0 / props.inertia if props.rotates else 0.0,
        g=_taken(scene.g, on("gravity")),
        k=_taken(ct.k, on("contact")),
        c=_taken(ct.c, on("contact") and damping != HUNT_CROSSLEY),
        dissipation=_taken(ct.dissipation, on("contact") and damping == HUNT_CROSSLEY),
        mu=_taken(ct.mu, on("friction")),
        alpha=_taken(ct.alpha, on("friction")),
        mu_roll=_taken(ct.mu_roll, on("rolling_friction")),
        roll_sharpness=_taken(ct.roll_sharpness, on("rolling_friction")),
        damping_law=damping,
        friction_law=FRICTION_CODES[ct.friction_law],
        roll_law=ROLL_CODES[ct.roll_law],
        gravity=on("gravity"),
        contact=on("contact"),
        friction=on("friction"),
        rolling=on("rolling_friction"),
        points_rotate=props.points_rotate,
    )
    return model, np.ascontiguousarray(props.points, dtype=np.float64)


def initial_state(scene: Scene) -> np.ndarray:
    """z0 = [x, y, theta, vx, vy, omega] of the COM."""
    i = scene.initial
    return np.array([*i.position, i.angle, *i.velocity, i.angular_velocity], dtype=np.float64)
