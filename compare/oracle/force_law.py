"""The reference's force law on many states at once (numpy), with a round-off scale beside it.

    accelerations(eq, Z, law) -> (a, scale): a (N, 3) = (ax, ay, alpha) in m/s^2, m/s^2, rad/s^2
        at states Z (N, 6) = [x, y, theta, vx, vy, omega], scale its round-off scale (same units)

The equations of reference.right_hand_side, written for arrays, each row on its own branch of
every switch; every family of scene_types.laws. `Law` names the ways a hand-written simulator
can deviate (compare/diagnosis/mistakes.py replaces one field at a time). `scale` is the sum of
the magnitudes of every term that enters an acceleration, what its round-off is proportional to.
Derivation: docs/oracle-laws.md#the-force-law-and-its-round-off-scale.
"""
from __future__ import annotations

from dataclasses import dataclass
from collections.abc import Callable

import numpy as np

from scene_types import Contact

from .reference import Equations

EPS = np.finfo(float).eps
# The slip vx - omega r_y of two codes differs by a few roundings of its inputs (the rotation of
# the arm, the product, the difference) and, at an RK4 stage, of the stage state itself: within
# SIGN_ULPS eps (|vx| + |omega| |r|) of zero its sign is not decided by the law but by rounding.
SIGN_ULPS = 64.0
# The schema's sharpness for a regularised family (s/m, s/rad): what a code uses that regularises
# where the scene asks the bare sign (a variant "tanh where the scene asks sign" needs a number).
DEFAULT_ALPHA = Contact().alpha
DEFAULT_ROLL_SHARPNESS = Contact().roll_sharpness


@dataclass(frozen=True)
class Law:
    """How the force law is evaluated; the defaults are the scene's own law (the reference).
    The fields: docs/oracle-laws.md#the-mistakes-knob. A regularised family the scene gives no
    sharpness for (tanh where it asks sign) uses DEFAULT_ALPHA or DEFAULT_ROLL_SHARPNESS."""

    slip_velocity: str = "contact"     # "contact": friction on the slip vc_x; "com": on vx
    torque_sign: float = 1.0           # +1: r_x Fy - r_y Fx; -1: the cross product backwards
    damping_in_air: bool = False       # the damper also acts at points not touching (d <= 0)
    damping_law: str | Callable | None = None     # None: the scene's; a family; Fn(eq, d, vc_y)
    friction_shape: str | Callable | None = None  # None: the scene's; a family; phi(slip, alpha)
    friction_load: str = "point"       # "point": mu Fn_i; "body": mu times the sum of all Fn
    gravity_mass: bool = True          # False: a weight of g newtons (the m forgotten)
    rolling: str = "scene"             # "scene", "tanh", "sign" or "none"
    points_turn: bool = True           # False: corners never rotated


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


def damping_family(eq: Equations, law: Law = SEED_LAW):
    """The damping law the code evaluates: a family name or a variant's function."""
    return law.damping_law or eq.law


def friction_family(eq: Equations, law: Law = SEED_LAW):
    """The friction law the code evaluates: a family name or a variant's function."""
    return law.friction_shape or eq.friction_law


def normal_force(eq: Equations, d, vcy, law: Law = SEED_LAW):
    """Fn (N) of the law's damping family at depths d (m) and normal velocities vc_y (m/s),
    arrays of one shape; meaningful where the point touches (d > 0)."""
    name = damping_family(eq, law)
    if callable(name):
        return name(eq, d, vcy)
    k, c = eq.k, eq.c
    if name == "compression":
        return k * d + c * np.maximum(0.0, -vcy)
    if name == "linear":
        return np.maximum(0.0, k * d - c * vcy)
    if name == "unclamped":
        return k * d - c * vcy
    if name == "hunt_crossley":
        return np.maximum(0.0, k * d * (1.0 - eq.dissipation * vcy))
    raise ValueError(f"unknown damping law {name!r}")


def normal_scale(eq: Equations, d, y, vy, om, r_err, law: Law = SEED_LAW):
    """What the round-off of Fn is proportional to (N): k (|y| + |r|) + c (|vy| + |omega| |r|)
    for the c-families; Hunt-Crossley's product k d (1 - D v_n) carries k (|y| + |r|) (1 + D V)
    + k |d| D V, V = |vy| + |omega| |r| the normal velocity's magnitude. A variant's function
    is taken at its scene's family."""
    name = damping_family(eq, law)
    if callable(name) or name != "hunt_crossley":
        name = eq.law
    if name != "hunt_crossley":
        return eq.k * (np.abs(y) + r_err) + eq.c * (np.abs(vy) + np.abs(om) * r_err)
    speed = np.abs(vy) + np.abs(om) * r_err
    diss = eq.dissipation * speed
    return eq.k * (np.abs(y) + r_err) * (1.0 + diss) + eq.k * np.abs(d) * diss


def _sharpness(eq: Equations) -> float:
    """alpha (s/m) for a regularised family: the scene's, or the default where it asks sign."""
    return eq.alpha if np.isfinite(eq.alpha) else DEFAULT_ALPHA


def friction_shape(eq: Equations, slip, law: Law = SEED_LAW):
    """(phi, dphi, alpha): the unit shape phi(slip) in [-1, 1] of the law's friction family at
    slips (m/s), |d phi / d(alpha slip)| (dimensionless) for the round-off scale, and the
    sharpness alpha (s/m; 0 for the sign, whose slope is nowhere finite but at its jump)."""
    name = friction_family(eq, law)
    if callable(name):
        alpha = _sharpness(eq)
        phi = name(slip, alpha)
        name = eq.friction_law
    else:
        phi = None
    if name == "sign":
        return (np.sign(slip) if phi is None else phi), np.zeros_like(slip), 0.0
    alpha = _sharpness(eq)
    arg = alpha * slip
    if name == "tanh":
        if phi is None:
            phi = np.tanh(arg)
        return phi, 1.0 - np.tanh(arg) ** 2, alpha
    if name == "ramp":
        inside = np.abs(arg) <= 1.0
        return (np.clip(arg, -1.0, 1.0) if phi is None else phi), inside.astype(float), alpha
    if name == "smooth_coulomb":
        if phi is None:
            phi = slip / np.sqrt(slip * slip + 1.0 / alpha ** 2)
        return phi, (1.0 + arg * arg) ** -1.5, alpha
    raise ValueError(f"unknown friction law {name!r}")


def sign_undecided(eq: Equations, slip, vx, om, r_err, law: Law = SEED_LAW):
    """(N, n) bool: where the law's friction is the bare sign and the slip lies within its own
    round-off of zero (SIGN_ULPS), so that two codes may take either side of the jump (a slip
    of exactly 0 from inputs of exactly 0 rounds nowhere: decided)."""
    name = friction_family(eq, law)
    if name != "sign":
        return np.zeros(np.shape(slip), dtype=bool)
    return np.abs(slip) < SIGN_ULPS * EPS * (np.abs(vx) + np.abs(om) * r_err)


def rolling_shape(eq: Equations, om, law: Law = SEED_LAW):
    """(s, s_scale): the rolling law's unit shape s(omega) and the round-off of tanh's argument
    carried through it (dimensionless); the sign of omega, a state component, rounds nowhere."""
    sharp = eq.roll_sharpness
    if law.rolling == "sign" or (law.rolling == "scene" and sharp is None):
        return np.sign(om), np.zeros_like(om)
    sharp = DEFAULT_ROLL_SHARPNESS if sharp is None else sharp
    s = np.tanh(sharp * om)
    return s, sharp * (1.0 - s * s) * np.abs(om)


def _friction(eq: Equations, law: Law, fn, fn_scale, acting, vx2, om2, vcx, r_err, jumps: bool = True):
    """(Ft, Ft's round-off scale), each (N, n) N, at the acting points; jumps: add the bare
    sign's jump where rounding decides its side (see accelerations)."""
    slip = vcx if law.slip_velocity == "contact" else vx2 * np.ones_like(vcx)
    load = fn if law.friction_load == "point" else fn.sum(axis=1, keepdims=True) * acting
    load_scale = fn_scale if law.friction_load == "point" else fn_scale.sum(axis=1, keepdims=True) * acting
    shape, dshape, alpha = friction_shape(eq, slip, law)
    ft = np.where(acting, -eq.mu * load * shape, 0.0)
    # d phi = alpha phi' d slip, d slip ~ eps (|vx| + |omega| |r|)
    ft_scale = np.where(acting, eq.mu * (load_scale + np.abs(load) * alpha * dshape
                                         * (np.abs(vx2) + np.abs(om2) * r_err)), 0.0)
    turning = om2 if law.slip_velocity == "contact" else np.zeros_like(om2)   # vx itself rounds nowhere
    undecided = sign_undecided(eq, slip, vx2, turning, r_err, law) & acting
    if jumps and undecided.any():
        # a jump of 2 mu |Fn| that rounding may or may not take, entered as its size over eps
        ft_scale = ft_scale + np.where(undecided, 2.0 * eq.mu * np.abs(load) / EPS, 0.0)
    return ft, ft_scale


def accelerations(eq: Equations, Z: np.ndarray, law: Law = SEED_LAW, touching=None, jumps: bool = True):
    """(a, scale): accelerations (ax, ay, alpha_theta) of shape (N, 3) in m/s^2, m/s^2, rad/s^2
    at the states Z (N, 6), and the round-off scale of each (same units, see the module docstring).
    touching (N, n) bool, optional: which points act, instead of d > 0 (to evaluate both sides
    of a contact switch at one state). jumps: the scale includes a bare sign's jump 2 mu |Fn|
    (over eps) where the slip is within its round-off of zero (sign_undecided), the difference
    two codes may take; False leaves it out, for telling a root of an equation from a point on
    that jump (the jump is no rounding of a root)."""
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
        fn = normal_force(eq, d, vcy, law)
        fn_scale = normal_scale(eq, d, y2, vy2, om2, r_err, law)
        if law.damping_in_air:
            acting = np.ones_like(touching)
            fn = np.where(touching, fn, eq.c * np.maximum(0.0, -vcy))
        else:
            acting = touching
            fn = np.where(touching, fn, 0.0)
        fn_scale = np.where(acting, fn_scale, 0.0)
        ft = np.zeros_like(fn)
        ft_scale = np.zeros_like(fn)
        if eq.friction:
            ft, ft_scale = _friction(eq, law, fn, fn_scale, acting, vx2, om2, vcx, r_err, jumps)
        fx += ft.sum(axis=1)
        fy += fn.sum(axis=1)
        tau += law.torque_sign * (rx * fn - ry * ft).sum(axis=1)
        sx += ft_scale.sum(axis=1)
        sy += fn_scale.sum(axis=1)
        st += (r_err * (fn_scale + ft_scale + np.abs(fn) + np.abs(ft))).sum(axis=1)
        if eq.rolling and law.rolling != "none":
            s, s_scale = rolling_shape(eq, om2, law)
            tau -= (eq.mu_roll * fn * s).sum(axis=1)
            st += (eq.mu_roll * (fn_scale + np.abs(fn) * (1.0 + s_scale))).sum(axis=1)
    inv_i = 1.0 / eq.inertia if eq.rotates else 0.0
    a = np.column_stack([fx / m, fy / m, tau * inv_i])
    scale = np.column_stack([sx / m, sy / m, st * inv_i])
    return a, scale


def bare_sign(eq: Equations, law: Law = SEED_LAW) -> bool:
    """Whether the law, in this scene, has a bare sign: friction "sign" or rolling "sign" (the
    force jumps where a slip or omega crosses zero)."""
    friction = eq.contact and eq.friction and friction_family(eq, law) == "sign"
    rolling = eq.contact and eq.rolling and law.rolling != "none" and (
        law.rolling == "sign" or (law.rolling == "scene" and eq.roll_sharpness is None))
    return bool(friction or rolling)


def contact_state(eq: Equations, Z: np.ndarray):
    """Per state and point: depth d (N, n) m and slip velocity vc_x (N, n) m/s."""
    rx, ry, _ = arms(eq, np.atleast_2d(Z)[:, 2])
    Z = np.atleast_2d(Z)
    return -(Z[:, 1:2] + ry), Z[:, 3:4] - Z[:, 5:6] * ry
