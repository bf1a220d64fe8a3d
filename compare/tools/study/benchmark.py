"""What batching and workers buy, measured in one run: `python -m compare tools study-bench [--out DIR]`.

1. custom_sim: runs per second of simulate_batch (one compiled call, prange over the runs, 1 and
   2 threads) against custom_sim.simulate called once per run, on the same runs (box_drop with
   RUNS stiffnesses) at three step sizes; the minimum of REPEATS timings after a warm-up. The
   count of unstable runs is printed beside: for those a single call also builds the
   diagnosis (the stable step), which a batch leaves to its caller.
2. MuJoCo: runs per second of mujoco_models.batch (rollout over several models, 1 and 2
   threads) against simulate_mujoco once per run.
3. The study's wall time on 1 and 2 workers of one thread each (the same study, a fresh folder
   each time, the cluster already started), and on 1 worker allowed 2 threads.

The machine's load average is printed before and after: on a shared machine the figures are
only as good as the quiet they were measured in. Writes DIR/benchmark.json (default reports/study_benchmark).
"""
from __future__ import annotations

import dataclasses
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

from ...files import finite_json

RUNS = 16
REPEATS = 3
STEPS = (1e-2, 1e-3, 1e-4)                 # s
STUDY = ["contact.k=3e3:3e4:4:log", "dt=2.5e-5:1e-4:4:log"]   # inside the stable region: whole runs


def _scenes(dt: float, integrator: str = "semi_implicit_euler"):
    import numpy as np

    from ...scenarios import load

    base = load("box_drop")
    return [dataclasses.replace(base, dt=dt, integrator=integrator,
                                contact=dataclasses.replace(base.contact, k=float(k)))
            for k in np.geomspace(3e3, 3e4, RUNS)]


def _best(fn) -> tuple[float, object]:
    """(the fastest of REPEATS timings of fn() after a warm-up call, s; fn's last result)."""
    result = fn()
    times = []
    for _ in range(REPEATS):
        start = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - start)
    return min(times), result


def _each(simulate, scenes) -> None:
    """One call per run; a run that diverges or chatters stops there, as it does in a batch."""
    from custom_sim import SimulationDiverged
    for s in scenes:
        try:
            simulate(s)
        except SimulationDiverged:
            pass


def custom_rates() -> list[dict]:
    from custom_sim import simulate
    from custom_sim.batch import simulate_batch

    out = []
    for dt in STEPS:
        scenes = _scenes(dt)
        single, _ = _best(lambda: _each(simulate, scenes))
        one, runs = _best(lambda: simulate_batch(scenes, threads=1))
        two, _ = _best(lambda: simulate_batch(scenes, threads=2))
        unstable = sum(r.diverged for r in runs)
        out.append({"dt": dt, "steps": scenes[0].steps, "runs": len(scenes), "unstable": unstable,
                    "runs_per_s_single_calls": len(scenes) / single,
                    "runs_per_s_batch_1_thread": len(scenes) / one,
                    "runs_per_s_batch_2_threads": len(scenes) / two,
                    "speedup_1_thread": single / one, "speedup_2_threads": single / two})
    return out


def mujoco_rates() -> list[dict]:
    from mujoco_models import simulate_mujoco
    from mujoco_models.batch import simulate_mujoco_batch

    out = []
    for dt in STEPS[1:]:
        scenes = _scenes(dt)
        single, _ = _best(lambda: [simulate_mujoco(s) for s in scenes])
        one, _ = _best(lambda: simulate_mujoco_batch(scenes, threads=1))
        two, _ = _best(lambda: simulate_mujoco_batch(scenes, threads=2))
        out.append({"dt": dt, "steps": scenes[0].steps, "runs": len(scenes),
                    "runs_per_s_single_calls": len(scenes) / single,
                    "runs_per_s_rollout_1_thread": len(scenes) / one,
                    "runs_per_s_rollout_2_threads": len(scenes) / two,
                    "speedup_1_thread": single / one, "speedup_2_threads": single / two})
    return out


def _warm() -> None:
    """Run in every worker before timing: imports, numba's cache and a MuJoCo twin loaded."""
    import dataclasses

    from custom_sim.batch import simulate_batch
    from mujoco_models.batch import simulate_mujoco_batch

    from ...scenarios import load

    scene = dataclasses.replace(load("box_drop"), duration=0.05)
    simulate_batch([scene], threads=1)
    simulate_mujoco_batch([scene])


def study_times() -> list[dict]:
    from ...executor import make_executor
    from ...scenarios import resolve
    from .fields import SceneSource, parse_vary
    from .runner import run_study

    source = SceneSource.read(resolve("box_drop"))
    varies = [parse_vary(v) for v in STUDY]
    integrators = ["explicit_euler", "semi_implicit_euler", "implicit_euler", "rk4"]
    out = []
    for workers, threads in ((1, 1), (2, 1), (1, 2)):
        engine = make_executor("dask", workers=workers, threads_per_task=threads)
        folder = Path(tempfile.mkdtemp(prefix="study-bench-"))
        try:
            # warm every worker (imports, numba's cache), then the client with a one-run study
            engine.client.run(_warm)
            warm = Path(tempfile.mkdtemp(prefix="study-warm-"))
            run_study(source, [parse_vary("contact.k=2e4")], ["rk4"], warm, engine=engine, progress=False)
            shutil.rmtree(warm, ignore_errors=True)
            start = time.perf_counter()
            study = run_study(source, varies, integrators, folder, engine=engine, progress=False)
            wall = time.perf_counter() - start
        finally:
            shutil.rmtree(folder, ignore_errors=True)
            engine.close()
        out.append({"workers": workers, "threads_per_task": threads, "runs": len(study.rows), "wall_time": wall})
    return out


def benchmark(out: str = "reports/study_benchmark") -> int:
    """Measure, print and write out/benchmark.json; 2 without Dask, else 0."""
    from ...executor import STUDY_EXTRA, dask_available
    if not dask_available():   # its third part runs a study
        print(f"error: tools study-bench needs Dask: {STUDY_EXTRA}", file=sys.stderr)
        return 2
    load_before = os.getloadavg()
    result = {"cores": os.cpu_count(), "load_before": load_before,
              "custom": custom_rates(), "mujoco": mujoco_rates(), "study": study_times(),
              "load_after": os.getloadavg()}
    one = next(s for s in result["study"] if s["workers"] == 1 and s["threads_per_task"] == 1)
    two = next(s for s in result["study"] if s["workers"] == 2)
    result["study_speedup_2_workers"] = one["wall_time"] / two["wall_time"]
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "benchmark.json").write_text(finite_json(result, indent=1))
    print(f"load average before {load_before[0]:.2f}, after {result['load_after'][0]:.2f} on {os.cpu_count()} cores")
    for r in result["custom"]:
        print(f"custom_sim dt={r['dt']:g} ({r['steps']} steps): {r['runs_per_s_single_calls']:.0f} runs/s one call "
              f"per run, batch {r['runs_per_s_batch_1_thread']:.0f} (1 thread, x{r['speedup_1_thread']:.1f}), "
              f"{r['runs_per_s_batch_2_threads']:.0f} (2 threads, x{r['speedup_2_threads']:.1f}); "
              f"{r['unstable']} of the {r['runs']} runs unstable")
    for r in result["mujoco"]:
        print(f"MuJoCo dt={r['dt']:g} ({r['steps']} steps): {r['runs_per_s_single_calls']:.1f} runs/s one call "
              f"per run, rollout {r['runs_per_s_rollout_1_thread']:.1f} (1 thread, x{r['speedup_1_thread']:.2f}), "
              f"{r['runs_per_s_rollout_2_threads']:.1f} (2 threads, x{r['speedup_2_threads']:.2f})")
    for s in result["study"]:
        print(f"study of {s['runs']} runs on {s['workers']} worker(s) x {s['threads_per_task']} thread(s): "
              f"{s['wall_time']:.2f} s")
    print(f"2 workers against 1: x{result['study_speedup_2_workers']:.2f} (linear: x2)")
    return 0
