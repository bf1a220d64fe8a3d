"""Contact points of a body: their arms at an angle, and the arc of angles where each is lowest."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# Angles sampled around the circle to find the arc where each contact point is the lowest.
ARC_SAMPLES = 3600


@dataclass(frozen=True)
class Geometry:
    """points (n, 2): contact points relative to the centre of mass, body frame (m); rotate: they
    turn with theta (box, compound); rotates: theta is a degree of freedom (not the point mass);
    onset: the height above the ground (m, world frame) where a point's force begins (0: at the
    ground; a collision margin or a field starts it above)."""

    points: np.ndarray
    rotate: bool
    rotates: bool
    onset: float = 0.0

    @classmethod
    def of_scene(cls, scene_d: dict) -> Geometry:
        mp = scene_d["mass_properties"]
        return cls(np.array(mp["contact_points"], dtype=float).reshape(-1, 2),
                   bool(mp["points_rotate"]), bool(mp["rotates"]))

    @property
    def size(self) -> float:
        """The farthest contact point from the centre of mass (m)."""
        return float(np.max(np.hypot(self.points[:, 0], self.points[:, 1]))) if len(self.points) else 0.0

    def arms(self, theta) -> tuple[np.ndarray, np.ndarray]:
        """World-frame arms (r_x, r_y) of every point, shape theta.shape + (n,) (m)."""
        theta = np.asarray(theta, dtype=float)[..., None]
        lx, ly = self.points[:, 0], self.points[:, 1]
        if not self.rotate:
            return np.broadcast_to(lx, theta.shape[:-1] + lx.shape), np.broadcast_to(ly, theta.shape[:-1] + ly.shape)
        c, s = np.cos(theta), np.sin(theta)
        return c * lx - s * ly, s * lx + c * ly

    def arm(self, i: int, theta) -> tuple[np.ndarray, np.ndarray]:
        rx, ry = self.arms(theta)
        return rx[..., i], ry[..., i]

    def margin(self, i: int, theta: float) -> float:
        """How far (m) the next point is above point i at angle theta (< 0: i is not the lowest)."""
        _, ry = self.arms(np.array([theta]))
        ry = ry[0]
        others = np.delete(ry, i)
        return float(np.min(others) - ry[i]) if others.size else np.inf

    def below_angle(self, i: int) -> float:
        """The angle that puts point i straight below the centre of mass (rad; 0 if points do not turn)."""
        if not self.rotate:
            return 0.0
        lx, ly = self.points[i]
        return float(np.angle(np.exp(1j * (-0.5 * np.pi - np.arctan2(ly, lx)))))

    def lowest_arcs(self) -> list[tuple[float, float] | None]:
        """For each point, the arc (start, end) of angles (rad, end > start) over which it is the
        lowest point, or None: a point inside the others' hull is never the lowest."""
        if not self.rotate:
            return [(0.0, 0.0) if i == int(np.argmin(self.points[:, 1])) else None for i in range(len(self.points))]
        theta = -np.pi + 2.0 * np.pi * np.arange(ARC_SAMPLES) / ARC_SAMPLES
        _, ry = self.arms(theta)
        order = np.sort(ry, axis=1)
        lowest = np.argmin(ry, axis=1)
        unique = order[:, 1] - order[:, 0] > 1e-12 * max(self.size, 1e-300)
        arcs: list[tuple[float, float] | None] = []
        step = 2.0 * np.pi / ARC_SAMPLES
        for i in range(len(self.points)):
            mine = (lowest == i) & unique
            if not mine.any():
                arcs.append(None)
                continue
            if mine.all():
                arcs.append((-np.pi, np.pi))
                continue
            # runs of consecutive samples (around the circle) where i is lowest: the longest
            starts = np.flatnonzero(mine & ~np.roll(mine, 1))
            best = (0, 0)
            for start in starts:
                rolled = np.roll(mine, -int(start))
                length = int(np.argmin(rolled))
                best = max(best, (length, int(start)))
            length, start = best
            a = theta[start]
            arcs.append((float(a), float(a + (length - 1) * step)))
        return arcs

    def with_points(self, points: np.ndarray) -> Geometry:
        return Geometry(np.asarray(points, dtype=float).reshape(-1, 2), self.rotate, self.rotates, self.onset)

    def with_onset(self, onset: float) -> Geometry:
        return Geometry(self.points, self.rotate, self.rotates, float(onset))
