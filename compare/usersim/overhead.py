"""What the harness adds per step to a user's Python step function, measured in one run.

    python -m compare tools overhead [MODULE:FUNCTION] [--scene NAME] [--steps N]

Times, interleaved and the minimum of repeats kept, (1) a bare loop calling a no-op step
`step(state, scene, dt) -> state` n times, (2) the harness's own loop (StepFunction.run) around
the same no-op step (the whole run: scene dict, checks, loop), for a step returning a numpy array and one returning a list; their
difference is the harness's cost per step. Then the given step function (default: the
worked example) on the scene: ns per step and the whole run's wall time.
"""
from __future__ import annotations

import dataclasses
import tempfile
import time
from pathlib import Path

import numpy as np

from ..scenarios import load
from .loader import StepFunction
from .scene_dict import scene_dict

OVERHEAD_GOAL = 2e-6   # s per step the harness may add (issue 11)
DEFAULT_SIM = str(Path(__file__).resolve().parents[2] / "examples" / "seed_sim.py") + ":step"
NOOPS = {"array": "def step(state, scene, dt):\n    return state\n",
         "list": "def step(state, scene, dt):\n    return [0.0, 0.3, 0.0, 0.0, 0.0, 0.0]\n"}


def _bare(step, z, sd, dt, n) -> float:
    start = time.perf_counter()
    for _ in range(n):
        z = step(z, sd, dt)
    return time.perf_counter() - start


def measure_overhead(scene, kind: str, repeats: int = 7) -> dict:
    """Seconds per step: bare calls, the harness's loop, and their difference."""
    folder = Path(tempfile.mkdtemp())
    (folder / f"noop_{kind}.py").write_text(NOOPS[kind])
    sim = StepFunction(f"{folder / f'noop_{kind}.py'}:step")
    sd, n = scene_dict(scene), scene.steps
    z0 = np.array(sd["state0"])
    bare, harness = [], []
    for _ in range(repeats):
        bare.append(_bare(sim.function, z0, sd, scene.dt, n))
        start = time.perf_counter()
        sim.run(scene)  # all of it: the scene dict, the first checked call, the loop, the NaN scan
        harness.append(time.perf_counter() - start)
    b, h = min(bare) / n, min(harness) / n
    return {"kind": kind, "bare_s_per_step": b, "harness_s_per_step": h, "overhead_s_per_step": h - b}


def print_overhead(spec: str | None = None, scene_name: str = "box_drop", steps: int = 20_000) -> int:
    """The no-op steps' overhead, then spec's step (default DEFAULT_SIM) on the scene, `steps`
    long; 0 when the overhead is within OVERHEAD_GOAL, else 1."""
    spec = spec or DEFAULT_SIM
    scene = load(scene_name)
    scene = dataclasses.replace(scene, duration=steps * scene.dt)
    worst = 0.0
    for kind in NOOPS:
        r = measure_overhead(scene, kind)
        worst = max(worst, r["overhead_s_per_step"])
        print(f"no-op step returning a {kind:<5}: bare {r['bare_s_per_step'] * 1e9:7.0f} ns/step, "
              f"in the harness {r['harness_s_per_step'] * 1e9:7.0f} ns/step, "
              f"harness adds {r['overhead_s_per_step'] * 1e9:6.0f} ns/step")
    sim = StepFunction(spec)
    run = min((sim.run(scene) for _ in range(3)), key=lambda r: r.wall_time)
    print(f"{spec} on {scene.name} ({scene.integrator}), {scene.steps} steps: "
          f"{run.wall_time / scene.steps * 1e6:.1f} us/step, {run.wall_time:.2f} s for the run")
    ok = worst <= OVERHEAD_GOAL
    print(f"harness overhead {worst * 1e9:.0f} ns/step: {'within' if ok else 'ABOVE'} the {OVERHEAD_GOAL * 1e6:g} us goal")
    return 0 if ok else 1
