"""Fitting through the step itself: a candidate law stepped by the integrator, compared with the user's."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .fit import LSQ_MAX_EVALUATIONS, PARAMETER_FLOOR, polish, worst
from .integrators import evaluated_at, predicted_rate
from .model import Law, kinematics
from .roundoff import inertias, rate_bound


def build(law: Law, slots: list[tuple[str, int]], x) -> Law:
    """The law with the slots' values set from x."""
    changes: dict = {}
    for (slot, j), value in zip(slots, x):
        value = float(value)
        if slot in ("g", "inertia"):
            changes[slot] = value
        elif slot == "lx":
            pts = law.geometry.points.copy()
            pts[:, 0] = value
            changes["geometry"] = law.geometry.with_points(pts)
        elif slot == "onset":
            changes["geometry"] = changes.get("geometry", law.geometry).with_onset(value)
        else:
            fam, p = changes.get(slot, getattr(law, slot))
            p = list(p)
            p[j] = value
            changes[slot] = (fam, tuple(p))
    return law.with_(**changes)


def values(law: Law, slots: list[tuple[str, int]]) -> np.ndarray:
    out = []
    for slot, j in slots:
        if slot in ("g", "inertia"):
            out.append(getattr(law, slot))
        elif slot == "lx":
            out.append(law.geometry.points[0, 0])
        elif slot == "onset":
            out.append(law.geometry.onset)
        else:
            out.append(getattr(law, slot)[1][j])
    return np.array(out, dtype=float)


def family_slots(law: Law, effect: str) -> list[tuple[str, int]]:
    part = getattr(law, effect)
    return [] if part is None else [(effect, j) for j in range(len(part[1]))]


@dataclass
class Stepped:
    """The user's steps beside a law's: residual (n, 3) in N, N, N m and the bound (n, 3)."""

    residual: np.ndarray
    bound: np.ndarray

    def worst(self, rows, channels) -> tuple[float, float]:
        return worst(self.residual[np.ix_(rows, channels)], self.bound[np.ix_(rows, channels)])


def compare(law: Law, integrator: str, Z0, Z1, H, rounding=None, base: np.ndarray | None = None) -> Stepped:
    """The user's velocity change against the law's under the integrator, with its bound
    (base: a bound already taken with the state's uncertainty carried by one law, kept as a
    floor; the law's own terms are added without carrying it again)."""
    M = inertias(law)
    rate = (Z1[:, 3:] - Z0[:, 3:]) / H[:, None]
    resid = (rate - predicted_rate(law, integrator, Z0, Z1, H)) * M
    if base is None:
        return Stepped(resid, rate_bound(law, integrator, Z0, Z1, H, rounding))
    return Stepped(resid, np.maximum(base, rate_bound(law, integrator, Z0, Z1, H, rounding, sensitivity=False)))


def fit(law: Law, slots, integrator: str, Z0, Z1, H, rows, channels, rounding=None,
        bound: np.ndarray | None = None, max_nfev: int = LSQ_MAX_EVALUATIONS) -> Law:
    """The law with `slots` fitted by least squares on the rows and channels given (weights:
    1 / the starting law's round-off bound, or `bound`)."""
    if not slots:
        return law
    Z0r, Z1r, Hr = Z0[rows], Z1[rows], H[rows]
    B = (rate_bound(law, integrator, Z0r, Z1r, Hr, rounding, sensitivity=False) if bound is None
         else bound[rows])[:, channels]
    # a channel where nothing acts has a zero bound (and a zero residual): weigh it as the others
    B = np.maximum(B, np.finfo(float).eps * np.max(B, initial=0.0) + np.finfo(float).tiny)
    rate = ((Z1r[:, 3:] - Z0r[:, 3:]) / Hr[:, None])[:, channels]
    Ze = evaluated_at(integrator, Z0r, Z1r)
    kin = None if Ze is None else kinematics(law.geometry, Ze)   # every trial that keeps the points

    def fun(x):
        trial = build(law, slots, x)
        M = inertias(trial)[channels]
        with np.errstate(all="ignore"):   # an inertia of 0 on the way: a huge residual, not a NaN
            r = ((rate - predicted_rate(trial, integrator, Z0r, Z1r, Hr, kin)[:, channels]) * M / B).ravel()
        return np.where(np.isfinite(r), r, 1e150)
    lower = [-np.inf if slot in ("lx", "inertia") else PARAMETER_FLOOR for slot, _ in slots]
    return build(law, slots, polish(fun, values(law, slots), lower, max_nfev))
