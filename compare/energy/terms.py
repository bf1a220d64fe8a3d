"""The terms of a trajectory's mechanical energy (J), each from the states alone."""
from __future__ import annotations

import numpy as np

from compare.oracle.rigid_body import RigidBody
from scene_types import Scene

from .law import arms

TERMS = ("translation", "rotation", "gravity", "contact")


def energy_terms(scene: Scene, rb: RigidBody, Z: np.ndarray) -> dict[str, np.ndarray]:
    """{term: (N,) J} at the states Z (N, 6): translation m |v|^2 / 2, rotation I omega^2 / 2,
    gravity m g y (0 without gravity), contact sum of k d^2 / 2 over touching points (0 without
    contact). Their sum is the energy column of docs/report-files.md."""
    Z = np.atleast_2d(np.asarray(Z, dtype=float))
    y, vx, vy, om = Z[:, 1], Z[:, 3], Z[:, 4], Z[:, 5]
    zero = np.zeros_like(y)
    rotation = 0.5 * rb.inertia * om * om if rb.rotates else zero
    gravity = rb.mass * scene.g * y if scene.has("gravity") else zero
    contact = zero
    if scene.has("contact"):
        _, ry = arms(rb, Z[:, 2])
        d = np.maximum(0.0, -(y[:, None] + ry))
        contact = 0.5 * scene.contact.k * (d * d).sum(axis=1)
    return {"translation": 0.5 * rb.mass * (vx * vx + vy * vy), "rotation": rotation,
            "gravity": gravity, "contact": contact}


def energy(scene: Scene, rb: RigidBody, Z: np.ndarray) -> np.ndarray:
    """E (N,) J: the sum of energy_terms."""
    return sum(energy_terms(scene, rb, Z).values())
