"""Whether a simulator's own energy column is the energy of its states, and which term explains it when not."""
from __future__ import annotations

from dataclasses import dataclass, field
from itertools import combinations

import numpy as np

from scene_types import Scene
from scene_types.trajectory import CSV_RELATIVE_ROUNDING

from .law import arms, body_of
from .terms import energy_terms

# the candidate explanations of a difference, fitted as column - E(states) = sum c_j term_j
CANDIDATES = {
    "translation": "translational kinetic energy m |v|^2 / 2",
    "rotation": "rotational kinetic energy I omega^2 / 2",
    "gravity": "gravitational energy m g y",
    "contact": "the contact's k d^2 / 2",
    "offset": "a constant (m g y measured from another height)",
}
MOST_TERMS = 2          # an explanation names at most this many terms
EPS = np.finfo(float).eps


@dataclass(frozen=True)
class ColumnVerdict:
    """agrees: the column is E(states) to within `tolerance` at every row; difference_max and
    tolerance_max (J); explained_by: the terms that explain the difference to within the
    tolerance (empty when it agrees, or when nothing does), each as a sentence, the fewest
    terms first, then whole terms (missing, counted twice) before a constant, before scaled
    terms; coefficients:
    {term: c} of that fit; text: one line for the report; alternatives: other explanations
    with as many terms that fit as well (a run whose terms barely change cannot tell them apart)."""

    agrees: bool
    difference_max: float
    tolerance_max: float
    explained_by: tuple[str, ...] = ()
    coefficients: dict = field(default_factory=dict)
    text: str = ""
    alternatives: tuple[str, ...] = ()


def row_tolerance(scene: Scene, states: np.ndarray, column: np.ndarray, terms: dict) -> np.ndarray:
    """(T,) J: how far the column may sit from E(states) by rounding alone. Each written number
    carries a relative rounding delta (CSV_RELATIVE_ROUNDING): the column delta |E|; the
    kinetic terms, quadratic in the velocities, 2 delta each; m g y, delta; k d^2 / 2, k d
    times the depth's rounding delta (|y| + |r| |theta|); plus the float round-off of the sums
    (8 eps of the largest energy of the run, which every row's sum may carry)."""
    delta = CSV_RELATIVE_ROUNDING
    magnitude = sum(np.abs(v) for v in terms.values())
    tol = delta * np.abs(column) + 2.0 * delta * (terms["translation"] + terms["rotation"]) \
        + delta * np.abs(terms["gravity"]) + 8.0 * EPS * np.max(magnitude + np.abs(column))
    if scene.has("contact"):
        rb = body_of(scene)
        rx, ry = arms(rb, states[:, 2])
        d = np.maximum(0.0, -(states[:, 1:2] + ry))
        reach = np.abs(states[:, 1:2]) + np.hypot(rx, ry) * np.abs(states[:, 2:3])
        tol = tol + scene.contact.k * (d * delta * reach).sum(axis=1)
    return tol


def _fit(basis: dict, names, diff, tol, fixed: dict | None = None):
    """(largest |residual| / tol, coefficients) of diff fitted by the named terms, in the
    tolerance's weights; fixed: {name: coefficient} held, the others fitted."""
    fixed = fixed or {}
    rest = diff - sum(c * basis[n] for n, c in fixed.items())
    free = [n for n in names if n not in fixed]
    coef = dict(fixed)
    if free:
        A = np.column_stack([basis[n] for n in free])
        found = np.linalg.lstsq(A / tol[:, None], rest / tol, rcond=None)[0]
        rest = rest - A @ found
        coef.update({n: float(c) for n, c in zip(free, found)})
    return float(np.max(np.abs(rest) / tol)), coef


def _describe(name: str, c: float, whole: float | None) -> str:
    """A sentence for one fitted term; whole: -1 or +1 when that exact coefficient also fits."""
    what = CANDIDATES[name]
    if name == "offset":
        return f"{what}: {c:+.6g} J"
    if whole == -1.0:
        return f"{what} missing"
    if whole == 1.0:
        return f"{what} counted twice"
    return f"{what} off by a factor {1.0 + c:.6g}"


def energy_column_check(scene: Scene, states, energy_column) -> ColumnVerdict:
    """Compare a simulator's energy column (T,) J with the energy of its states (T, 6); when
    they differ, fit the difference with the fewest terms (at most MOST_TERMS) of CANDIDATES
    that leave every row within its rounding tolerance, and name them."""
    Z = np.atleast_2d(np.asarray(states, dtype=float))
    column = np.asarray(energy_column, dtype=float)
    terms = energy_terms(scene, body_of(scene), Z)
    diff = column - sum(terms.values())
    tol = row_tolerance(scene, Z, column, terms)
    diff_max, tol_max = float(np.max(np.abs(diff))), float(np.max(tol))
    if np.all(np.abs(diff) <= tol):
        return ColumnVerdict(True, diff_max, tol_max, text=f"the energy column is the energy of the states "
                                                           f"(largest difference {diff_max:.3g} J, within rounding)")
    basis = {name: terms[name] for name in ("translation", "rotation", "gravity", "contact")
             if np.any(terms[name] != 0.0)}
    basis["offset"] = np.ones_like(diff)
    for size in range(1, MOST_TERMS + 1):
        found = []
        for names in combinations(basis, size):
            excess, coef = _fit(basis, names, diff, tol)
            if excess <= 1.0:
                whole = {n: next((w for w in (-1.0, 1.0) if _fit(basis, names, diff, tol, {n: w})[0] <= 1.0), None)
                         for n in names if n != "offset"}
                rank = 2 if any(w is None for w in whole.values()) else int("offset" in names)
                found.append((rank, excess, tuple(_describe(n, coef[n], whole.get(n)) for n in names), coef))
        if found:
            found.sort(key=lambda f: (f[0], f[1]))
            _, _, said, coef = found[0]
            others = tuple("; ".join(f[2]) for f in found[1:])
            text = (f"the energy column differs from the energy of the states by up to {diff_max:.3g} J: "
                    + "; ".join(said))
            if others:
                text += " (this run cannot tell it from: " + " | ".join(others) + ")"
            return ColumnVerdict(False, diff_max, tol_max, said, coef, text, others)
    return ColumnVerdict(False, diff_max, tol_max,
                         text=f"the energy column differs from the energy of the states by up to {diff_max:.3g} J, "
                              f"and no combination of at most {MOST_TERMS} of its terms explains it")
