"""The fit: mujoco.minimize.least_squares over the twin's contact settings, several scenes at once.

Decision variable z = ln(p / p0), one entry per fitted parameter (parameters.py), p0 the base
mapping's value (gain 1, or the base's solimp / impratio), with box bounds ln(lower / p0) ..
ln(upper / p0).

Objective: the largest error of each fitted scene relative to that scene's largest error under
the base mapping (the figures calibration.py's guard compares), minimised over the scenes: a
minimax, approximated by a high p-norm. At every step i of scene s the position difference
over P_s and, for a body that turns, the angle difference over A_s (P_s, A_s: the base
mapping's largest differences) give ratios e_si; the objective is
    (sum_s mean_i e_si^p)^(1/p)        (p = P_NORM)
(mean_i e_si^p)^(1/p) tends to scene s's largest ratio as p grows, and the sum over scenes to
the largest of those: the optimiser cannot buy the mean with a peak, as plain least squares did
(it lowered box_slide's RMS and raised its largest error).

It is solved as iteratively reweighted least squares (Lawson's idea) inside minimize's
Levenberg-Marquardt: the residual is the signed differences (x, y over P_s; angle over A_s),
and the norm (PNorm) gives the p-norm's exact gradient with the Gauss-Newton matrix of a least
squares weighted by e^(p-2), frozen at the current point. That step is the weighted least-squares
step of Lawson's scheme, so a target the twin can reach exactly is still reached in a few
steps (Newton on e^p itself only shrinks e by 1/(p-1) a step); where the step overshoots, the
regulariser shortens it. Why this and not Lawson's outer loop or a hard max: it is one solve,
so the batched finite differences serve unchanged, and unlike a hard max it still rewards
lowering a scene that is not the worst (a tie does not stop the fit). What p leaves over: with
S scenes the p-norm lets one scene's worst ratio rise by up to S^(1/p) (4.4 % for two at
p = 16) where another falls to nothing, so the fit then steps back along its way from the
start to the point whose largest ratio over the scenes is smallest (`step_back`), the start
included: the result is never worse than the start on the grid of every step.

mujoco.minimize evaluates the residual on a matrix of candidates, one column each: the
finite-difference Jacobian asks for n columns at once. Each call here turns the columns into
k copies of each scene's compiled twin and rolls them out in one mujoco.rollout call.
"""
from __future__ import annotations

import io
import os
import re
import time
from dataclasses import dataclass, field

import numpy as np
from mujoco import minimize

from .settings import calibrated
from .targets import Batch, Target, errors

# Finite-difference step in z (a relative change of the parameter). minimize's default
# sqrt(eps) = 1.5e-8 moves a contact onset by far less than one step, so the difference
# quotient would see only the jitter of the discrete onset; 1e-3 (0.1 %) still resolves a
# gain to three digits.
FD_STEP = 1e-3
# Iterations by default. On box_slide and point_drop the objective falls from 0.78 to 0.53 in 5
# iterations and to 0.52 by the 12th (docs/calibration.md); each iteration costs n + 1 rollouts
# or more of every fitted scene.
MAX_ITERATIONS = 12
# Levenberg-Marquardt's regulariser grows by this factor after a rejected trial step (minimize's
# default 10^0.1). Each trial is one rollout of every scene, and on a contact's rough objective
# most rejections need the regulariser orders of magnitude up: with the default, 150 of the 168
# rollouts of `calibrate box_slide point_drop` were rejected trials; with 10, about 25 of 79.
MU_FACTOR = 10.0
# Marquardt's scaling: each z measured in units of its Jacobian column's norm, refreshed every
# iteration, so the regulariser acts alike on every parameter. box_slide's largest error moves
# thirtyfold for 0.1 % in mu and a few percent for 10 % in the damping: with one absolute
# regulariser for both, the stiff direction held it at 1e7 and froze the others (dx 1e-6 a step;
# the objective 0.779 to 0.764 in 12 iterations, against 0.518 scaled).
X_SCALE = "jac"
# A fitted z within this of a bound (0.1 % relative) sits on the bound.
AT_BOUND = 1e-3
CONVERGED = ("norm(dx) < tol.", "norm(gradient) < tol.")
# The exponent of the p-norm that stands for the largest ratio (module docstring). Summed over
# S scenes it overstates the largest by at most S^(1/p) (4.4 % for two at p = 16); the mean over
# n steps understates it by at most n^(-1/p), less for a smooth error whose peak spans many steps
# (box_slide starts at 0.78). A larger p puts the weight e^(p-2) on fewer steps, and the weighted
# Gauss-Newton model of the step grows poorer.
P_NORM = 16
# The ratio a diverged step scores (its position is NaN): far above any real ratio, so the
# optimiser backs off; 100^p = 1e32 stays finite.
DIVERGED_RATIO = 100.0
# A scene's scale is its largest difference under the base mapping, floored here: two codes that
# agree do so only to round-off over a run (1e-16 per step, 1e5 steps, 1 m: 1e-11 m; the contact
# check's floor is a hundred times that), so a start closer than this is as good as exact. The
# same floor in rad for the angle (a radius of gyration of order 1 m turns one into the other).
SCALE_FLOOR = 1e-9   # m, rad
# Points tried between the start (0) and the optimiser's result (1) by step_back.
STEP_BACK = (1.0, 0.875, 0.75, 0.625, 0.5, 0.375, 0.25, 0.125)


@dataclass
class FitResult:
    """What the optimiser did: values (gains or values, one per parameter), status in the
    optimiser's words, the objective per iteration, and the cost."""

    params: tuple
    start: np.ndarray
    values: np.ndarray
    status: str
    converged: bool
    iterations: int
    objective: list[float]          # at each iterate (the last: at the optimiser's result):
                                    # (sum_s mean_i (difference / the start's largest)^p)^(1/p),
                                    # about the largest ratio over the scenes (PNorm)
    at_bound: list[str]             # names of parameters stuck on a bound, with which bound
    wall_time: float                # s
    mujoco_steps: int               # every step of every rollout of the fit
    residual_evaluations: int
    log: str = ""
    extra: dict = field(default_factory=dict)
    scales: dict = field(default_factory=dict)   # scene -> {"position": m, "angle": rad}: the
                                                 # start's largest differences, the ratios' units
    # scene -> the start's errors (targets.errors) and path, measured once for the scales and
    # reused by calibration.py (the base mapping's run does not change during a fit)
    start_errors: dict = field(default_factory=dict)
    start_paths: dict = field(default_factory=dict)
    ratios: dict = field(default_factory=dict)   # scene -> largest ratio at the values returned
    step_back: float = 1.0          # fraction of the optimiser's step kept (step_back)
    optimiser_values: np.ndarray | None = None   # where the optimiser itself ended (before step_back)

    @property
    def parameters(self) -> dict[str, float]:
        return {getattr(p, "name", p): float(v) for p, v in zip(self.params, self.values)}


def start_values(params, targets: list[Target]) -> np.ndarray:
    """p0: 1 for a gain, the first scene's base value for a shared value."""
    base = targets[0].base.settings
    return np.array([1.0 if p.kind == "gain" else base.field(p.field)[p.index[0]] for p in params])


def fit(targets: list[Target], params, max_iter: int = MAX_ITERATIONS, nthread: int = 2,
        start: np.ndarray | None = None) -> FitResult:
    """Fit the parameters to every target at once; the optimiser is deterministic, so the same
    inputs give the same numbers (tests/test_calibration.py runs it twice)."""
    p0 = start_values(params, targets) if start is None else np.asarray(start, float)
    lower = np.log(np.array([p.lower for p in params]) / p0)
    upper = np.log(np.array([p.upper for p in params]) / p0)
    z0 = np.clip(np.zeros(len(params)), lower, upper)
    calls = [0]

    with Batch(nthread) as batch:
        paths0 = {t.name: batch.paths(t, [calibrated(t.base, params, p0 * np.exp(z0))])[0] for t in targets}
        calls[0] += 1                               # the start, one candidate on every scene
        errors0 = {t.name: errors(t, paths0[t.name]) for t in targets}
        scales = [start_scale(t, errors0[t.name]) for t in targets]
        r0 = np.concatenate([signed_ratios(t, paths0[t.name][None], sc)[0] for t, sc in zip(targets, scales)])
        residual = make_residual(targets, params, p0, batch, calls, scales, start=(z0, r0))
        worst = make_worst(targets, params, p0, batch, calls, scales)
        begin = time.perf_counter()
        z, trace, log, kept, ratios = minimax(residual, worst, PNorm.of(targets, scales), z0, lower, upper,
                                              max_iter, len(targets))
        z_end = np.ravel(trace[-1].candidate)     # the optimiser's own end point (the trace's last log)
        wall = time.perf_counter() - begin
        steps = batch.steps
    status, _ = _status(log)
    iterations = len(trace) - 1   # one log per iteration, then one at the result
    at_bound = [f"{p.name} (lower bound {p.lower:g})" if zi - lo < AT_BOUND else
                f"{p.name} (upper bound {p.upper:g})"
                for p, zi, lo, hi in zip(params, z, lower, upper) if zi - lo < AT_BOUND or hi - zi < AT_BOUND]
    return FitResult(tuple(params), p0, p0 * np.exp(z), status, status in CONVERGED,
                     iterations, [float(t.objective) for t in trace], at_bound, wall,
                     steps, calls[0], log,
                     scales={t.name: {"position": sc[0], "angle": sc[1]} for t, sc in zip(targets, scales)},
                     start_errors=errors0, start_paths=paths0,
                     ratios={t.name: float(r) for t, r in zip(targets, ratios)}, step_back=float(kept),
                     optimiser_values=p0 * np.exp(z_end))


def start_scale(target: Target, start: dict) -> tuple[float, float | None]:
    """The units of a scene's ratios: its largest position difference (m) and, for a body that
    turns, its largest angle difference (rad) under the start values, at least SCALE_FLOOR;
    None for the angle of a body that does not turn."""
    if start["diverged"]:
        return 1.0, (1.0 if target.rotates else None)
    angle = max(SCALE_FLOOR, start["angle_error_max"]) if target.rotates else None
    return max(SCALE_FLOOR, start["position_error_max"]), angle


def ratios_of(target: Target, paths: np.ndarray, scale) -> np.ndarray:
    """(k, m): each step's position difference over the scene's position scale and, for a body
    that turns, each step's angle difference over its angle scale; DIVERGED_RATIO where the run
    is not finite."""
    d = paths[:, 1:, :] - target.reference[None, 1:, :]
    parts = [np.hypot(d[..., 0], d[..., 1]) / scale[0]]
    if scale[1] is not None:
        parts.append(np.abs(d[..., 2]) / scale[1])
    e = np.concatenate(parts, axis=1)
    return np.where(np.isfinite(e), np.minimum(e, DIVERGED_RATIO), DIVERGED_RATIO)


def signed_ratios(target: Target, paths: np.ndarray, scale) -> np.ndarray:
    """(k, m): each step's x and y difference over the scene's position scale, then, for a body
    that turns, its angle difference over the angle scale; DIVERGED_RATIO where not finite."""
    d = paths[:, 1:, :] - target.reference[None, 1:, :]
    parts = [d[..., 0] / scale[0], d[..., 1] / scale[0]]
    if scale[1] is not None:
        parts.append(d[..., 2] / scale[1])
    e = np.concatenate(parts, axis=1)
    return np.where(np.isfinite(e), np.clip(e, -DIVERGED_RATIO, DIVERGED_RATIO), DIVERGED_RATIO)


def make_residual(targets: list[Target], params, p0: np.ndarray, batch: Batch, calls: list, scales,
                  start=None):
    """minimize's residual: z (n, k) -> (m, k), the k candidates of each scene in one rollout;
    each scene's signed ratios (signed_ratios), scenes one after the other. start: (z0, its
    residual), already run, returned without a rollout when asked for z0 alone."""

    def residual(z: np.ndarray) -> np.ndarray:
        z = np.atleast_2d(z.T).T                    # (n, k): one column per candidate
        if start is not None and z.shape[1] == 1 and np.array_equal(z[:, 0], start[0]):
            return start[1][:, None].copy()
        values = p0[:, None] * np.exp(z)
        parts = []
        for target, scale in zip(targets, scales):
            settings = [calibrated(target.base, params, values[:, j]) for j in range(z.shape[1])]
            parts.append(signed_ratios(target, batch.paths(target, settings), scale))
        calls[0] += z.shape[1]
        return np.concatenate(parts, axis=1).T      # (m, k)
    return residual


class PNorm(minimize.Norm):
    """(sum over groups g of w_g |r_g|^p)^(1/p), r_g a step's (x, y) ratios or its angle ratio,
    w_g 1 / (its scene's number of groups): about the largest ratio (module docstring).

    The p-th root makes the value, its gradient and the Hessian below scale-free: minimize's
    regulariser is absolute, and F = sum w |r|^p itself shrinks as e^p (1e-21 at e = 0.05), which
    left the regulariser dominant and ended a fit far from a target it could reach. The Hessian
    is Lawson's: the Gauss-Newton matrix of the least squares weighted by w |r_g|^(p-2), frozen at
    the current point (the p-norm's exact gradient, with the same factor)."""

    def __init__(self, group: np.ndarray, weight: np.ndarray, p: float = P_NORM):
        self.group, self.weight, self.p = group, weight, p    # group: (m,) row -> group; weight per group

    @classmethod
    def of(cls, targets: list[Target], scales) -> PNorm:
        """The norm for the residual rows make_residual stacks."""
        groups, weights, first = [], [], 0
        for target, scale in zip(targets, scales):
            n = target.steps
            own = [np.arange(n), np.arange(n)] + ([np.arange(n, 2 * n)] if scale[1] is not None else [])
            count = n * (2 if scale[1] is not None else 1)
            groups += [first + g for g in own]
            weights.append(np.full(count, 1.0 / count))
            first += count
        return cls(np.concatenate(groups), np.concatenate(weights))

    def _terms(self, r: np.ndarray):
        square = np.bincount(self.group, weights=r.ravel() ** 2, minlength=len(self.weight))
        return square, float(np.sum(self.weight * square ** (self.p / 2)))

    def value(self, r: np.ndarray):
        return self._terms(r)[1] ** (1.0 / self.p)

    def grad_hess(self, r: np.ndarray, proj: np.ndarray):
        square, total = self._terms(r)
        if total == 0.0:
            return np.zeros((proj.shape[1], 1)), proj.T @ proj
        # d/dr of total^(1/p) = total^(1/p - 1) w |r_g|^(p-2) r, row by row
        w = (total ** (1.0 / self.p - 1.0) * self.weight * square ** (self.p / 2 - 1))[self.group][:, None]
        return proj.T @ (w * r), proj.T @ (w * proj)


def make_worst(targets: list[Target], params, p0: np.ndarray, batch: Batch, calls: list, scales):
    """z (n, k) -> (k, scenes): each candidate's largest ratio on each scene (ratios_of), the
    k candidates of a scene in one rollout."""

    def worst(z: np.ndarray) -> np.ndarray:
        values = p0[:, None] * np.exp(z)
        out = np.empty((z.shape[1], len(targets)))
        for j, (target, scale) in enumerate(zip(targets, scales)):
            settings = [calibrated(target.base, params, values[:, i]) for i in range(z.shape[1])]
            out[:, j] = ratios_of(target, batch.paths(target, settings), scale).max(axis=1)
        calls[0] += z.shape[1]
        return out
    return worst


def minimax(residual, worst, norm, z0: np.ndarray, lower: np.ndarray, upper: np.ndarray, max_iter: int,
            scenes: int):
    """minimize.least_squares of norm(residual(z)) from z0 within the bounds, then step_back.
    residual: z (n, k) -> (m, k); worst: z (n, k) -> (k, scenes), each scene's largest ratio (1 at
    z0). Returns z, the optimiser's trace and log, the fraction of its step kept, and the largest
    ratios there."""
    text = io.StringIO()
    z, trace = minimize.least_squares(z0, residual, bounds=(lower, upper), eps=FD_STEP, norm=norm,
                                      max_iter=max_iter, mu_factor=MU_FACTOR, x_scale=X_SCALE,
                                      verbose=minimize.Verbosity.ITER, output=text)
    kept, ratios = step_back(worst, z0, z, scenes)
    return z0 + kept * (z - z0), trace, text.getvalue(), kept, ratios


def step_back(worst, z0: np.ndarray, z: np.ndarray, scenes: int):
    """The fraction t of the step z0 -> z (STEP_BACK, or 0: the start) whose largest ratio over
    the scenes is smallest, ties broken by the next largest (the p-norm can trade a few percent
    of one scene's worst for another's, module docstring), and each scene's largest ratio there.
    Every t in one call of worst (one rollout call per scene)."""
    ts = [t for t in STEP_BACK if np.any(z != z0)]
    rows = np.ones((1, scenes))                     # the start: every ratio 1 by definition
    if ts:
        rows = np.vstack([rows, worst(np.column_stack([z0 + t * (z - z0) for t in ts]))])
    best = min(range(len(rows)), key=lambda i: (tuple(sorted(rows[i], reverse=True)), i))
    return (0.0 if best == 0 else ts[best - 1]), rows[best]


def jacobian_cost(targets: list[Target], params, nthread: int = 2) -> dict:
    """One finite-difference Jacobian's residual columns, timed two ways in one run: batched
    (one rollout call per scene, k models over the threads) and one column per call (a
    Python loop over the parameters). Same numbers both ways (checked), seconds each."""
    p0 = start_values(params, targets)
    z = FD_STEP * np.eye(len(params))
    with Batch(nthread) as batch:
        residual = make_residual(targets, params, p0, batch, [0],
                                 [(1.0, 1.0 if t.rotates else None) for t in targets])
        residual(z[:, :1])                            # warm up
        begin = time.perf_counter()
        batched = residual(z)
        t_batched = time.perf_counter() - begin
        begin = time.perf_counter()
        looped = np.column_stack([residual(z[:, j:j + 1]) for j in range(len(params))])
        t_looped = time.perf_counter() - begin
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return {"columns": len(params), "threads": batch.nthread, "cpus": os.cpu_count(),
            "load_average": load, "batched": t_batched,
            "one_by_one": t_looped, "same_numbers": bool(np.array_equal(batched, looped))}


def _status(log: str) -> tuple[str, int]:
    """The optimiser's own termination message ("maximum iterations reached.", ...) and its
    count of iterations, from what it prints (least_squares returns neither)."""
    match = re.search(r"Terminated after (\d+) iterations: (.*?) y:", log)
    if not match:
        return "unknown (no termination message)", -1
    return match.group(2).strip(), int(match.group(1))

