"""MuJoCo's friction rows under the penalty mapping: made to read min(c_t |v|, mu Fn).

    penalty_friction_rows(scene, props, a_hat, impedance, dt) -> FrictionRows
        impratio = FRICTION_IMPRATIO; c_t = mu alpha N_ref (N s/m), the law's slope at zero slip
        at the resting load N_ref = m g / n_rest (N), or 1 / (A_ref dt) for the bare sign;
        solreffriction's B = c_t (A_ref + R_t), so a row reads f = -c_t v at A_ref (1/kg)

Why MuJoCo's defaults fail (viscous with the normal damping; sliding raises Fn) and the
derivation: docs/physics.md#the-penalty-mappings-friction-rows.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .rigid_body import RigidBody
from scene_types.schema import Scene

FRICTION_IMPRATIO = 1e4


@dataclass(frozen=True)
class FrictionRows:
    """impratio, solreffriction (direct form), and the numbers behind them."""

    impratio: float
    solreffriction: tuple[float, float]
    damping: float        # c_t, N s/m: the viscous slope of a friction row below mu Fn
    reference_load: float  # N_ref, N per contact (0 without gravity)
    a_ref: float          # 1/kg, tangential inverse inertia of a resting contact point


def resting_contacts(scene: Scene) -> int:
    """Contact points that carry the body at rest: 1 (point, circle) or 2 (the ends of a face)."""
    return 1 if scene.body.shape in ("point", "circle") else 2


def tangential_inverse_inertia(scene: Scene, props: RigidBody) -> float:
    """1/m + r_y^2 / I (1/kg) at the lowest contact point of the body lying at theta = 0."""
    inv = 1.0 / props.mass
    if not props.rotates:
        return inv
    ry = scene.body.radius if scene.body.shape == "circle" else float(np.min(props.points[:, 1]))
    return inv + ry * ry / props.inertia


def penalty_friction_rows(scene: Scene, props: RigidBody, a_hat: float,
                          impedance: float, dt: float) -> FrictionRows:
    """The friction rows of the penalty mapping (docs/physics.md); a_hat 1/kg, impedance d,
    dt the twin's step (s: the sign law's row)."""
    impratio = FRICTION_IMPRATIO
    a_ref = tangential_inverse_inertia(scene, props)
    if scene.contact.friction_law == "sign":
        load = props.mass * scene.g / resting_contacts(scene) if scene.has("gravity") else 0.0
        damping = 1.0 / (a_ref * dt)
    elif scene.has("gravity"):
        load = props.mass * scene.g / resting_contacts(scene)
        damping = scene.contact.mu * scene.contact.alpha * load
    else:
        load, damping = 0.0, scene.contact.c
    r_t = (1.0 - impedance) / impedance * a_hat / impratio
    # B = -solreffriction[1] / d must equal c_t (A_ref + R_t)
    return FrictionRows(impratio, (0.0, -impedance * damping * (a_ref + r_t)), damping, load, a_ref)
