"""MuJoCo's friction rows under the penalty mapping: made to read min(c_t |v|, mu Fn).

With flat impedance d (solref.py), an elliptic-cone friction row j of a contact solves

    f_j = (aref_j - a0_j - sum_i A_ji f_i) / (A_jj + R_j),    aref_j = -B v_j,   R_j = R_n / impratio

(K = 0 for friction rows; B = -solreffriction[1] / d, or the normal's damping when
solreffriction is 0 0). Left at MuJoCo's defaults (impratio 1, B from solref), two things go
wrong, both measured by the tests:

- the row is viscous with the *normal* damping c, far weaker than our tanh law, whose slope
  at zero slip is mu Fn alpha (mu alpha m g = 490 N s/m against c = 20 for box_slide);
- when c v > mu Fn the solver projects (Fn, c v) onto the cone in the metric of A + R, and
  with R_t = R_n this raises the normal force to (Fn + mu c v) / (1 + mu^2): a sliding body
  is pushed out of the ground (32 N instead of 10 N at 3 m/s in the test).

So the penalty twin uses explicit contact pairs with

    impratio = FRICTION_IMPRATIO   R_t = R_n / impratio: projecting in the metric of A + R
                                   raises Fn by only mu c_t v (A_t + R_t) / R_n, about
                                   2 mu c_t v / impratio: 2 mu^2 alpha v N_ref / 1e4 = 1 % of
                                   N_ref at 2 m/s for mu 0.5, alpha 100
    c_t = mu alpha N_ref           the friction law's slope at zero slip and the resting load
                                   N_ref = m g / n_rest per contact (tanh, ramp and smooth_coulomb
                                   all have the slope mu Fn alpha there; without gravity: the
                                   normal damping c). The bare sign's slope is infinite: its row
                                   gets c_t = 1 / (A_ref h), the damping that stops a resting
                                   contact point's slip in one step h, the stiffest the step
                                   resolves (a hard Coulomb cone, as MuJoCo's own friction)
    B = c_t (A_ref + R_t)          so that f = -c_t v exactly when A_jj = A_ref, the contact
                                   point's tangential inverse inertia 1/m + r_y^2 / I at rest

R_t = (1 - d) / d * A_hat / impratio is then about A_hat, comparable with A_jj: the row also
cancels a share A_jj / (A_jj + R_t) of the other tangential accelerations at the contact
(partial stiction our tanh law does not have). Rolling rows share B and the cone: their
regularisation is R_t mu^2 / mu_roll^2, which makes the rolling torque c_t (A_ref + R_t)
omega / (A_r + R_t mu^2 / mu_roll^2) below its cap mu_roll Fn.
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
    """The friction rows of the penalty mapping (module docstring); a_hat 1/kg, impedance d,
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
