"""Time `identify` per scene for a step function: the designed calls and the fits, best of a few;
and the regression route on a 40 000-step CSV no family fits.

    python -m compare tools identify-bench [MODULE:FUNCTION] [SCENE ...] [--repeat N] [--step-us US]

Default: examples/seed_sim.py:step (plain numpy) on every built-in scene, each call held to at
least 30 us (a step in plain Python). Prints, per scene, the calls made, the fastest and the
median wall time of N runs (each from a fresh import), and the time the step function itself
took (the rest is the identification's own work); then the regression route's time.
"""
from __future__ import annotations

import statistics
import sys
import time

import numpy as np

from scene_types.state import STATE_COMPONENTS

from ..table import text

# The budget one scene's designed identification is held to, for a step of STEP_US (s).
BUDGET = 2.0
# What one call of a step in plain Python costs (us): every call is held to at least this.
STEP_US = 30.0
# The regression route: a CSV of this many steps, no family fitting its normal force, within
# RUN_BUDGET (s).
RUN_STEPS = 40_000
RUN_BUDGET = 3.0


class _Timed:
    """The step function, its own time added up."""

    def __init__(self, simulator, step_us: float = 0.0):
        self.simulator, self.spent = simulator, 0.0
        self.spec = simulator.spec
        self.least = step_us * 1e-6

    def fresh(self):
        self.simulator.fresh()
        inner = self.simulator.function

        def timed(*args):
            t = time.perf_counter()
            try:
                return inner(*args)
            finally:
                while time.perf_counter() - t < self.least:   # a step in plain Python
                    pass
                self.spent += time.perf_counter() - t
        self.function = timed


def field_states(scene, steps: int) -> np.ndarray:
    """A run no family fits: RK4 (the regression route's slowest: its laws are stepped by RK4
    there) of the body on a smooth field 2000 m g exp(-z / 4 mm) (1 - v_n s/m) at each contact
    point (z its height), no friction, `steps` steps of the scene's dt."""
    from ..usersim.scene_dict import scene_dict
    sd = scene_dict(scene)
    mp = sd["mass_properties"]
    m, inertia, pts = mp["mass"], mp["inertia"], np.array(mp["contact_points"], dtype=float)
    g, h = sd["g"], sd["dt"]
    def rate(z):
        c, s = np.cos(z[2]), np.sin(z[2])
        rx, ry = c * pts[:, 0] - s * pts[:, 1], s * pts[:, 0] + c * pts[:, 1]
        fn = 2000.0 * m * g * np.exp(-(z[1] + ry) / 0.004) * np.maximum(0.0, 1.0 - (z[4] + z[5] * rx))
        return np.array([z[3], z[4], z[5], 0.0, fn.sum() / m - g, (rx * fn).sum() / inertia])

    z = np.array(sd["state0"], dtype=float)
    out = np.empty((steps + 1, 6))
    out[0] = z
    for i in range(steps):
        k1 = rate(z)
        k2 = rate(z + 0.5 * h * k1)
        k3 = rate(z + 0.5 * h * k2)
        k4 = rate(z + h * k3)
        z = z + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
        out[i + 1] = z
    return out


def time_run(repeat: int = 3) -> tuple[float, float, dict]:
    """(best seconds, best CPU seconds, the identification) of the regression route on box_drop's RUN_STEPS-step CSV
    of field_states, written at 17 digits and read back as `--trajectories` reads it."""
    import tempfile
    from pathlib import Path

    from ..scenarios import load
    from ..usersim import load_simulator
    from .whole_run import identify_run

    scene = load("box_drop")
    states = field_states(scene, RUN_STEPS)
    with tempfile.TemporaryDirectory() as tmp:
        t = np.arange(len(states)) * scene.dt
        np.savetxt(Path(tmp) / "box_drop.csv", np.column_stack([t, states]), delimiter=",",
                   header=",".join(("t", *STATE_COMPONENTS)), comments="", fmt="%.17g")
        run = load_simulator(trajectories=tmp).run(scene)
    times, cpu = [], []
    for _ in range(repeat):
        start, start_cpu = time.perf_counter(), time.process_time()
        out = identify_run(run.states, scene, run.rounding, "trajectories")
        times.append(time.perf_counter() - start)
        cpu.append(time.process_time() - start_cpu)
    return min(times), min(cpu), out


def print_times(spec: str, names: list[str], repeat: int = 3, step_us: float = STEP_US) -> int:
    """The table of the named scenes (default: every built-in), then the regression route's
    line; 0 when the slowest scene is within BUDGET and the run within RUN_BUDGET, else 1."""
    from ..scenarios import load_all
    from ..usersim import load_simulator
    from .from_step import identify_step

    simulator = load_simulator(spec)
    scenes = load_all(names)
    identify_step(simulator, scenes[0])   # first use: imports and scipy's lazy modules, not timed
    worst, rows = 0.0, []
    for scene in scenes:
        print(f"{scene.name} ...", file=sys.stderr, flush=True)
        times, own, cpu, calls = [], [], [], 0
        for _ in range(repeat):
            timed = _Timed(simulator, step_us)
            start, start_cpu = time.perf_counter(), time.process_time()
            out = identify_step(timed, scene)
            times.append(time.perf_counter() - start)
            cpu.append(time.process_time() - start_cpu)
            own.append(timed.spent)
            calls = out["calls"]
        worst = max(worst, min(times))
        rows.append([scene.name, str(calls), f"{min(times):.3f}", f"{statistics.median(times):.3f}", f"{min(cpu):.3f}",
                     f"{min(own):.3f}"])
    print(text(["scene", "calls", "best s", "median s", "cpu s", "in step s"], rows, align=["left", *["right"] * 5]))
    print(f"slowest scene {worst:.3f} s (budget {BUDGET:g} s, every call at least {step_us:g} us)")
    print("regression ...", file=sys.stderr, flush=True)
    run_s, run_cpu, out = time_run(repeat)
    normal = out["normal"]["law"] or f"none fits (closest {out['normal'].get('closest', {}).get('law')})"
    print(f"regression: box_drop CSV of {out['steps']} steps, normal {normal}: {run_s:.3f} s, cpu {run_cpu:.3f} s "
          f"(budget {RUN_BUDGET:g} s)")
    return 0 if worst <= BUDGET and run_s <= RUN_BUDGET else 1
