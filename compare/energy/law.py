"""The scene's contact law on many states at once, split into the part it stores and the part it dissipates."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from compare.oracle.rigid_body import RigidBody, rigid_body
from scene_types import Scene

EFFECTS = ("damping", "friction", "rolling")   # the columns of every work array, in this order


@dataclass(frozen=True)
class Loads:
    """The ground's load on every contact point of N states, each array (N, n): arms rx, ry (m,
    world frame), depth d (m, > 0 below the ground), the law's normal force fn (N), its elastic
    part k d (N), friction ft (N, along x) and rolling-resistance torque roll (N m,
    counter-clockwise). Each point's load is scaled by its share (1 touching, 0 in the air)."""

    rx: np.ndarray
    ry: np.ndarray
    d: np.ndarray
    fn: np.ndarray
    elastic: np.ndarray
    ft: np.ndarray
    roll: np.ndarray


def body_of(scene: Scene) -> RigidBody:
    """The scene's mass properties and contact points (compare.oracle.rigid_body)."""
    return rigid_body(scene.body)


def arms(rb: RigidBody, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """World-frame arms (rx, ry), each (N, n) m: the body-frame points turned by theta, or
    as they are for the point mass and the disk (whose point stays straight below)."""
    pts = np.asarray(rb.points, dtype=float).reshape(-1, 2)
    lx, ly = pts[None, :, 0], pts[None, :, 1]
    theta = np.asarray(theta, dtype=float)[:, None]
    if rb.turning:
        cs, sn = np.cos(theta), np.sin(theta)
        return cs * lx - sn * ly, sn * lx + cs * ly
    ones = np.ones_like(theta)
    return lx * ones, ly * ones


def normal_law(contact, d: np.ndarray, vn: np.ndarray) -> np.ndarray:
    """Fn (N) of the scene's damping_law at depth d (m) and normal velocity vn (m/s, > 0 leaving)."""
    k, law = contact.k, contact.damping_law
    if law == "compression":
        return k * d + contact.c * np.maximum(0.0, -vn)
    if law == "linear":
        return np.maximum(0.0, k * d - contact.c * vn)
    if law == "unclamped":
        return k * d - contact.c * vn
    if law == "hunt_crossley":
        return np.maximum(0.0, k * d * (1.0 - contact.dissipation * vn))
    raise ValueError(f"unknown damping_law {law!r}")


def friction_shape(contact, slip: np.ndarray) -> np.ndarray:
    """The friction law's smooth or bare sign of the slip (m/s), between -1 and 1."""
    law = contact.friction_law
    if law == "sign":
        return np.sign(slip)
    x = contact.alpha * slip
    if law == "tanh":
        return np.tanh(x)
    if law == "ramp":
        return np.clip(x, -1.0, 1.0)
    if law == "smooth_coulomb":
        return x / np.hypot(x, 1.0)
    raise ValueError(f"unknown friction_law {law!r}")


def roll_shape(contact, omega: np.ndarray) -> np.ndarray:
    """The rolling law's sign of omega (rad/s): tanh(roll_sharpness omega) or sign(omega)."""
    if contact.roll_law == "sign":
        return np.sign(omega)
    if contact.roll_law == "tanh":
        return np.tanh(contact.roll_sharpness * omega)
    raise ValueError(f"unknown roll_law {contact.roll_law!r}")


def loads(scene: Scene, rb: RigidBody, Z: np.ndarray, share: np.ndarray | None = None) -> Loads:
    """The law's load at every point of the states Z (N, 6); share (N, n): each point's load
    factor, default 1 where d > 0 and 0 elsewhere (implicit Euler's touchdown jump takes a
    fraction, work.py)."""
    Z = np.atleast_2d(np.asarray(Z, dtype=float))
    rx, ry = arms(rb, Z[:, 2])
    zero = np.zeros_like(rx)
    d = -(Z[:, 1:2] + ry)
    if not scene.has("contact"):
        return Loads(rx, ry, d, zero, zero, zero, zero)
    ct = scene.contact
    share = (d > 0.0).astype(float) if share is None else share
    vx, vy, om = Z[:, 3:4], Z[:, 4:5], Z[:, 5:6]
    fn = share * normal_law(ct, d, vy + om * rx)
    ft = -ct.mu * fn * friction_shape(ct, vx - om * ry) if scene.has("friction") else zero
    rolling = scene.has("rolling_friction") and rb.rotates
    roll = -ct.mu_roll * fn * roll_shape(ct, om) if rolling else zero
    return Loads(rx, ry, d, fn, share * ct.k * d, ft, roll)


def accelerations(scene: Scene, rb: RigidBody, Z: np.ndarray, ld: Loads) -> np.ndarray:
    """(ax, ay, alpha_theta) (N, 3) in m/s^2 and rad/s^2 of the loads ld at the states Z, with
    gravity when the scene lists it."""
    fx = ld.ft.sum(axis=1)
    fy = ld.fn.sum(axis=1) - (rb.mass * scene.g if scene.has("gravity") else 0.0)
    tau = (ld.rx * ld.fn - ld.ry * ld.ft + ld.roll).sum(axis=1)
    alpha = tau / rb.inertia if rb.rotates else np.zeros_like(tau)
    return np.column_stack([fx / rb.mass, fy / rb.mass, alpha])


def dissipated_power(ld: Loads, U: np.ndarray) -> np.ndarray:
    """Power (N, 3) W against damping, friction and rolling of the loads ld when the body moves
    at the generalised velocity U (N, 3) = (vx, vy, omega): each point moves at
    (Ux - Uw ry, Uy + Uw rx). The damping force is what the normal law adds to the spring k d."""
    ux, uy, uw = U[:, 0:1], U[:, 1:2], U[:, 2:3]
    damping = -((ld.fn - ld.elastic) * (uy + uw * ld.rx)).sum(axis=1)
    friction = -(ld.ft * (ux - uw * ld.ry)).sum(axis=1)
    rolling = -(ld.roll * uw).sum(axis=1)
    return np.column_stack([damping, friction, rolling])
