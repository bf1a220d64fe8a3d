"""The numeric model the compiled loop reads: a scene flattened to numbers and effect switches.

An effect the scene does not list is switched off, and its parameters are set to NaN: if
its term were ever evaluated, the NaN would reach the state and stop the run, so a finite
trajectory is a proof that the term was never evaluated.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .bodies import MassProperties, mass_properties
from scene_types.schema import Scene

COMPRESSION, LINEAR = 0, 1  # damping laws, see contact_force in forces.py


class Model(NamedTuple):
    inv_mass: float      # 1/kg
    inv_inertia: float   # 1/(kg m^2); 0 for the point mass (never turns)
    g: float             # m/s^2, NaN without gravity
    k: float             # N/m
    c: float             # N s/m
    mu: float            # -, NaN without friction
    alpha: float         # s/m, NaN without friction
    mu_roll: float       # m, NaN without rolling friction
    damping_law: int     # COMPRESSION or LINEAR
    gravity: bool
    contact: bool
    friction: bool
    rolling: bool
    points_rotate: bool  # contact points turn with the body


def build_model(scene: Scene, props: MassProperties | None = None) -> tuple[Model, np.ndarray]:
    """The compiled loop's model and the contact points (n, 2) relative to the COM (m)."""
    props = props or mass_properties(scene.body)
    nan = float("nan")
    ct = scene.contact
    on = scene.has
    model = Model(
        inv_mass=1.0 / props.mass,
        inv_inertia=1.0 / props.inertia if props.rotates else 0.0,
        g=scene.g if on("gravity") else nan,
        k=ct.k if on("contact") else nan,
        c=ct.c if on("contact") else nan,
        mu=ct.mu if on("friction") else nan,
        alpha=ct.alpha if on("friction") else nan,
        mu_roll=ct.mu_roll if on("rolling_friction") else nan,
        damping_law=LINEAR if ct.damping_law == "linear" else COMPRESSION,
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
