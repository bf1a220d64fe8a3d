"""The reverse fit: custom_sim's k (N/m), c (N s/m), mu and alpha (s/m) that reproduce a
MuJoCo trajectory of the scene: what a MuJoCo contact setting means as a spring-damper.

Same optimiser as fit.py (mujoco.minimize.least_squares in z = ln(gain), gains on each scene's
own k, c, mu, alpha, bounds GAIN_BOUNDS), but the candidates are custom_sim runs: numba-compiled
and a few milliseconds each, so a residual call runs its columns one after the other.
The target is the twin's run under a mapping (default: the scene's [mujoco] solref).
"""
from __future__ import annotations

import dataclasses
import io
import time

import numpy as np
from mujoco import minimize

from custom_sim import Scene, SimulationDiverged, simulate

from .fit import AT_BOUND, CONVERGED, FD_STEP, FitResult, _status
from .parameters import GAIN_BOUNDS
from .targets import DIVERGED_DISTANCE, MAX_SAMPLES

# The reverse fit's runs are custom_sim's (milliseconds each): it keeps its 30 iterations
# (the forward fit's default fell to 12, fit.MAX_ITERATIONS).
MAX_ITERATIONS = 30

REVERSE_PARAMETERS = ("k", "c", "mu", "alpha")
UNITS = {"k": "N/m", "c": "N s/m", "mu": "", "alpha": "s/m"}


@dataclasses.dataclass
class ReverseTarget:
    """A scene and the MuJoCo path (steps + 1, 3: x, y, theta) custom_sim must follow."""

    scene: Scene
    reference: np.ndarray
    samples: np.ndarray
    length: float
    mapping: str


def prepare_reverse(scene: Scene, mapping: str | None = None) -> ReverseTarget:
    from custom_sim import mass_properties
    from mujoco_models import simulate_mujoco

    mapping = mapping or scene.mujoco.solref
    tr = simulate_mujoco(scene, mapping, dt=scene.dt)   # on custom_sim's step grid
    props = mass_properties(scene.body)
    length = float(np.sqrt(props.inertia / props.mass)) if props.rotates else 0.0
    n = len(tr.t) - 1
    samples = np.unique(np.linspace(1, n, min(MAX_SAMPLES, n)).round().astype(int))
    return ReverseTarget(scene, np.column_stack([tr.x, tr.y, tr.theta]), samples, length, mapping)


def with_gains(scene: Scene, gains) -> Scene:
    """The scene with k, c, mu, alpha multiplied by gains (in REVERSE_PARAMETERS order)."""
    ct = scene.contact
    return dataclasses.replace(scene, contact=dataclasses.replace(
        ct, k=ct.k * gains[0], c=ct.c * gains[1], mu=ct.mu * gains[2], alpha=ct.alpha * gains[3]))


def custom_path(scene: Scene) -> np.ndarray | None:
    """custom_sim's (steps + 1, 3) x, y, theta, or None if it diverged."""
    try:
        tr = simulate(scene)
    except SimulationDiverged:
        return None
    return np.column_stack([tr.x, tr.y, tr.theta])


def _residual_one(target: ReverseTarget, path) -> np.ndarray:
    s = target.samples
    if path is None:
        return np.full(3 * len(s), DIVERGED_DISTANCE / np.sqrt(len(s)))
    d = path[s] - target.reference[s]
    d[:, 2] *= target.length
    return d.reshape(-1) / np.sqrt(len(s))


def reverse_fit(targets: list[ReverseTarget], max_iter: int = MAX_ITERATIONS) -> FitResult:
    """Gains on k, c, mu, alpha that make custom_sim follow every target."""
    n = len(REVERSE_PARAMETERS)
    lower, upper = np.full(n, np.log(GAIN_BOUNDS[0])), np.full(n, np.log(GAIN_BOUNDS[1]))
    counts = {"steps": 0, "runs": 0}

    def residual(z: np.ndarray) -> np.ndarray:
        z = np.atleast_2d(z.T).T
        cols = []
        for j in range(z.shape[1]):
            gains = np.exp(z[:, j])
            parts = []
            for t in targets:
                parts.append(_residual_one(t, custom_path(with_gains(t.scene, gains))))
                counts["steps"] += t.scene.steps
                counts["runs"] += 1
            cols.append(np.concatenate(parts))
        return np.column_stack(cols)

    text = io.StringIO()
    begin = time.perf_counter()
    z, trace = minimize.least_squares(np.zeros(n), residual, bounds=(lower, upper), eps=FD_STEP,
                                      max_iter=max_iter, verbose=minimize.Verbosity.FINAL, output=text)
    wall = time.perf_counter() - begin
    status, _ = _status(text.getvalue())
    iterations = len(trace) - 1
    at_bound = [f"{name} ({'lower' if zi - lower[i] < AT_BOUND else 'upper'} bound)"
                for i, (name, zi) in enumerate(zip(REVERSE_PARAMETERS, z))
                if zi - lower[i] < AT_BOUND or upper[i] - zi < AT_BOUND]
    result = FitResult(REVERSE_PARAMETERS, np.ones(n), np.exp(z), status, status in CONVERGED,
                       iterations, [float(t.objective) for t in trace], at_bound, wall, 0,
                       counts["runs"], text.getvalue())
    result.extra["custom_steps"] = counts["steps"]
    return result


def reverse_errors(target: ReverseTarget, gains) -> dict:
    """position and angle error max of custom_sim (with gains) against the MuJoCo path."""
    path = custom_path(with_gains(target.scene, gains))
    if path is None:
        return {"position_error_max": None, "angle_error_max": None, "diverged": True}
    d = path - target.reference
    return {"position_error_max": float(np.hypot(d[:, 0], d[:, 1]).max()),
            "angle_error_max": float(np.abs(d[:, 2]).max()), "diverged": False}
