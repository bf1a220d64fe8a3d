"""What watching for chatter costs: ns per step with and without the tracker, in one run.

    python -m compare tools chatter-cost [SCENE ...]

Each scene (default: the built-ins) runs its full duration with its integrator and dt in the
compiled loop, recording nothing, twice per round: with the chatter tracker (custom_sim's
default: `integrate(..., watch)` with a row per contact point) and without it (a watch of 0
rows, which the loop skips). The rounds alternate the two, and each keeps its minimum CPU
time of the stepping thread, so load from other processes falls on neither side alone.
"""
from __future__ import annotations

import time

import numpy as np

from custom_sim import INTEGRATORS, mass_properties
from custom_sim.integrators import integrate
from custom_sim.model import build_model, initial_state
from custom_sim.runner import blowup_guard, new_watch

from ...scenarios import load_all
from ...table import stream

ROUNDS = 5


def cost(scene) -> tuple[float, float]:
    """(ns per step with the tracker, without it)."""
    props = mass_properties(scene.body)
    model, points = build_model(scene, props)
    z0 = initial_state(scene)
    guard = blowup_guard(scene, props, z0, applied_input=False)
    ext, none = np.zeros((1, 3)), np.empty((0, 6))
    code = INTEGRATORS[scene.integrator].code

    def run(watch) -> float:
        z, counters = z0.copy(), np.zeros(4, dtype=np.int64)
        start = time.thread_time()
        failed = integrate(model, points, z, scene.dt, scene.steps, code, ext, none, counters, guard, watch)
        spent = time.thread_time() - start
        assert failed < 0, f"{scene.name} stopped at step {failed}"
        return spent

    best = {"with": np.inf, "without": np.inf}
    for _ in range(ROUNDS + 1):  # the first round compiles (or loads the cache) and warms up
        best["with"] = min(best["with"], run(new_watch(props)))
        best["without"] = min(best["without"], run(np.empty((0, new_watch(props).shape[1]))))
    return best["with"] / scene.steps * 1e9, best["without"] / scene.steps * 1e9


def print_table(names: list[str]) -> int:
    """The costs of the named scenes (default: the built-ins), in Markdown; 0."""
    def rows():
        for scene in load_all(names or None):
            with_, without = cost(scene)
            yield [scene.name, scene.integrator, str(scene.steps), f"{with_:.1f}", f"{without:.1f}",
                   f"{with_ / without - 1:+.0%}"]
    stream(["scene", "integrator", "steps", "ns/step, chatter watched", "ns/step, not watched", "extra"], rows())
    return 0
