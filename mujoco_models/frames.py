"""The 2D scene frame inside MuJoCo: the body moves in MuJoCo's x-z plane.

Joints, in this order: slide "x" (axis 1 0 0), slide "y" (axis 0 0 1: MuJoCo's z is our y),
hinge "theta" (axis 0 -1 0, anchored at the COM, so the hinge angle is our counter-clockwise
angle: a positive turn about -y takes +x towards +z). The point mass has no hinge.

The body frame is the scene's geometry frame (compound parts at their offsets), the COM sits
at `com` in it, and the body's origin is the world origin at qpos = 0. A turn about the COM
leaves the COM in place, so

    COM (x, y) = (qpos_x + com_x, qpos_y + com_y),  theta = qpos_theta,  v = qvel.
"""
from __future__ import annotations

import numpy as np

from .rigid_body import RigidBody


def joint_count(props: RigidBody) -> int:
    """nq = nv: 3 for a body that turns, 2 for the point mass."""
    return 3 if props.rotates else 2


def qpos_qvel(props: RigidBody, state) -> tuple[np.ndarray, np.ndarray]:
    """MuJoCo's (qpos, qvel) for a 2D state [x, y, theta, vx, vy, omega]."""
    x, y, theta, vx, vy, omega = (float(s) for s in state)
    cx, cy = props.com
    n = joint_count(props)
    return (np.array([x - cx, y - cy, theta][:n]), np.array([vx, vy, omega][:n]))


def states_from_q(props: RigidBody, qpos: np.ndarray, qvel: np.ndarray) -> np.ndarray:
    """(T, 6) 2D states from qpos and qvel of shape (T, nq)."""
    qpos, qvel = np.atleast_2d(qpos), np.atleast_2d(qvel)
    out = np.zeros((qpos.shape[0], 6))
    out[:, 0] = qpos[:, 0] + props.com[0]
    out[:, 1] = qpos[:, 1] + props.com[1]
    out[:, 3:5] = qvel[:, :2]
    if joint_count(props) == 3:
        out[:, 2] = qpos[:, 2]
        out[:, 5] = qvel[:, 2]
    return out
