"""Fitting each family to forces read off the steps at a known state (the three Euler steps)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .families import Family
from .fit import PARAMETER_FLOOR, SHARPNESS_GRID, Fit, linear_solve, polish, resolution, rounded, worst


@dataclass
class Rows:
    """One equation per row: inputs per point (n, p), the target (n,), and its bound (n,)."""

    target: np.ndarray
    bound: np.ndarray
    touching: np.ndarray
    a: np.ndarray          # first input per point: depth d, or the load Fn
    b: np.ndarray          # second: normal velocity v_n, slip v or spin omega


def model_of(fam: Family, rows: Rows, p) -> np.ndarray:
    f = fam.force(np.where(rows.touching, rows.a, 0.0), rows.b, tuple(p))
    return np.where(rows.touching, f, 0.0).sum(axis=1)


def _start_normal(fam: Family, rows: Rows) -> np.ndarray:
    w = 1.0 / rows.bound
    d = np.where(rows.touching, rows.a, 0.0)
    vn = np.where(rows.touching, rows.b, 0.0)
    if fam.name == "compression":
        return linear_solve(np.column_stack([d.sum(1), np.maximum(0.0, -vn).sum(1)]), rows.target, w)
    # the clamped laws: rows where the force is on (open clamp) are linear in (k, c) or (k, k D)
    on = rows.target > rows.bound if fam.name != "unclamped" else np.ones(len(rows.target), dtype=bool)
    if fam.name == "hunt_crossley":
        k, kd = linear_solve(np.column_stack([d.sum(1), -(d * vn).sum(1)])[on], rows.target[on], w[on])
        return np.array([k, kd / k if k else 0.0])
    return linear_solve(np.column_stack([d.sum(1), -vn.sum(1)])[on], rows.target[on], w[on])


def _start_sharp(fam: Family, rows: Rows) -> np.ndarray:
    """(coefficient, sharpness) of a law -coef Fn phi(sharpness v): the coefficient solved
    linearly at each sharpness of the grid, the best pair kept."""
    w = 1.0 / rows.bound
    best, start = np.inf, np.array([0.0, SHARPNESS_GRID[0]])
    for s in SHARPNESS_GRID:
        unit = model_of(fam, rows, (1.0, s))
        (coef,) = linear_solve(unit[:, None], rows.target, w)
        cost = np.sum((w * (rows.target - coef * unit)) ** 2)
        if cost < best:
            best, start = cost, np.array([coef, s])
    return start


def fit_family(fam: Family, rows: Rows, bound_of=None) -> Fit:
    """The family fitted to the rows; bound_of(fam, params) -> (n,) the round-off bound with the
    fitted law's own terms (the larger of it and rows.bound is used)."""
    if fam.effect == "normal":
        x0 = _start_normal(fam, rows)
    elif len(fam.params) == 2:
        x0 = _start_sharp(fam, rows)
    elif len(fam.params) == 1:
        x0 = linear_solve(model_of(fam, rows, (1.0,))[:, None], rows.target, 1.0 / rows.bound)
    else:
        x0 = np.zeros(0)

    def fun(x):
        return (rows.target - model_of(fam, rows, x)) / rows.bound
    x = polish(fun, x0, np.full(len(fam.params), PARAMETER_FLOOR))
    bound = rows.bound if bound_of is None else np.maximum(rows.bound, bound_of(fam, tuple(x)))
    residual, relative = worst(rows.target - model_of(fam, rows, x), bound)
    res = resolution(lambda p: model_of(fam, rows, p), x, bound)
    shown = rounded(x, res, lambda p: worst(rows.target - model_of(fam, rows, p), bound)[1], relative)
    return Fit(fam, tuple(float(v) for v in x), residual, relative, {"shown": shown})


def fit_effect(families, rows: Rows, bound_of=None) -> list[Fit]:
    return [fit_family(f, rows, bound_of) for f in families]


@dataclass
class TorqueRows:
    """I alpha = sum_p (r_x Fn - r_y Ft) + roll: per row alpha (rad/s^2), per point r_x, r_y (m),
    Fn, Ft (N), omega (rad/s), touching; the bound (N m); free_arm: r_x = l_x is fitted too (a
    point that does not turn: the circle's)."""

    alpha: np.ndarray
    rx: np.ndarray
    ry: np.ndarray
    fn: np.ndarray
    ft: np.ndarray
    om: np.ndarray
    touching: np.ndarray
    bound: np.ndarray
    free_arm: bool


def torque_model(rows: TorqueRows, fam: Family | None, p, lx) -> np.ndarray:
    rx = np.full_like(rows.rx, lx) if rows.free_arm else rows.rx
    tau = np.where(rows.touching, rx * rows.fn - rows.ry * rows.ft, 0.0)
    if fam is not None and fam.params:
        tau = tau + np.where(rows.touching, fam.force(rows.fn, rows.om[:, None], tuple(p)), 0.0)
    return tau.sum(axis=1)


def fit_torque(rows: TorqueRows, fam: Family | None, inertia0: float) -> tuple[np.ndarray, float, float, tuple]:
    """(residual per row N m, inertia, l_x or nan, rolling parameters): I, the rolling family's
    parameters (fam None: no rolling) and, for a point that does not turn, its l_x."""
    n_roll = len(fam.params) if fam is not None else 0
    n_arm = 1 if rows.free_arm else 0

    def unpack(x):
        return x[0], (x[1] if n_arm else 0.0), tuple(x[1 + n_arm:])

    def fun(x):
        inertia, lx, p = unpack(x)
        return (inertia * rows.alpha - torque_model(rows, fam, p, lx)) / rows.bound

    w = 1.0 / rows.bound
    starts = []
    sharp_grid = SHARPNESS_GRID if n_roll == 2 else [None]
    for s in sharp_grid:
        # linear in (I, l_x, mu_roll) once the sharpness is fixed
        cols = [rows.alpha]
        if n_arm:
            cols.append(-np.where(rows.touching, rows.fn, 0.0).sum(axis=1))
        if n_roll:
            unit = np.where(rows.touching, fam.force(rows.fn, rows.om[:, None], (1.0,) if s is None else (1.0, s)),
                            0.0).sum(axis=1)
            cols.append(-unit)
        rhs = torque_model(rows, None, (), 0.0) if not n_arm else np.where(
            rows.touching, -rows.ry * rows.ft, 0.0).sum(axis=1)
        x = linear_solve(np.column_stack(cols), rhs, w)
        if s is not None:
            x = np.append(x, s)
        starts.append((np.sum(fun(x) ** 2), x))
    x0 = min(starts, key=lambda t: t[0])[1] if starts else np.array([inertia0])
    if not np.all(np.isfinite(x0)):
        x0 = np.array([inertia0] + [0.0] * (n_arm + n_roll))
    # the inertia and the arm free (a flipped torque shows as a negative inertia), the rolling law's floor
    x = polish(fun, x0, np.array([-np.inf] * (1 + n_arm) + [PARAMETER_FLOOR] * n_roll))
    inertia, lx, p = unpack(x)
    resid = inertia * rows.alpha - torque_model(rows, fam, p, lx)
    return resid, float(inertia), float(lx) if n_arm else float("nan"), tuple(float(v) for v in p)
