"""Cost of one step in each simulator, measured in the same run: nanoseconds per step.

Both sides take all their steps in compiled code and record nothing, so the number is the
cost of the physics, not of Python or of storing a trajectory:

    custom   custom_sim.Stepper(scene).advance(n): one call into the numba loop
             (custom_sim.integrators.integrate with an `out` of 0 rows: no recording),
             less the same with n = 0 (per_step: the steps' cost, not the call's)
    mujoco   mujoco.mj_step(model, data, nstep=n): MuJoCo's C loop, nothing recorded, and
             mujoco.rollout (C loop that also copies the state out each step); the faster of
             the two is MuJoCo's figure, so the ratio never flatters us

Each side runs the scene's full duration (its own mix of flight, impact and rest) from the
scene's initial state, once to warm up, then REPEATS times; the minimum is the cost (noise
from other processes only ever adds time). Our side uses the scene's integrator and dt,
MuJoCo's side the scene's [mujoco] integrator and dt.

Beside the cost: the Newton iterations per step (implicit Euler solves a 3x3 system per
iteration; the other integrators take none), from the stepper's own counters. With
`before=custom_sim_at(REV)` our side is also timed as of an older revision of custom_sim, in
alternation with today's, so that a change is shown before and after in one run.

The cost is the CPU time of the stepping thread (clock_gettime(CLOCK_THREAD_CPUTIME_ID)):
on an idle core it equals the wall time, and on a shared machine it does not charge one side
for the time the scheduler gave to other processes. A MuJoCo run lasts 100 times longer than
ours and would be preempted far more often, so a wall-clock ratio on a busy machine flatters
us. The wall time is kept beside it (`*_wall` keys).
"""
from __future__ import annotations

import dataclasses
import importlib
import io
import re
import subprocess
import sys
import tarfile
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from custom_sim import Scene, Stepper

from . import minimal_loop
from custom_sim.integrators import NEWTON_ITERS

ROOT = Path(__file__).resolve().parents[3]   # the repository (for git revisions)

REPEATS = 7                 # timed repeats after the warm-up; the minimum is reported
TIME_BUDGET = 0.5           # s per side, scene and round: fewer repeats for slow runs (at least 2)
# The two sides are timed in alternation, ROUNDS times, and each keeps its minimum: a burst of
# load from another process (or on the sibling hyperthread, which slows even CPU time) then
# cannot fall on one side's whole measurement.
ROUNDS = 3


@dataclass(frozen=True)
class BenchResult:
    """ns per step from the CPU time of the stepping thread; *_wall from the wall clock."""

    name: str
    steps: int
    ns_per_step_custom: float
    ns_per_step_mujoco: float
    ns_per_step_custom_wall: float
    ns_per_step_mujoco_wall: float
    mujoco_loop: str            # "mj_step" or "rollout": the faster C loop
    integrator_custom: str
    integrator_mujoco: str
    dt_custom: float
    dt_mujoco: float
    newton_per_step: float = 0.0                 # Newton iterations per step (implicit Euler)
    ns_per_step_before: float | None = None      # ours as of the revision given to bench_scene
    ns_per_step_before_wall: float | None = None
    ns_per_step_minimal: float | None = None     # the floor: one minimal compiled loop of the law (minimal_loop.py)
    yours: str | None = None                     # the user's simulator (--sim), its spec
    ns_per_step_yours: float | None = None       # its whole run through the harness, per step (CPU)
    ns_per_step_yours_wall: float | None = None
    integrator_yours: str | None = None
    ns_per_call_harness: float | None = None     # of that, the harness's own loop per call (usersim/overhead.py)

    @property
    def ratio(self) -> float:
        """How many of our steps cost as much as one of MuJoCo's."""
        return self.ns_per_step_mujoco / self.ns_per_step_custom

    def as_dict(self) -> dict:
        d = {"name": self.name, "ns_per_step_custom": self.ns_per_step_custom,
             "ns_per_step_mujoco": self.ns_per_step_mujoco, "ratio": self.ratio}
        d.update({k: v for k, v in dataclasses.asdict(self).items() if k not in d})
        return d


@dataclass(frozen=True)
class Timing:
    """Minimum over repeats (s): CPU time of the calling thread, and wall time."""

    cpu: float
    wall: float


def min_time(run, repeats: int = REPEATS, budget: float = TIME_BUDGET) -> Timing:
    """Minimum CPU and wall time (s) of run() over repeats, after one warm-up call."""
    first = time.perf_counter()
    run()
    warm = time.perf_counter() - first
    repeats = max(2, min(repeats, int(budget / max(warm, 1e-9))))
    cpu = wall = np.inf
    for _ in range(repeats):
        w0, c0 = time.perf_counter(), time.thread_time()
        run()
        c1, w1 = time.thread_time(), time.perf_counter()
        cpu, wall = min(cpu, c1 - c0), min(wall, w1 - w0)
    return Timing(cpu, wall)


def custom_step_runner(scene: Scene, steps: int, start=None, stepper=Stepper):
    """A callable taking `steps` steps of the scene from its initial state (or `start`,
    [x, y, theta, vx, vy, omega]), recording nothing. stepper: the Stepper class (today's, or
    an older revision's from custom_sim_at)."""
    def run():
        s = stepper(scene)
        if start is not None:
            s.reset(start)
        s.advance(steps)
    return run


def per_step(run_steps, steps: int, **timing) -> Timing:
    """ns per step (CPU, wall) of run_steps(steps), less the fixed cost of a call, run_steps(0)
    (building the stepper, the call into compiled code): the cost of the steps alone.

    Without it an older revision (custom_sim_at) is charged some 0.1 ms a call that is none of
    its steps: its Model namedtuple has the same field types as today's, so numba's dispatcher
    finds today's type under their shared type fingerprint, and every call of the older loop
    takes numba's slow path to its own (5 ns a step on elastic_bounce's 30000 steps)."""
    t = min_time(run_steps(steps), **timing)
    fixed = min_time(run_steps(0), **timing)
    return Timing(1e9 * max(t.cpu - fixed.cpu, 0.0) / steps, 1e9 * max(t.wall - fixed.wall, 0.0) / steps)


def custom_ns_per_step(scene: Scene, steps: int | None = None, stepper=Stepper, **timing) -> Timing:
    """ns per step (CPU, wall) of our simulator on the scene (per_step: without the fixed cost of a call)."""
    return per_step(lambda n: custom_step_runner(scene, n, stepper=stepper), steps or scene.steps, **timing)


def newton_per_step(scene: Scene) -> float:
    """Newton iterations per step over the scene's run (0 for the explicit integrators)."""
    s = Stepper(scene)
    s.advance(scene.steps)
    return float(s.counters[NEWTON_ITERS]) / max(1, scene.steps)


def custom_sim_at(revision: str):
    """custom_sim as of a git revision of this repository, imported under its own name
    (custom_sim_at_<revision>) beside today's, for before/after timings in one process.
    Raises ValueError when git cannot produce it."""
    name = "custom_sim_at_" + re.sub(r"\W", "_", revision)
    if name in sys.modules:
        return sys.modules[name]
    proc = subprocess.run(["git", "archive", "--format=tar", revision, "custom_sim"], cwd=ROOT,
                          capture_output=True)
    if proc.returncode != 0:
        raise ValueError(f"--against {revision}: git archive failed: {proc.stderr.decode().strip()}")
    folder = Path(tempfile.mkdtemp(prefix="bench_before_"))
    with tarfile.open(fileobj=io.BytesIO(proc.stdout)) as tar:
        tar.extractall(folder, filter="data")
    (folder / "custom_sim").rename(folder / name)
    sys.path.insert(0, str(folder))
    return importlib.import_module(name)


def mujoco_setup(scene: Scene, integrator: str | None = None, dt: float | None = None):
    """(model, data, initial full-physics state) of the scene's twin, at the keyframe."""
    import mujoco
    from mujoco_models import build_model
    from mujoco_models.spec import INTEGRATORS

    model = build_model(scene)
    integrator = integrator or scene.mujoco.integrator
    model.opt.integrator = INTEGRATORS[integrator]
    model.opt.timestep = dt or scene.mujoco.dt or scene.dt
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    state = np.empty(mujoco.mj_stateSize(model, spec))
    mujoco.mj_getState(model, data, state, spec)
    return model, data, state


def mujoco_step_runner(model, data, state, steps: int, loop: str = "mj_step"):
    """A callable taking `steps` MuJoCo steps from `state` in C (mj_step or rollout)."""
    import mujoco
    from mujoco import rollout

    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    if loop == "rollout":
        out = np.empty((1, steps, state.size))

        def run():
            rollout.rollout(model, data, state, nstep=steps, state=out)
        return run

    def run():
        mujoco.mj_setState(model, data, state, spec)
        mujoco.mj_step(model, data, nstep=steps)
    return run


def mujoco_ns_per_step(scene: Scene, steps: int | None = None, integrator: str | None = None,
                       dt: float | None = None, loops=("mj_step", "rollout"), **timing) -> tuple[Timing, str]:
    """(ns per step as (CPU, wall), loop) for the faster of MuJoCo's C loops on the scene's twin."""
    model, data, state = mujoco_setup(scene, integrator, dt)
    dt = model.opt.timestep
    steps = steps or max(1, int(round(scene.duration / dt)))
    best = {}
    for loop in loops:
        t = min_time(mujoco_step_runner(model, data, state, steps, loop), **timing)
        best[loop] = Timing(1e9 * t.cpu / steps, 1e9 * t.wall / steps)
    loop = min(best, key=lambda k: best[k].cpu)
    return best[loop], loop


def yours_runner(sim, scene: Scene):
    """A callable running the scene once with the user's simulator through the harness (a fresh
    import, the scene dict, the checked loop: what `run` does), with the integrator it declares."""
    from .yours import variant
    sc = variant(scene, sim.integrator_for(scene), scene.dt)

    def run():
        sim.run(sc)
    return run


def harness_share(sim, scene: Scene) -> float | None:
    """ns the harness adds per call of a step function (a no-op step in its loop against a bare
    loop, compare/usersim/overhead.py); None for a simulator the harness does not call per step."""
    if getattr(sim, "kind", "") != "step":
        return None
    from ...usersim.overhead import measure_overhead
    return 1e9 * max(measure_overhead(scene, "array")["overhead_s_per_step"], 0.0)


def bench_scene(scene: Scene, rounds: int = ROUNDS, before=None, yours=None, **timing) -> BenchResult:
    """Both simulators on one scene, in alternation in this process, `rounds` times; with
    `before` (a module from custom_sim_at) that revision's stepper too, in the same rounds; with
    `yours` (a simulator from compare/usersim) the user's code too, a whole run per timing."""
    dt_mj = scene.mujoco.dt or scene.dt
    steps_mj = max(1, int(round(scene.duration / dt_mj)))
    ours = theirs = old = user = Timing(np.inf, np.inf)
    loops = {}
    floor = np.inf
    for _ in range(max(1, rounds)):
        t = custom_ns_per_step(scene, **timing)
        ours = Timing(min(ours.cpu, t.cpu), min(ours.wall, t.wall))
        if minimal_loop.applies(scene):
            floor = min(floor, per_step(lambda n: minimal_loop.runner(scene, n), scene.steps, **timing).cpu)
        if before is not None:
            t = custom_ns_per_step(scene, stepper=before.Stepper, **timing)
            old = Timing(min(old.cpu, t.cpu), min(old.wall, t.wall))
        if yours is not None:
            t = min_time(yours_runner(yours, scene), **timing)
            user = Timing(min(user.cpu, 1e9 * t.cpu / scene.steps), min(user.wall, 1e9 * t.wall / scene.steps))
        t, loop = mujoco_ns_per_step(scene, steps_mj, **timing)
        if t.cpu < theirs.cpu:
            loops["best"] = loop
        theirs = Timing(min(theirs.cpu, t.cpu), min(theirs.wall, t.wall))
    loop = loops["best"]
    return BenchResult(scene.name, scene.steps, ours.cpu, theirs.cpu, ours.wall, theirs.wall, loop,
                       scene.integrator, scene.mujoco.integrator, scene.dt, dt_mj,
                       newton_per_step=newton_per_step(scene),
                       ns_per_step_before=None if before is None else old.cpu,
                       ns_per_step_before_wall=None if before is None else old.wall,
                       ns_per_step_minimal=None if floor == np.inf else floor,
                       **({} if yours is None else
                          {"yours": yours.label, "integrator_yours": yours.integrator_for(scene),
                           "ns_per_step_yours": user.cpu if getattr(yours, "kind", "") in ("step", "whole") else user.wall,
                           "ns_per_step_yours_wall": user.wall, "ns_per_call_harness": harness_share(yours, scene)}))


@dataclass(frozen=True)
class Linearity:
    """CPU time of n and of 10 n steps (s) on each side; a ratio near 10 means linear cost."""

    name: str
    steps: int
    custom: tuple[float, float]
    mujoco: tuple[float, float]

    @property
    def custom_ratio(self) -> float:
        return self.custom[1] / self.custom[0]

    @property
    def mujoco_ratio(self) -> float:
        return self.mujoco[1] / self.mujoco[0]


def linearity(scene: Scene, **timing) -> Linearity:
    """Time n and 10 n steps (n: the scene's steps) in both simulators, both counts started
    from the state at the end of the scene, so the two runs see the same kind of step (the
    body at rest or rolling on) and only the count differs."""
    import mujoco

    n = scene.steps
    stepper = Stepper(scene)
    end = stepper.advance(n).copy()
    custom = (min_time(custom_step_runner(scene, n, end), **timing).cpu,
              min_time(custom_step_runner(scene, 10 * n, end), **timing).cpu)
    model, data, state = mujoco_setup(scene)
    m_n = max(1, int(round(scene.duration / model.opt.timestep)))
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    mujoco.mj_step(model, data, nstep=m_n)
    mujoco.mj_getState(model, data, state, spec)
    mj = (min_time(mujoco_step_runner(model, data, state, m_n), **timing).cpu,
          min_time(mujoco_step_runner(model, data, state, 10 * m_n), **timing).cpu)
    return Linearity(scene.name, n, custom, mj)
