"""Where contact begins: each contact point found by bisection on the height, whatever the law."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .geometry import Geometry
from .integrators import FALL_SHARE, READS_AT_END
from .probes import Scales, onset_angles
from .roundoff import POINT_ULPS, eps

# Steps of doubling tried to bracket the onset, up or down from the scene's own point.
BRACKET_TRIES = 12
# A force is seen where the step's velocity differs from free fall's by more than this many ulps
# of the vertical velocity (an angular one times the body's size): the rounding of v1 = v0 - g h.
TOUCH_ULPS = 2.0


@dataclass
class PointFound:
    """A contact point found: index in the scene's list, angles (rad), onset arms r_y (m),
    the fitted body-frame point (lx, ly) (lx None when the points do not turn: not seen from
    heights), the largest residual (m) and its ratio to the round-off bound (relative), and
    the point's uncertainty (m) from that bound."""

    index: int
    angles: list[float]
    ry: np.ndarray
    point: tuple[float | None, float]
    residual: float
    relative: float
    uncertainty: np.ndarray
    bound: np.ndarray | None = None   # each height's round-off bound (m)


class OnsetSearch:
    """Bisection on the height of the centre of mass, the body at rest at a given angle."""

    def __init__(self, calls, geometry: Geometry, scales: Scales, g: float, integrator: str):
        self.calls, self.geometry, self.scales = calls, geometry, scales
        self.h = scales.dt
        self.shift = FALL_SHARE.get(integrator, 0.0) * g * self.h * self.h
        self._free = {}
        self.onset = None
        self.lift = 0.0
        if integrator in READS_AT_END:
            self.lift = -self._free_fall(0.0)[1]
            self._free = {}

    def _free_fall(self, theta: float) -> np.ndarray:
        if theta not in self._free:
            y = 10.0 * self.scales.size + 1.0
            self._free[theta] = self.calls.one([0.0, y, theta, 0.0, self.lift, 0.0], self.h, "free fall")[3:]
        return self._free[theta]

    def touches(self, theta: float, y: float) -> bool:
        """Whether the step's velocity change differs from free fall's beyond its rounding:
        TOUCH_ULPS of |v| (a smooth field's 1e-228 N far above the ground is no force seen; the
        first force of a penalty law shows a few ulps deeper, inside POINT_ULPS)."""
        v1 = self.calls.one([0.0, y, theta, 0.0, self.lift, 0.0], self.h, f"onset at angle {theta:.6g} rad")[3:]
        free = self._free_fall(theta)
        tol = TOUCH_ULPS * eps() * (np.abs(v1[1]) + np.abs(free[1]))
        return bool(np.any(np.abs(v1 - free) * np.array([1.0, 1.0, max(self.scales.size, 1e-3)]) > tol))

    def height(self, i: int, theta: float) -> float | None:
        """The onset height y* (m) of the centre of mass at angle theta: touching below, not above."""
        _, ry = self.geometry.arm(i, theta)
        guess = -float(ry)
        step = max(self.scales.depth, 1e-6 * self.scales.size)
        hi = lo = None
        for k in range(BRACKET_TRIES):
            y = guess + step * 2.0 ** k
            if not self.touches(theta, y):
                hi = y
                break
        for k in range(BRACKET_TRIES):
            y = guess - 0.5 * step * 2.0 ** (k - BRACKET_TRIES // 2)
            if hi is not None and y >= hi:
                continue
            if self.touches(theta, y):
                lo = y
                break
        if hi is None or lo is None:
            return None
        while True:
            mid = lo + 0.5 * (hi - lo)
            if mid <= lo or mid >= hi:
                return 0.5 * (lo + hi)
            if self.touches(theta, mid):
                lo = mid
            else:
                hi = mid

    def points(self) -> tuple[list[PointFound], list[int], bool | None]:
        """(points found, indices never found touching, whether they turn with theta: True or
        False as the heights say, None when no hypothesis fits)."""
        found, missing = [], []
        for i, angles in onset_angles(self.geometry):
            with self.calls.session():
                ys = [self.height(i, th) for th in angles]
            if any(y is None for y in ys):
                missing.append(i)
                continue
            ys = np.array(ys)
            ry = -(ys - self.shift)
            # plus the depth whose force first shows in v1 = v0 - g h + h Fn / m: an ulp of the
            # weight's share, Fn = k d ~ eps m g, a depth of eps m g / k (the resting depth's eps)
            unit = eps()   # float32 arithmetic: its own eps
            bound = (POINT_ULPS * unit * (np.abs(ys) + np.hypot(*self.geometry.points[i])) + 4.0 * unit * self.shift
                     + POINT_ULPS * unit * self.scales.depth)
            found.append(self._fit(i, np.array(angles), ry, bound))
            found[-1].bound = bound
        self.onset = self._world_onset(found)
        turn = None
        if found:
            rotating = [f for f in found if f.point[0] is not None]
            if self.geometry.rotate and len(rotating) == len(found):
                turn = True if all(f.relative <= 1.0 for f in found) else None
            elif not self.geometry.rotate:
                turn = False if all(f.relative <= 1.0 for f in found) else None
        return found, missing, turn

    def _world_onset(self, found: list[PointFound]) -> float | None:
        """The height above the ground (m) where the force begins, when that is not at the
        contact points and the same for every point (a world-frame margin or field), or None.
        Points that turn: each point's l and one shared onset b fitted to r_y = sin(theta) l_x +
        cos(theta) l_y - b (found replaced by the joint fit where it holds and the points alone
        do not). A point that does not turn: b = the scene's l_y - the one found (the two are
        one unknown; named as the onset, the point kept the scene's)."""
        if not found:
            return None
        if not self.geometry.rotate:
            f = found[0]
            b = float(self.geometry.points[f.index, 1] - f.point[1])
            if abs(b) <= f.uncertainty[1] or any(g.relative > 1.0 for g in found):
                return None
            for g in found:
                g.point = (g.point[0], float(self.geometry.points[g.index, 1]))
            return b
        if all(f.relative <= 1.0 for f in found) or any(f.point[0] is None for f in found):
            return None
        n = len(found)
        rows, target, bound = [], [], []
        for j, f in enumerate(found):
            for th, ry, bd in zip(f.angles, f.ry, f.bound):
                row = np.zeros(2 * n + 1)
                row[2 * j:2 * j + 2] = np.sin(th), np.cos(th)
                row[-1] = -1.0
                rows.append(row)
                target.append(ry)
                bound.append(bd)
        A, t, bound = np.array(rows), np.array(target), np.array(bound)
        x = np.linalg.lstsq(A, t, rcond=None)[0]
        x = x + np.linalg.lstsq(A, t - A @ x, rcond=None)[0]   # one refinement: the residual in metres
        resid = np.abs(A @ x - t)
        relative = float(np.max(resid / bound))
        if relative > 1.0 or A.shape[0] <= A.shape[1]:
            return None
        unc = np.abs(np.linalg.pinv(A)) @ bound
        for j, f in enumerate(found):
            f.point = (float(x[2 * j]), float(x[2 * j + 1]))
            f.relative = relative
            f.residual = float(np.max(resid))
            f.uncertainty = unc[2 * j:2 * j + 2]
        return float(x[-1])

    def _fit(self, i: int, angles: np.ndarray, ry: np.ndarray, bound: np.ndarray) -> PointFound:
        if self.geometry.rotate:
            A = np.column_stack([np.sin(angles), np.cos(angles)])
            pinv = np.linalg.pinv(A)
            l = pinv @ ry
            resid = np.abs(A @ l - ry)
            # a point that does not turn with the body (the user's mistake): r_y the same at every angle
            flat = np.abs(ry - ry.mean())
            if np.max(resid / bound) > 1.0 and np.max(flat / bound) <= 1.0:
                return PointFound(i, list(angles), ry, (None, float(ry.mean())), float(flat.max()),
                                  float(np.max(flat / bound)), np.array([np.inf, bound.max()]))
            return PointFound(i, list(angles), ry, (float(l[0]), float(l[1])), float(resid.max()),
                              float(np.max(resid / bound)), np.abs(pinv) @ bound)
        flat = np.abs(ry - ry.mean())
        return PointFound(i, list(angles), ry, (None, float(ry.mean())), float(flat.max()),
                          float(np.max(flat / bound)), np.array([np.inf, bound.max()]))
