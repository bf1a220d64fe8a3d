"""The fit: mujoco.minimize.least_squares over the twin's contact settings, several scenes at once.

Decision variable z = ln(p / p0), one entry per fitted parameter (parameters.py), p0 the base
mapping's value (gain 1, or the base's solimp / impratio), with box bounds ln(lower / p0) ..
ln(upper / p0). The residual stacks, for every scene, the COM's x, y and the angle times the
radius of gyration at up to targets.MAX_SAMPLES times, over the scene's duration (targets.py),
each scene divided by its own error at the start (its RMS residual under the base mapping):
the objective is 0.5 sum over scenes of (RMS error / RMS error at the start)^2, so a scene the
mapping already follows to 1e-5 m weighs as much as one it misses by 0.1 m, and the fit cannot
buy a share of the large error with a hundredfold of the small one.

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
from .targets import Batch, Target, residual_of

# Finite-difference step in z (a relative change of the parameter). minimize's default
# sqrt(eps) = 1.5e-8 moves a contact onset by far less than one step, so the difference
# quotient would see only the jitter of the discrete onset; 1e-3 (0.1 %) still resolves a
# gain to three digits.
FD_STEP = 1e-3
MAX_ITERATIONS = 30
# A fitted z within this of a bound (0.1 % relative) sits on the bound.
AT_BOUND = 1e-3
CONVERGED = ("norm(dx) < tol.", "norm(gradient) < tol.")
# A scene's weight is 1 / its RMS error at the start, floored here: two codes that agree do so
# only to round-off over a run (1e-16 per step, 1e5 steps, 1 m: 1e-11 m; the contact check's
# floor is a hundred times that), so a start closer than this is as good as exact.
SCALE_FLOOR = 1e-9   # m


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
    objective: list[float]          # 0.5 |r|^2 at each iterate (the last: at the result), r
                                    # each scene's residual / its scale (dimensionless)
    at_bound: list[str]             # names of parameters stuck on a bound, with which bound
    wall_time: float                # s
    mujoco_steps: int               # every step of every rollout of the fit
    residual_evaluations: int
    log: str = ""
    extra: dict = field(default_factory=dict)
    scales: dict = field(default_factory=dict)   # scene -> its RMS error at the start (m), its weight's inverse

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
        scales = start_scales(targets, params, p0 * np.exp(z0), batch)
        calls[0] += 1                               # the start, one candidate on every scene
        residual = make_residual(targets, params, p0, batch, calls, scales)
        begin = time.perf_counter()
        text = io.StringIO()
        z, trace = minimize.least_squares(z0, residual, bounds=(lower, upper), eps=FD_STEP,
                                          max_iter=max_iter, verbose=minimize.Verbosity.FINAL,
                                          output=text)
        wall = time.perf_counter() - begin
        steps = batch.steps
    log = text.getvalue()
    status, _ = _status(log)
    iterations = len(trace) - 1   # one log per iteration, then one at the result
    at_bound = [f"{p.name} (lower bound {p.lower:g})" if zi - lo < AT_BOUND else
                f"{p.name} (upper bound {p.upper:g})"
                for p, zi, lo, hi in zip(params, z, lower, upper) if zi - lo < AT_BOUND or hi - zi < AT_BOUND]
    return FitResult(tuple(params), p0, p0 * np.exp(z), status, status in CONVERGED,
                     iterations, [float(t.objective) for t in trace], at_bound, wall,
                     steps, calls[0], log,
                     scales={t.name: float(v) for t, v in zip(targets, scales)})


def start_scales(targets: list[Target], params, values: np.ndarray, batch: Batch) -> np.ndarray:
    """Each scene's RMS residual (m) at the start values, at least SCALE_FLOOR."""
    out = []
    for target in targets:
        r = residual_of(target, batch.paths(target, [calibrated(target.base, params, values)]))
        out.append(max(SCALE_FLOOR, float(np.linalg.norm(r))))
    return np.array(out)


def make_residual(targets: list[Target], params, p0: np.ndarray, batch: Batch, calls: list,
                  scales=None):
    """minimize's residual: z (n, k) -> (m, k), the k candidates of each scene in one rollout;
    each scene's part divided by its scale (start_scales; default 1 m)."""
    scales = np.ones(len(targets)) if scales is None else np.asarray(scales, float)

    def residual(z: np.ndarray) -> np.ndarray:
        z = np.atleast_2d(z.T).T                    # (n, k): one column per candidate
        values = p0[:, None] * np.exp(z)
        parts = []
        for target, scale in zip(targets, scales):
            settings = [calibrated(target.base, params, values[:, j]) for j in range(z.shape[1])]
            parts.append(residual_of(target, batch.paths(target, settings)) / scale)
        calls[0] += z.shape[1]
        return np.concatenate(parts, axis=1).T      # (m, k)
    return residual


def jacobian_cost(targets: list[Target], params, nthread: int = 2) -> dict:
    """One finite-difference Jacobian's residual columns, timed two ways in one run: batched
    (one rollout call per scene, k models over the threads) and one column per call (a
    Python loop over the parameters). Same numbers both ways (checked), seconds each."""
    p0 = start_values(params, targets)
    z = FD_STEP * np.eye(len(params))
    with Batch(nthread) as batch:
        residual = make_residual(targets, params, p0, batch, [0])
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

