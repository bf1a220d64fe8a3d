"""The reference's force law on many states at once (numpy), with a round-off scale beside it.

The same equations as reference.right_hand_side, written for arrays: states Z of shape (N, 6) =
[x, y, theta, vx, vy, omega], one row per state, each row on its own branch of every switch
(touching or not, which side of max(), the sign of omega). For contact point i, arm r_i:

    r_i  = R(theta) l_i   (l_i itself for the circle and the point mass)
    d_i  = -(y + r_iy)                     touching while d_i > 0
    vc_i = (vx - omega r_iy, vy + omega r_ix)
    Fn_i = k d_i + c max(0, -vc_iy)        compression law (seed Algorithm 1, line 4)
         | max(0, k d_i - c vc_iy)         linear law (never pulls)
    Ft_i = -mu Fn_i tanh(alpha vc_ix)      (seed Algorithm 1, line 5, at the point's velocity)
    tau  = sum_i (r_ix Fn_i - r_iy Ft_i) - mu_roll Fn_i s(omega)

`Law` names the ways a hand-written simulator can deviate from these lines. The default is the
seed's law; compare/verdict/mistakes.py builds its catalogue by replacing one field at a time,
so a variant differs from the reference in exactly the line it names and nowhere else.

`scale` is what the round-off of each acceleration is proportional to: the sum of the
magnitudes of every term that enters it, each term's inputs taken in absolute value (running
error analysis: a sum of n terms computed in floating point is off by at most about n eps times
the sum of their magnitudes, whatever cancellation leaves of the result). The depth d = -(y + r_y)
is the worst cancellation (0.05 m - 0.0495 m at rest): its round-off is eps (|y| + |r|), and
k times that is the term k (|y| + |r|). An angle theta of many turns costs eps |theta| in
R(theta), so |r| enters as |l| (1 + |theta|).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .reference import Equations


@dataclass(frozen=True)
class Law:
    """How the force law is evaluated. The defaults are the seed's law (the reference).

    slip_velocity      "contact": friction on the contact point's velocity vc_x; "com": on vx
    torque_sign        +1: tau = r x F = r_x Fy - r_y Fx; -1: the cross product taken backwards
    damping_in_air     the damper c max(0, -vc_y) also acts at points not touching (d <= 0)
    damping_law        None: the scene's; else "compression" or "linear" regardless of the scene
    friction_shape     "tanh" or "sign" (the unregularised Coulomb law)
    friction_load      "point": mu Fn_i at each point; "body": mu times the sum of all Fn
    gravity_mass       True: weight m g; False: a force of g newtons (the m forgotten)
    rolling            "scene": as the reference (the scene's roll_law);
                       "sign": the bare sign(omega); "none": no rolling resistance
    points_turn        True: contact arms turn with theta; False: corners never rotated
    """

    slip_velocity: str = "contact"
    torque_sign: float = 1.0
    damping_in_air: bool = False
    damping_law: str | None = None
    friction_shape: str = "tanh"
    friction_load: str = "point"
    gravity_mass: bool = True
    rolling: str = "scene"
    points_turn: bool = True


SEED_LAW = Law()


def arms(eq: Equations, theta: np.ndarray, law: Law = SEED_LAW):
    """World-frame arms (rx, ry) of the contact points, each (N, n) m, and the size of their
    round-off |l| (1 + |theta|) (N, n) m."""
    pts = np.asarray(eq.points, dtype=float)
    lx, ly = pts[:, 0][None, :], pts[:, 1][None, :]
    length = np.hypot(lx, ly)
    theta = theta[:, None]
    if eq.turning and law.points_turn:
        cs, sn = np.cos(theta), np.sin(theta)
        return cs * lx - sn * ly, sn * lx + cs * ly, length * (1.0 + np.abs(theta))
    ones = np.ones_like(theta)
    return lx * ones, ly * ones, length * ones


def accelerations(eq: Equations, Z: np.ndarray, law: Law = SEED_LAW, touching=None):
    """(a, scale): accelerations (ax, ay, alpha_theta) of shape (N, 3) in m/s^2, m/s^2, rad/s^2
    at the states Z (N, 6), and the round-off scale of each (same units, see the module).
    touching (N, n) bool, optional: which points act, instead of d > 0 (to evaluate both sides
    of a contact switch at one state)."""
    Z = np.atleast_2d(Z)
    y, theta, vx, vy, om = Z[:, 1], Z[:, 2], Z[:, 3], Z[:, 4], Z[:, 5]
    n_rows = Z.shape[0]
    m = eq.mass
    weight = m * eq.g if law.gravity_mass else eq.g
    fx = np.zeros(n_rows)
    fy = np.full(n_rows, -weight)
    tau = np.zeros(n_rows)
    sx = np.zeros(n_rows)
    sy = np.full(n_rows, abs(weight))
    st = np.zeros(n_rows)
    if eq.contact:
        rx, ry, r_err = arms(eq, theta, law)
        y2, vx2, vy2, om2 = y[:, None], vx[:, None], vy[:, None], om[:, None]
        d = -(y2 + ry)
        touching = d > 0.0 if touching is None else np.asarray(touching, dtype=bool)
        vcx = vx2 - om2 * ry
        vcy = vy2 + om2 * rx
        k, c = eq.k, eq.c
        if (law.damping_law or eq.law) == "compression":
            fn = k * d + c * np.maximum(0.0, -vcy)
        else:
            fn = np.maximum(0.0, k * d - c * vcy)
        # what the round-off of Fn is proportional to: k (|y| + |r|) + c (|vy| + |omega| |r|)
        fn_scale = k * (np.abs(y2) + r_err) + c * (np.abs(vy2) + np.abs(om2) * r_err)
        if law.damping_in_air:
            acting = np.ones_like(touching)
            fn = np.where(touching, fn, c * np.maximum(0.0, -vcy))
        else:
            acting = touching
            fn = np.where(touching, fn, 0.0)
        fn_scale = np.where(acting, fn_scale, 0.0)
        ft = np.zeros_like(fn)
        ft_scale = np.zeros_like(fn)
        if eq.friction:
            slip = vcx if law.slip_velocity == "contact" else vx2 * np.ones_like(vcx)
            load = fn if law.friction_load == "point" else fn.sum(axis=1, keepdims=True) * acting
            load_scale = fn_scale if law.friction_load == "point" else fn_scale.sum(axis=1, keepdims=True) * acting
            arg = eq.alpha * slip
            shape = np.tanh(arg) if law.friction_shape == "tanh" else np.sign(arg)
            ft = np.where(acting, -eq.mu * load * shape, 0.0)
            # d tanh = alpha sech^2 d slip, d slip ~ eps (|vx| + |omega| |r|)
            sech2 = 1.0 - np.tanh(arg) ** 2
            ft_scale = np.where(acting, eq.mu * (load_scale + np.abs(load) * eq.alpha * sech2
                                                 * (np.abs(vx2) + np.abs(om2) * r_err)), 0.0)
        fx += ft.sum(axis=1)
        fy += fn.sum(axis=1)
        tau += law.torque_sign * (rx * fn - ry * ft).sum(axis=1)
        sx += ft_scale.sum(axis=1)
        sy += fn_scale.sum(axis=1)
        st += (r_err * (fn_scale + ft_scale + np.abs(fn) + np.abs(ft))).sum(axis=1)
        if eq.rolling and law.rolling != "none":
            if law.rolling == "sign" or eq.roll_sharpness is None:
                s = np.sign(om2)
                s_scale = np.zeros_like(om2)
            else:
                s = np.tanh(eq.roll_sharpness * om2)
                s_scale = eq.roll_sharpness * (1.0 - s * s) * np.abs(om2)
            tau -= (eq.mu_roll * fn * s).sum(axis=1)
            st += (eq.mu_roll * (fn_scale + np.abs(fn) * (1.0 + s_scale))).sum(axis=1)
    inv_i = 1.0 / eq.inertia if eq.rotates else 0.0
    a = np.column_stack([fx / m, fy / m, tau * inv_i])
    scale = np.column_stack([sx / m, sy / m, st * inv_i])
    return a, scale


def contact_state(eq: Equations, Z: np.ndarray):
    """Per state and point: depth d (N, n) m and slip velocity vc_x (N, n) m/s (seed law)."""
    rx, ry, _ = arms(eq, np.atleast_2d(Z)[:, 2])
    Z = np.atleast_2d(Z)
    return -(Z[:, 1:2] + ry), Z[:, 3:4] - Z[:, 5:6] * ry
