"""Mechanical energy of a trajectory (J), the `energy` column of every trajectory file.

E = m (vx^2 + vy^2) / 2 + I omega^2 / 2     kinetic
  + m g y                                  gravitational (0 without gravity)
  + sum over touching points of k d^2 / 2  elastic contact (0 without contact)

The elastic part of every damping law is the spring k d (hunt_crossley's k d (1 - D vc_y) too:
its damping is the term in vc_y), so one potential serves all of them.
"""
from __future__ import annotations

import numpy as np

from .bodies import MassProperties, contact_points_world
from scene_types.schema import Scene


def energy_parts(scene: Scene, props: MassProperties, states: np.ndarray):
    """(kinetic, gravitational, contact) energy arrays for states of shape (T, 6)."""
    x, y, theta, vx, vy, omega = states.T
    m = props.mass
    kinetic = 0.5 * m * (vx * vx + vy * vy) + 0.5 * props.inertia * omega * omega
    gravity = m * scene.g * y if scene.has("gravity") else np.zeros_like(y)
    contact = np.zeros_like(y)
    if scene.has("contact"):
        _, py = contact_points_world(props, x, y, theta)
        depth = np.maximum(0.0, -py)
        contact = 0.5 * scene.contact.k * np.sum(depth * depth, axis=1)
    return kinetic, gravity, contact
