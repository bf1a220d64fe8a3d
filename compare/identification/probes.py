"""The designed states: flight, where contact begins, depths, normal velocities, slips and spins."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .geometry import Geometry

# How far the lowest point sits above the ground in flight (m), plus twice the body's size.
FLIGHT_CLEARANCE = 1.0
# A probe's point moves at most this share of its depth in one step (it stays in contact, and
# implicit Euler's and RK4's evaluation states stay near the designed one).
DEPTH_SHARE_PER_STEP = 0.2
# A probe's depth stays below this share of the gap to the next-lowest point (one point touches).
DEPTH_SHARE_OF_MARGIN = 0.125
# Normal velocities, as shares of the largest one allowed at each depth (both signs and 0).
VELOCITY_SHARES = (1.0 / 27.0, 1.0 / 9.0, 1.0 / 3.0, 1.0)
NORMAL_DEPTHS = (0.25, 0.5, 1.0, 2.0)       # times the probe depth
FRICTION_DEPTHS = (1.0, 2.0)
# Slips (m/s) in units of 1/alpha (the stiction band), and absolute ones beyond it.
SLIPS_IN_BAND = (0.25, 0.5, 1.0, 1.5, 2.0, 3.0, 5.0)
SLIPS_ABSOLUTE = (0.1, 0.3, 1.0, 3.0)
# Spins (rad/s) in units of 1/roll_sharpness, and absolute ones.
SPINS_IN_BAND = (0.25, 0.5, 1.0, 2.0, 4.0)
SPINS_ABSOLUTE = (1.0, 10.0)
# The scale of a law that takes none (the sign friction, the sign rolling law), s/m and s/rad.
DEFAULT_SHARPNESS = 100.0


@dataclass
class Probes:
    """States (n, 6) stepped with steps H (n,) s, each with the contact point it presses in
    (-1: none) and a kind; Z1 the user's step from each (filled in by the caller)."""

    kind: np.ndarray
    Z0: np.ndarray
    H: np.ndarray
    point: np.ndarray
    Z1: np.ndarray | None = None

    @classmethod
    def build(cls, rows: list[tuple[str, np.ndarray, float, int]]) -> Probes:
        if not rows:
            return cls(np.array([], dtype=object), np.zeros((0, 6)), np.zeros(0), np.zeros(0, dtype=int))
        kind, Z0, H, point = zip(*rows)
        return cls(np.array(kind, dtype=object), np.array(Z0, dtype=float), np.array(H, dtype=float),
                   np.array(point, dtype=int))

    def __len__(self) -> int:
        return len(self.Z0)

    def take(self, mask) -> Probes:
        return Probes(self.kind[mask], self.Z0[mask], self.H[mask], self.point[mask],
                      None if self.Z1 is None else self.Z1[mask])

    def of(self, *kinds: str) -> Probes:
        return self.take(np.isin(self.kind, kinds))

    def join(self, other: Probes) -> Probes:
        z1 = None if self.Z1 is None or other.Z1 is None else np.vstack([self.Z1, other.Z1])
        return Probes(np.concatenate([self.kind, other.kind]), np.vstack([self.Z0, other.Z0]),
                      np.concatenate([self.H, other.H]), np.concatenate([self.point, other.point]), z1)


@dataclass(frozen=True)
class Scales:
    """The scene's numbers the probes are sized by: step dt (s), resting depth (m), damper
    ratio c/k (s), stiction band 1/alpha (m/s), 1/roll_sharpness (rad/s)."""

    dt: float
    depth: float
    c_over_k: float
    band: float
    spin_band: float
    size: float
    depths: dict | None = None   # {multiple of the probe depth: depth m} where the law is not linear
    rest: float = 0.0            # the scene's resting compression m g / k (m), kept when depths are measured

    def at(self, share: float, d0: float) -> float:
        """The probe depth `share` times d0, or the one measured for that multiple."""
        return share * d0 if not self.depths or share not in self.depths else self.depths[share]

    @classmethod
    def of(cls, scene_d: dict, geometry: Geometry) -> Scales:
        ct, mp = scene_d["contact"], scene_d["mass_properties"]
        g = scene_d["g"] if "gravity" in scene_d["effects"] else 0.0
        rest = mp["mass"] * g / ct["k"]
        size = max(geometry.size, 0.05)
        return cls(dt=float(scene_d["dt"]), depth=rest if rest > 0.0 else 1e-3 * size,
                   c_over_k=ct["c"] / ct["k"],
                   band=1.0 / (ct["alpha"] or DEFAULT_SHARPNESS),
                   spin_band=1.0 / (ct["roll_sharpness"] or DEFAULT_SHARPNESS), size=size)


def state(geometry: Geometry, point: int, theta: float, depth: float, vn=0.0, slip=0.0, om=0.0,
          x: float = 0.0) -> np.ndarray:
    """The state that puts `point` at `depth` below the ground with normal velocity vn and slip
    (m/s), the body at angle theta spinning at om: vy = vn - om r_x, vx = slip + om r_y."""
    rx, ry = (float(a) for a in geometry.arm(point, theta))
    return np.array([x, geometry.onset - ry - depth, theta, slip + om * ry, vn - om * rx, om])


def flight(geometry: Geometry, scales: Scales) -> Probes:
    """States high above the ground, at several angles, velocities and spins (none for a point mass)."""
    turns = geometry.rotates
    y = FLIGHT_CLEARANCE + 2.0 * scales.size
    rows = []
    for theta, vx, vy, om in ((0.0, 0.0, 0.0, 0.0), (0.7, 1.5, -2.0, 3.0), (-2.1, -0.7, 1.2, -8.0),
                              (0.3, 0.3, 0.0, 0.5)):
        rows.append(("flight", np.array([0.1, y, theta if turns else 0.0, vx, vy, om if turns else 0.0]),
                     scales.dt, -1))
    return Probes.build(rows)


def main_point(geometry: Geometry) -> tuple[int, float, float]:
    """(point, angle, gap): the farthest point from the centre of mass, turned straight below it
    (no lever arm for the normal force), and the gap (m) to the next-lowest point there."""
    i = int(np.argmax(np.hypot(geometry.points[:, 0], geometry.points[:, 1])))
    theta = geometry.below_angle(i)
    return i, theta, geometry.margin(i, theta)


def probe_depth(scales: Scales, gap: float) -> float:
    """The depth the probes are sized by (m): the resting compression, kept a few times under the gap."""
    return min(scales.depth, DEPTH_SHARE_OF_MARGIN * gap)


def pairs(geometry: Geometry, scales: Scales) -> Probes:
    """Contact states (the main point pressed in twice its probe depth), each stepped with dt and
    dt/2: down, up and sideways (one of each), so the force depends on position and velocity."""
    i, theta, gap = main_point(geometry)
    d = 2.0 * probe_depth(scales, gap)
    v = 0.5 * DEPTH_SHARE_PER_STEP * d / scales.dt
    if scales.c_over_k > 0.0:   # below k d / c, where every damper keeps the force on
        v = min(v, 0.5 * d / scales.c_over_k)
    rows = []
    for vn, slip in ((-v, 0.0), (v, 0.0), (0.0, 2.0 * scales.band)):
        z = state(geometry, i, theta, d, vn, slip)
        rows += [("pair", z, scales.dt, i), ("pair", z, 0.5 * scales.dt, i)]
    return Probes.build(rows)


def onset_angles(geometry: Geometry) -> list[tuple[int, list[float]]]:
    """For each point that can be the lowest: three angles inside its arc where it is (the main
    point's centred on straight below). Points inside the others' hull are left out."""
    if not geometry.rotate:
        i = int(np.argmin(geometry.points[:, 1]))
        return [(i, [0.0, 0.9, -2.2] if geometry.rotates else [0.0])]
    main, below, _ = main_point(geometry)
    out = []
    for i, arc in enumerate(geometry.lowest_arcs()):
        if arc is None:
            continue
        a, b = arc
        if i == main:
            half = 0.5 * min(below - a, b - below)
            centre = below
        else:
            half = 0.25 * (b - a)
            centre = 0.5 * (a + b)
        out.append((i, [centre - half, centre, centre + half]))
    return out


def contact_states(geometry: Geometry, scales: Scales, friction: bool, rolling: bool) -> Probes:
    """The normal, friction, rolling and torque probes on the (identified) geometry."""
    i, theta, gap = main_point(geometry)
    d0 = probe_depth(scales, gap)
    h_normal = scales.dt
    if scales.c_over_k > 0.0:   # reach normal velocities past k d / c, where the clamped dampers differ
        h_normal = min(scales.dt, 0.25 * DEPTH_SHARE_PER_STEP * scales.c_over_k)
    rows = []
    for share in NORMAL_DEPTHS:
        d = scales.at(share, d0)
        # within a step the point moves a fifth of its depth, or of the scene's (a depth measured
        # from a far onset is no scale for the law's speed)
        vmax = DEPTH_SHARE_PER_STEP * min(d, share * d0 if not scales.depths else share * scales.rest) / h_normal
        for v in (0.0, *(s * vmax for s in VELOCITY_SHARES), *(-s * vmax for s in VELOCITY_SHARES)):
            rows.append(("normal", state(geometry, i, theta, d, vn=v), h_normal, i))
    if friction:
        slips = sorted({*(s * scales.band for s in SLIPS_IN_BAND), *SLIPS_ABSOLUTE})
        for share in FRICTION_DEPTHS:
            for s in slips:
                for sign in (1.0, -1.0):
                    rows.append(("friction", state(geometry, i, theta, scales.at(share, d0), slip=sign * s),
                                 scales.dt, i))
        if geometry.rotates:
            spin = 1.0 / scales.size
            for s in (scales.band, 0.3, 3.0):
                for om in (spin, -spin, 10.0 * spin):
                    rows.append(("friction", state(geometry, i, theta, d0, slip=s, om=om), scales.dt, i))
                    rows.append(("friction", state(geometry, i, theta, d0, slip=-s, om=-om), scales.dt, i))
    if rolling:
        spins = sorted({*(s * scales.spin_band for s in SPINS_IN_BAND), *SPINS_ABSOLUTE})
        for share in FRICTION_DEPTHS:
            for om in spins:
                for sign in (1.0, -1.0):
                    rows.append(("rolling", state(geometry, i, theta, scales.at(share, d0), om=sign * om),
                                 scales.dt, i))
    if geometry.rotate:
        for j, angles in onset_angles(geometry):
            for th in (angles[0], angles[2]):
                dj = min(scales.depth, DEPTH_SHARE_OF_MARGIN * geometry.margin(j, th))
                for share in (0.5, 1.0):
                    rows.append(("torque", state(geometry, j, th, share * dj), scales.dt, j))
    return Probes.build(rows)
