"""Time `identify` per scene for a step function: the designed calls and the fits, best of a few.

    python -m compare tools identify-bench [MODULE:FUNCTION] [SCENE ...] [--repeat N]

Default: examples/seed_sim.py:step (plain numpy) on every built-in scene. Prints, per scene, the
calls made, the fastest and the median wall time of N runs (each from a fresh import), and the
time the step function itself took (the rest is the identification's own work).
"""
from __future__ import annotations

import statistics
import sys
import time

from ..table import text

# The budget one scene's identification is held to, for a plain numpy step function (s).
BUDGET = 5.0


class _Timed:
    """The step function, its own time added up."""

    def __init__(self, simulator):
        self.simulator, self.spent = simulator, 0.0
        self.spec = simulator.spec

    def fresh(self):
        self.simulator.fresh()
        inner = self.simulator.function

        def timed(*args):
            t = time.perf_counter()
            try:
                return inner(*args)
            finally:
                self.spent += time.perf_counter() - t
        self.function = timed


def print_times(spec: str, names: list[str], repeat: int = 3) -> int:
    """The table of the named scenes (default: every built-in); 0 when the slowest scene is
    within BUDGET, else 1."""
    from ..scenarios import load_all
    from ..usersim import load_simulator
    from .from_step import identify_step

    simulator = load_simulator(spec)
    scenes = load_all(names)
    identify_step(simulator, scenes[0])   # first use: imports and scipy's lazy modules, not timed
    worst, rows = 0.0, []
    for scene in scenes:
        print(f"{scene.name} ...", file=sys.stderr, flush=True)
        times, own, calls = [], [], 0
        for _ in range(repeat):
            timed = _Timed(simulator)
            start = time.perf_counter()
            out = identify_step(timed, scene)
            times.append(time.perf_counter() - start)
            own.append(timed.spent)
            calls = out["calls"]
        worst = max(worst, min(times))
        rows.append([scene.name, str(calls), f"{min(times):.3f}", f"{statistics.median(times):.3f}", f"{min(own):.3f}"])
    print(text(["scene", "calls", "best s", "median s", "in step s"], rows, align=["left", *["right"] * 4]))
    print(f"slowest scene {worst:.3f} s (budget {BUDGET:g} s)")
    return 0 if worst <= BUDGET else 1
