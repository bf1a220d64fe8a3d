"""Fitting one family: weighted least squares on the residual over its round-off bound, and the choice."""
from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from .families import FAMILIES, Family

# Every family's parameters are what a scene file accepts: k, c, dissipation, mu, alpha, mu_roll
# and roll_sharpness at least 0 (scene_types.schema). A fit outside that is no family: a spring
# alone (c = 0) stepped by semi-implicit Euler is exactly implicit Euler's with c = -k h.
PARAMETER_FLOOR = 0.0
# The least-squares stop: parameters and cost steady to a few ulps (a correct family's residual
# is round-off, so the fit must not stop before that).
LSQ_TOL = 1e-15
LSQ_MAX_EVALUATIONS = 400
# The nonlinear parameters (alpha s/m, roll_sharpness s/rad) tried before the polish: a
# logarithmic grid wide enough for a stiction band from 10 m/s down to 1 um/s.
SHARPNESS_GRID = np.geomspace(0.1, 1e6, 43)
# Several starting points of one family are each taken this far, and only the best polished to
# round-off (a family that fits nothing would spend LSQ_MAX_EVALUATIONS from every start).
SCOUT_EVALUATIONS = 30


@dataclass
class Fit:
    """A family fitted: its parameters, the largest residual (N or N m) and the largest ratio
    of residual to round-off bound (`relative`; the family reproduces the step when <= 1)."""

    family: Family
    params: tuple
    residual: float
    relative: float
    extra: dict = field(default_factory=dict)   # parameters fitted beside the family's (inertia, arm)

    @property
    def fits(self) -> bool:
        return bool(self.relative <= 1.0)

    @property
    def named(self) -> dict:
        return dict(zip(self.family.params, self.params))


def polish(fun, x0, lower=None, max_nfev: int = LSQ_MAX_EVALUATIONS) -> np.ndarray:
    """least_squares from x0 to round-off (or max_nfev evaluations), each parameter at least
    `lower` (None: free); x0 returned when it is already a better point."""
    x0 = np.asarray(x0, dtype=float)
    if x0.size == 0:
        return x0
    lower = np.full(x0.size, -np.inf) if lower is None else np.asarray(lower, dtype=float)
    x0 = np.maximum(x0, lower)
    r0 = fun(x0)
    if not np.all(np.isfinite(r0)):
        return x0
    from scipy.optimize import least_squares   # here: a passing run never fits a law

    try:
        with np.errstate(all="ignore"), warnings.catch_warnings():   # a family far off overflows on the way
            warnings.simplefilter("ignore", RuntimeWarning)
            sol = least_squares(fun, x0, method="trf", x_scale="jac", bounds=(lower, np.inf),
                                xtol=LSQ_TOL, ftol=LSQ_TOL, gtol=LSQ_TOL, max_nfev=max_nfev)
    except (ValueError, np.linalg.LinAlgError):
        return x0
    if not np.all(np.isfinite(sol.fun)):
        return x0
    return sol.x if np.sum(sol.fun ** 2) <= np.sum(r0 ** 2) else x0


def linear_solve(A: np.ndarray, b: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Weighted linear least squares: argmin |w (A x - b)|."""
    A = np.asarray(A, dtype=float)
    if A.shape[0] == 0:
        return np.zeros(A.shape[1])
    x, *_ = np.linalg.lstsq(A * w[:, None], b * w, rcond=None)
    return x


# A parameter's resolution is read from a change this small (relative to the parameter, or to 1
# where it is 0): small enough that the force is linear in it, far above its own rounding.
RESOLUTION_STEP = 1e-6


def resolution(model, x, bound: np.ndarray) -> tuple[float, ...]:
    """Per parameter of x, the change that moves model(x) (n,) by its round-off bound (n,) at
    some row: what the probes resolve of it (inf where no row depends on it)."""
    x = np.asarray(x, dtype=float)
    base = model(x)
    b = np.maximum(np.asarray(bound, dtype=float), np.finfo(float).tiny)
    out = []
    for j in range(x.size):
        step = RESOLUTION_STEP * max(abs(x[j]), 1.0)
        moved = x.copy()
        moved[j] += step
        slope = np.max(np.abs(model(moved) - base) / b) if base.size else 0.0
        out.append(float(step / slope) if slope > 0 and np.isfinite(slope) else float("inf"))
    return tuple(out)


def resolved(value: float, res: float | None, finer: int = 0) -> float:
    """value rounded to the decade of its resolution res (finer: that many decades below)."""
    if res is None or not np.isfinite(res) or res <= 0 or not np.isfinite(value):
        return value
    decimals = int(finer - np.floor(np.log10(res)))
    return float(round(float(value), decimals)) + 0.0   # decimal rounding: 0.1, not 0.09999999999999999


# Decades below a parameter's resolution tried before its fitted digits are kept whole.
ROUNDING_DECADES = 4


def rounded(x, res, relative_of, relative: float) -> tuple[float, ...]:
    """x rounded to the digits the probes carry (0.49999999999999906 is 0.5, a c of 2e-21
    N s/m is 0): the coarsest of the decades of each parameter's resolution (res) and the few
    below whose law still reproduces the rows as well (relative_of(x) <= 1 for a family that
    fits, no more than its fitted relative otherwise); x itself where none does."""
    x = tuple(float(v) for v in x)
    allowed = 1.0 if relative <= 1.0 else relative * (1.0 + 1e-9)
    for finer in range(ROUNDING_DECADES):
        cand = tuple(resolved(v, r, finer) for v, r in zip(x, res))
        if cand == x:
            return cand
        try:
            with np.errstate(all="ignore"):
                rel = relative_of(cand)
        except (ZeroDivisionError, FloatingPointError, ValueError):   # a sharpness rounded to 0
            continue
        if rel <= allowed:
            return cand
    return x


def worst(residual: np.ndarray, bound: np.ndarray) -> tuple[float, float]:
    """(largest |residual|, largest |residual| / bound); (0, 0) over no rows."""
    residual, bound = np.abs(np.ravel(residual)), np.ravel(bound)
    if residual.size == 0:
        return 0.0, 0.0
    if not np.all(np.isfinite(residual)):
        return float("inf"), float("inf")
    return float(residual.max()), float(np.max(residual / np.maximum(bound, np.finfo(float).tiny)))


def weights(bound: np.ndarray) -> np.ndarray:
    """Least-squares weights 1 / bound^2, scaled to at most 1 (a zero bound: weight 1)."""
    b = np.maximum(np.asarray(bound, dtype=float), np.finfo(float).tiny)
    return (b.min() / b) ** 2


def choose(fits: list[Fit], preferred: str | None) -> tuple[Fit | None, list[str], Fit]:
    """(the family named or None, the other families that reproduce the step equally, the
    closest family). Among several that reproduce it, the one with the fewest parameters is
    named (no friction rather than tanh with mu = 0; the sign law rather than a tanh too sharp
    for any probe to resolve), then the scene's own (every damping law at c = 0), then the
    first in the scene_types order."""
    good = [f for f in fits if f.fits]
    closest = min(fits, key=lambda f: f.relative)
    if not good:
        return None, [], closest
    fewest = min(len(f.family.params) for f in good)
    simplest = [f for f in good if len(f.family.params) == fewest]
    named = next((f for f in simplest if f.family.name == preferred), simplest[0])
    if not named.family.params:   # "none": the others fit only by vanishing (mu = 0), not as themselves
        return named, [], closest
    return named, [f.family.name for f in good if f is not named], closest


def families(effect: str) -> tuple[Family, ...]:
    return FAMILIES[effect]
