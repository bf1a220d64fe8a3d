"""What the harness adds per step to a user's Python step function, and a process's round trip.

    python -m compare tools overhead [MODULE:FUNCTION] [--sim-process COMMAND] [--scene NAME] [--steps N]

Times, interleaved and the minimum of repeats kept, (1) a bare loop calling a no-op step
`step(state, scene, dt) -> state` n times, (2) the harness's own loop (StepFunction.run) around
the same no-op step (the whole run: scene dict, checks, loop), for a step returning a numpy array and one returning a list; their
difference is the harness's cost per step. Then the given step function (default: the
worked example) on the scene: ns per step and the whole run's wall time.

Beside it, the round trip of a step through a process (--sim-process, process.py): the
harness's loop (Process.run) around a no-op process written in C (it answers the state it is
given; built with cc, or a Python one where cc is missing), wall time per step (the minimum of
repeats) and the CPU time each side spends; then the given process (default: the C worked
example, examples/process/step.c) on the scene.
"""
from __future__ import annotations

import dataclasses
import math
import resource
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from ..scenarios import load
from .loader import StepFunction
from .scene_dict import scene_dict

OVERHEAD_GOAL = 2e-6   # s per step the harness may add (issue 11)
ROUND_TRIP_GOAL = 20e-6   # s per step a process's round trip may take, on 2 cores (issue 35)
EXAMPLE_C = Path(__file__).resolve().parents[2] / "examples" / "process" / "step.c"
NOOP_C = r"""#include <stdio.h>
#include <string.h>
static char line[1 << 16];
int main(void) {   /* `ready scene`, then each `step DT X Y THETA VX VY OMEGA` answered with X ... OMEGA */
    while (fgets(line, sizeof line, stdin)) {
        if (!strncmp(line, "scene ", 6)) fputs("ready scene\n", stdout);
        else fputs(strchr(strchr(line, ' ') + 1, ' ') + 1, stdout);
        fflush(stdout);
    }
    return 0;
}
"""
NOOP_PY = ("import sys\nfor line in sys.stdin:\n    print('ready scene' if line.startswith('scene ') "
           "else line.split(' ', 2)[2], end='' if line.startswith('step ') else '\\n', flush=True)\n")
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


def print_overhead(spec: str | None = None, scene_name: str = "box_drop", steps: int = 20_000,
                   process: str | None = None) -> int:
    """The no-op steps' overhead, then spec's step (default DEFAULT_SIM) on the scene, `steps`
    long; then a process's round trip (print_round_trip); 0 when the overhead is within
    OVERHEAD_GOAL and the round trip within ROUND_TRIP_GOAL, else 1."""
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
    run = min((sim.run(scene) for _ in range(3)), key=lambda r: r.wall_time or math.inf)
    assert run.wall_time is not None   # a function's run is timed
    print(f"{spec} on {scene.name} ({scene.integrator}), {scene.steps} steps: "
          f"{run.wall_time / scene.steps * 1e6:.1f} us/step, {run.wall_time:.2f} s for the run")
    trip = print_round_trip(scene, process)
    ok = worst <= OVERHEAD_GOAL
    print(f"harness overhead {worst * 1e9:.0f} ns/step: {'within' if ok else 'ABOVE'} the {OVERHEAD_GOAL * 1e6:g} us goal")
    fast = trip <= ROUND_TRIP_GOAL
    print(f"process round trip {trip * 1e6:.1f} us/step: {'within' if fast else 'ABOVE'} the "
          f"{ROUND_TRIP_GOAL * 1e6:g} us goal")
    return 0 if ok and fast else 1


def _build(source: str, folder: Path, name: str) -> str | None:
    """source compiled with cc into folder/name (its path), or None where cc is missing or fails."""
    cc = shutil.which("cc")
    if cc is None:
        return None
    (folder / f"{name}.c").write_text(source)
    done = subprocess.run([cc, "-O2", "-o", str(folder / name), str(folder / f"{name}.c"), "-lm"],
                          capture_output=True)
    return str(folder / name) if done.returncode == 0 else None


def measure_round_trip(scene, command: str, repeats: int = 5) -> dict:
    """Seconds per step of Process(command).run(scene): wall (the fastest of repeats), and the
    CPU time of the harness and of the process in that run."""
    from .process import Process
    best: tuple[float, float, float] | None = None
    for _ in range(repeats):
        sim = Process(command)
        before, cpu = resource.getrusage(resource.RUSAGE_CHILDREN), time.process_time()
        wall = sim.run(scene).wall_time    # run ends the process: its CPU time is counted
        cpu = time.process_time() - cpu
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        child = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
        assert wall is not None   # a process's run is timed
        if best is None or wall < best[0]:
            best = (wall, cpu, child)
    assert best is not None, "repeats >= 1"
    n = scene.steps
    return {"wall_s_per_step": best[0] / n, "harness_cpu_s_per_step": best[1] / n,
            "process_cpu_s_per_step": best[2] / n}


def print_round_trip(scene, command: str | None = None) -> float:
    """The no-op process's round trip, then `command`'s (default: the C worked example) on the
    scene; the no-op's wall time per step (s)."""
    folder = Path(tempfile.mkdtemp())
    noop = _build(NOOP_C, folder, "noop")
    if noop is None:
        (folder / "noop.py").write_text(NOOP_PY)
        noop, what = f"{shlex.quote(sys.executable)} {folder / 'noop.py'}", "Python (no cc to build the C one)"
    else:
        what = "C"
    r = measure_round_trip(scene, noop)
    print(f"no-op process ({what}) through --sim-process: {r['wall_s_per_step'] * 1e6:5.1f} us/step round trip "
          f"(CPU: harness {r['harness_cpu_s_per_step'] * 1e6:.1f} us, process {r['process_cpu_s_per_step'] * 1e6:.1f} us)")
    if command is None:
        built = _build(EXAMPLE_C.read_text(), folder, "step")
        command, label = built, "examples/process/step.c"
    else:
        label = command
    if command is not None:
        u = measure_round_trip(scene, command, repeats=3)
        print(f"{label} on {scene.name} ({scene.integrator}), {scene.steps} steps: "
              f"{u['wall_s_per_step'] * 1e6:.1f} us/step, {u['wall_s_per_step'] * scene.steps:.2f} s for the run")
    shutil.rmtree(folder, ignore_errors=True)
    return r["wall_s_per_step"]
