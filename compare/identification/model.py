"""A candidate law set (gravity, body, the three families) as the body's accelerations, vectorised."""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .families import Family
from .geometry import Geometry


@dataclass(frozen=True)
class Law:
    """Everything a step's forces depend on: g (m/s^2), mass (kg), inertia (kg m^2), the contact
    points, and each effect's family with its parameters (None: the effect is not applied)."""

    g: float
    mass: float
    inertia: float
    geometry: Geometry
    normal: tuple[Family, tuple] | None
    friction: tuple[Family, tuple] | None
    rolling: tuple[Family, tuple] | None

    def with_(self, **changes) -> Law:
        return replace(self, **changes)


@dataclass(frozen=True)
class Kinematics:
    """What contacts() takes from the states and the points alone, whatever the law: per state
    and point, arms (m), depth (m), normal velocity and slip (m/s), touching mask; and the spin
    (n, 1) rad/s. A fit that tries many laws on the same states computes it once."""

    geometry: Geometry
    rx: np.ndarray
    ry: np.ndarray
    d: np.ndarray
    vn: np.ndarray
    slip: np.ndarray
    touching: np.ndarray
    om: np.ndarray


@dataclass(frozen=True)
class Contacts(Kinematics):
    """The kinematics with a law's forces at each point: normal and friction force (N), rolling
    torque (N m)."""

    fn: np.ndarray
    ft: np.ndarray
    roll: np.ndarray


def kinematics(geometry: Geometry, Z: np.ndarray) -> Kinematics:
    """The contact points' kinematics at states Z (n, 6)."""
    Z = np.atleast_2d(np.asarray(Z, dtype=float))
    y, theta, vx, vy, om = Z[:, 1:2], Z[:, 2], Z[:, 3:4], Z[:, 4:5], Z[:, 5:6]
    rx, ry = geometry.arms(theta)
    d = geometry.onset - (y + ry) if geometry.onset else -(y + ry)
    return Kinematics(geometry, rx, ry, d, vy + om * rx, vx - om * ry, d > 0.0, om)


def contacts(law: Law, Z: np.ndarray, kin: Kinematics | None = None) -> Contacts:
    """The contact quantities of every point at states Z (n, 6); kin: kinematics(law.geometry,
    Z) when already computed (it is used only for that geometry, or for the same points with
    another onset: the depths shifted)."""
    if kin is not None and kin.geometry is not law.geometry and kin.geometry.points is law.geometry.points \
            and kin.geometry.rotate == law.geometry.rotate:   # the same points, another onset: d shifts
        d = kin.d + (law.geometry.onset - kin.geometry.onset)
        kin = replace(kin, geometry=law.geometry, d=d, touching=d > 0.0)
    elif kin is None or kin.geometry is not law.geometry:
        kin = kinematics(law.geometry, Z)
    d, vn, slip, touching, om = kin.d, kin.vn, kin.slip, kin.touching, kin.om
    zero = np.zeros_like(d)
    fn = zero
    if law.normal is not None:
        fam, p = law.normal
        fn = np.where(touching, fam.force(np.where(touching, d, 0.0), vn, p), 0.0)
    ft = roll = zero
    if law.friction is not None:
        fam, p = law.friction
        ft = np.where(touching, fam.force(fn, slip, p), 0.0)
    if law.rolling is not None:
        fam, p = law.rolling
        roll = np.where(touching, fam.force(fn, om, p), 0.0)
    return Contacts(**vars(kin), fn=fn, ft=ft, roll=roll)


def accelerations(law: Law, Z: np.ndarray, kin: Kinematics | None = None) -> np.ndarray:
    """(ax, ay, alpha) at states Z (n, 6): m/s^2, m/s^2, rad/s^2 (kin: as contacts())."""
    c = contacts(law, Z, kin)
    fx = c.ft.sum(axis=1)
    fy = c.fn.sum(axis=1) - law.mass * law.g
    tau = (c.rx * c.fn - c.ry * c.ft + c.roll).sum(axis=1)
    alpha = tau / law.inertia if law.geometry.rotates else np.zeros_like(tau)
    return np.column_stack([fx / law.mass, fy / law.mass, alpha])


def force_terms(law: Law, Z: np.ndarray) -> np.ndarray:
    """The magnitudes (n, 3) whose rounding a force evaluation carries, per channel (N, N, N m):
    each term of each touching point's force, with the inputs that enter it (a depth
    d = -(y + r_y) rounds on |y| + |r_y|, not on d), so that a few ulps of these bound two
    codes' difference in computing the same law."""
    c = contacts(law, Z)
    Z = np.atleast_2d(np.asarray(Z, dtype=float))
    y, vx, vy, om = (np.abs(Z[:, j:j + 1]) for j in (1, 3, 4, 5))
    k = c_eff = 0.0
    if law.normal is not None:
        fam, p = law.normal
        k = abs(p[0])
        c_eff = abs(p[1]) if fam.name != "hunt_crossley" else abs(p[0] * p[1]) * np.abs(c.d)
    arm = np.hypot(c.rx, c.ry)
    n_terms = k * (y + np.abs(c.ry)) + c_eff * (vy + np.abs(om * c.rx) + np.abs(c.vn)) + np.abs(c.fn)
    t_terms = np.zeros_like(n_terms)
    if law.friction is not None and law.friction[1]:
        fam, p = law.friction
        sharp = abs(p[1]) if len(p) > 1 else 0.0
        t_terms = abs(p[0]) * (n_terms + np.abs(c.fn) * (1.0 + sharp * (vx + np.abs(om * c.ry))))
    r_terms = np.zeros_like(n_terms)
    if law.rolling is not None and law.rolling[1]:
        fam, p = law.rolling
        sharp = abs(p[1]) if len(p) > 1 else 0.0
        r_terms = abs(p[0]) * (n_terms + np.abs(c.fn) * (1.0 + sharp * om))
    q_terms = np.abs(c.rx) * n_terms + np.abs(c.ry) * t_terms + r_terms + arm * (np.abs(c.fn) + np.abs(c.ft))
    on = c.touching
    return np.column_stack([np.where(on, t_terms, 0.0).sum(axis=1),
                            law.mass * abs(law.g) + np.where(on, n_terms, 0.0).sum(axis=1),
                            np.where(on, q_terms, 0.0).sum(axis=1)])
