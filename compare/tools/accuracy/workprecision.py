"""Work-precision sweep: what each integrator's accuracy costs, in both simulators.

For every scene: the reference (compare.oracle.reference, DOP853 at tight tolerance), each of
our integrators at dt = GRID / n for n in LADDER and MuJoCo's for n in MUJOCO_LADDER (s), and
MuJoCo's own converged solution. Error: the COM distance (m) to the reference on the grid
t_k = k GRID, max and RMS; cost: force evaluations and the CPU time (s) of the stepping, the
minimum over repeats. Only stable runs are kept; a rung predicted over RUN_BUDGET is skipped.
The method: docs/physics.md#8-accuracy-against-cost.
"""
from __future__ import annotations

import dataclasses
import math
import os
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from custom_sim import INTEGRATORS, Scene, SimulationDiverged, Stepper, mass_properties
from custom_sim.energy import energy_parts
from scene_types.integrators import MUJOCO

from ...oracle import reference as ref_mod
from .stability_search import energy_scale, energy_verdict

GRID = 2e-3          # s: errors are measured every 2 ms (every step size below divides it)
LADDER = (1, 2, 4, 10, 20, 40, 100, 200, 400, 1000)       # dt = 2 ms ... 2 us
MUJOCO_LADDER = (1, 2, 4, 10, 20, 40, 100)                 # dt = 2 ms ... 20 us
MUJOCO_CONVERGED = "RK4"
MUJOCO_CONVERGED_N = 400                                    # dt = 5 us
RUN_BUDGET = 1.5      # s: longest single run a rung may take (predicted from the previous rung)
CONVERGED_BUDGET = 20.0   # s: longest run of MuJoCo's converged solution (the 60 s stress scenes)
MUJOCO_RK4_STEP = 20e-6   # s: a MuJoCo RK4 step of these twins, generously (measured 7-19 us)
TIMING_BUDGET = 0.3   # s: repeats of a run's timing stop when they add up to this
MAX_REPEATS = 15
MIN_REPEATS = 2     # a spread needs two timings
TARGET_ERROR = 1e-3   # m: "what is the cheapest way to reach 1 mm here?"
# Initial-height change (m) whose growth measures how strongly the motion amplifies errors:
# far above the reference's own error (1e-9 m), far below any measured error's effect.
PERTURBATION = 1e-7


def grid_times(scene: Scene) -> np.ndarray:
    """t_k = k GRID up to the scene's duration (s)."""
    n = int(round(scene.duration / GRID))
    return np.arange(n + 1) * GRID


def steps_for(scene: Scene, dt: float) -> int:
    return int(round(scene.duration / dt))


@dataclass
class Run:
    """One simulation of the sweep (units: m, rad, s)."""

    simulator: str
    integrator: str
    dt: float
    steps: int
    stable: bool = True
    note: str = ""
    error_max: float = math.nan
    error_l2: float = math.nan
    angle_error_max: float = math.nan
    error_max_self: float = math.nan     # MuJoCo: against its own converged solution
    error_l2_self: float = math.nan
    cpu_time: float = math.nan           # s, stepping thread
    wall_time: float = math.nan
    repeats: int = 0
    cpu_time_spread: float = math.nan    # s, max - min of the repeats' CPU times: the noise
    force_evals: int = 0
    residual_end: float = math.nan       # J: the energy balance's R(end) = E(end) - E(0) + W (compare/energy)
    residual_max: float = math.nan       # J: max |R| over the run
    states: np.ndarray | None = field(default=None, repr=False)   # (K+1, 6) on the grid

    def as_dict(self) -> dict:
        d = dataclasses.asdict(self)
        d.pop("states")
        return {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in d.items()}


@dataclass
class SceneSweep:
    """Everything measured on one scene."""

    scene: Scene
    reference: dict
    runs: list[Run]
    mujoco_converged: dict
    stability: list = field(default_factory=list)
    # the user's simulator (--sim), when given: {"label": its spec, "declared": whether its module
    # names its integrator, "integrators": those it ran, "skipped": {integrator: why not}}
    yours: dict = field(default_factory=dict)

    def of(self, simulator: str, integrator: str) -> list[Run]:
        return [r for r in self.runs if r.simulator == simulator and r.integrator == integrator]


# ---------------------------------------------------------------------------------------
# Errors


def position_errors(states: np.ndarray, ref_states: np.ndarray) -> tuple[float, float, float]:
    """(max, RMS) of the COM distance (m) and max angle difference (rad) over the grid."""
    e = np.hypot(states[:, 0] - ref_states[:, 0], states[:, 1] - ref_states[:, 1])
    return float(e.max()), float(np.sqrt(np.mean(e * e))), float(np.max(np.abs(states[:, 2] - ref_states[:, 2])))


def grid_verdict(scene: Scene, states: np.ndarray, scale: float) -> tuple[bool, str]:
    """Stability of a run from its grid states: finite and no energy growth."""
    if not np.all(np.isfinite(states)):
        return False, "non-finite state"
    ke, pe, ce = energy_parts(scene, mass_properties(scene.body), states)
    return energy_verdict(ke + pe + ce, ce, scale)


# ---------------------------------------------------------------------------------------
# Our simulator


def custom_grid_run(scene: Scene, integrator: str, dt: float) -> tuple[np.ndarray, int]:
    """States on the grid (K+1, 6) and force evaluations of one run; raises SimulationDiverged."""
    sc = dataclasses.replace(scene, integrator=integrator, dt=dt)
    per = int(round(GRID / dt))
    stepper = Stepper(sc)
    out = [stepper.state.copy()]
    for _ in range(len(grid_times(scene)) - 1):
        out.append(stepper.advance(per).copy())
    return np.array(out), int(stepper.counters[0])


def timed(run) -> tuple[float, float, int, float]:
    """(min CPU time, min wall time, repeats, CPU spread) of run() -> (cpu s, wall s): one
    warm-up call, then as many repeats as fit in TIMING_BUDGET (MIN_REPEATS to MAX_REPEATS);
    the spread max - min of the repeats' CPU times is how far noise moved them."""
    _, first = run()
    repeats = int(np.clip(math.ceil(TIMING_BUDGET / max(first, 1e-9)), MIN_REPEATS, MAX_REPEATS))
    times = [run() for _ in range(repeats)]
    cpu = [t[0] for t in times]
    return min(cpu), min(t[1] for t in times), repeats, max(cpu) - min(cpu)


def custom_wall(scene: Scene, integrator: str, dt: float):
    sc = dataclasses.replace(scene, integrator=integrator, dt=dt)
    n = sc.steps

    def run():
        stepper = Stepper(sc)
        w0, c0 = time.perf_counter(), time.thread_time()
        stepper.advance(n)
        return time.thread_time() - c0, time.perf_counter() - w0
    return run


def custom_residual(scene: Scene, integrator: str, dt: float) -> tuple[float, float]:
    """(R(end), max |R|) J of our run at (integrator, dt): the energy the numerics made or lost."""
    from custom_sim import simulate

    from ...energy import balance
    sc = dataclasses.replace(scene, integrator=integrator, dt=dt)
    try:
        traj = simulate(sc)
    except SimulationDiverged:   # chatter the grid run does not watch: no balance to show
        return math.nan, math.nan
    r = balance(sc, traj.t, traj.states(), integrator).R
    return float(r[-1]), float(np.max(np.abs(r)))


def mujoco_residual(scene: Scene, integrator: str, dt: float) -> tuple[float, float]:
    """(R(end), max |R|) J of MuJoCo's native run at (integrator, dt), from its states (nan for
    RK4, whose stage forces the states do not carry)."""
    from mujoco_models import simulate_mujoco

    if integrator == "RK4":
        return math.nan, math.nan
    from ...energy.mujoco_side import native_from_run
    traj = simulate_mujoco(scene, integrator=integrator, dt=dt)
    r = native_from_run(scene, traj.t, traj.states(), traj.integrator, traj.meta.get("solref_mapping", "penalty")).R
    return float(r[-1]), float(np.max(np.abs(r)))


def ladder_runs(simulator: str, scene: Scene, integrator: str, ref_states: np.ndarray, scale: float,
                ladder, grid_run, wall, diverged) -> list[Run]:
    """One integrator over a ladder of steps (steps per grid interval), coarse to fine, until a
    run would exceed RUN_BUDGET: grid_run gives (states on the grid, force evaluations, ...),
    wall the timed run, `diverged` the exception of a blown-up run; each stable run's energy
    residual beside its error."""
    runs, last_time, dt_prev = [], None, None
    for n in ladder:
        dt = GRID / n
        run = Run(simulator, integrator, dt, steps_for(scene, dt))
        if last_time is not None and last_time * (dt_prev / dt) > RUN_BUDGET:
            break
        dt_prev = dt
        try:
            states, evals = grid_run(scene, integrator, dt)[:2]
        except diverged as exc:
            run.stable, run.note = False, str(exc)
            runs.append(run)
            continue
        run.stable, run.note = grid_verdict(scene, states, scale)
        run.force_evals = evals
        if run.stable:
            run.error_max, run.error_l2, run.angle_error_max = position_errors(states, ref_states)
            run.cpu_time, run.wall_time, run.repeats, run.cpu_time_spread = timed(wall(scene, integrator, dt))
            residual = custom_residual if simulator == "custom" else mujoco_residual
            run.residual_end, run.residual_max = residual(scene, integrator, dt)
            last_time = run.wall_time
            run.states = states
        runs.append(run)
    return runs


def custom_ladder(scene: Scene, integrator: str, ref_states: np.ndarray, scale: float,
                  ladder=LADDER) -> list[Run]:
    """Our integrator over the ladder."""
    return ladder_runs("custom", scene, integrator, ref_states, scale, ladder,
                       custom_grid_run, custom_wall, SimulationDiverged)


# ---------------------------------------------------------------------------------------
# MuJoCo


def mujoco_grid_run(scene: Scene, integrator: str, dt: float):
    """(states on the grid, force evaluations, wall time of the recorded C rollout)."""
    from mujoco_models import simulate_mujoco

    traj = simulate_mujoco(scene, integrator=integrator, dt=dt)
    per = int(round(GRID / dt))
    states = traj.states()[::per]
    return states[:len(grid_times(scene))], traj.force_evals, traj.wall_time


def mujoco_wall(scene: Scene, integrator: str, dt: float):
    from .benchmark import mujoco_setup

    model, data, state = mujoco_setup(scene, integrator, dt)
    n = steps_for(scene, dt)

    def run():
        import mujoco
        mujoco.mj_setState(model, data, state, mujoco.mjtState.mjSTATE_FULLPHYSICS)
        w0, c0 = time.perf_counter(), time.thread_time()
        mujoco.mj_step(model, data, nstep=n)
        return time.thread_time() - c0, time.perf_counter() - w0
    return run


def mujoco_ladder(scene: Scene, integrator: str, ref_states: np.ndarray, scale: float,
                  ladder=MUJOCO_LADDER) -> list[Run]:
    """A MuJoCo integrator over MUJOCO_LADDER (errors against our reference; the error against
    MuJoCo's own converged solution is filled in once that is known)."""
    from mujoco_models import MujocoDiverged

    return ladder_runs("mujoco", scene, integrator, ref_states, scale, ladder,
                       mujoco_grid_run, mujoco_wall, MujocoDiverged)


def mujoco_converged(scene: Scene, n: int = MUJOCO_CONVERGED_N) -> dict:
    """MuJoCo's own converged solution: RK4 at GRID / MUJOCO_CONVERGED_N, and its change from
    RK4 at twice the step (an estimate of its own error). A long scene takes a coarser step,
    halved in n until the run is predicted to fit CONVERGED_BUDGET."""
    while n > 1 and steps_for(scene, GRID / n) * MUJOCO_RK4_STEP > CONVERGED_BUDGET:
        n //= 2
    dt = GRID / n
    fine, _, wall = mujoco_grid_run(scene, MUJOCO_CONVERGED, dt)
    coarse, _, _ = mujoco_grid_run(scene, MUJOCO_CONVERGED, 2 * dt)
    change = float(np.max(np.hypot(*(fine[:, :2] - coarse[:, :2]).T)))
    return {"integrator": MUJOCO_CONVERGED, "dt": dt, "states": fine, "change_at_double_step": change,
            "wall_time": wall}


# ---------------------------------------------------------------------------------------
# The reference, with its convergence and sensitivity


def reference_task(scene: Scene, cache_dir: str | None) -> dict:
    t = grid_times(scene)
    start = time.perf_counter()
    ref = ref_mod.cached_reference(scene, t, cache_dir)
    tight = ref_mod.cached_reference(scene, t, cache_dir, rtol=ref.rtol / 100, atol=ref.atol / 100)
    x0, y0 = scene.initial.position
    nudged = dataclasses.replace(scene, initial=dataclasses.replace(scene.initial, position=(x0, y0 + PERTURBATION)))
    twin = ref_mod.cached_reference(nudged, t, cache_dir)
    change = np.hypot(*(ref.states[:, :2] - tight.states[:, :2]).T)
    growth = np.hypot(*(ref.states[:, :2] - twin.states[:, :2]).T) / PERTURBATION
    return {
        "states": ref.states,
        "rtol": ref.rtol, "atol": ref.atol, "method": ref.method,
        "nfev": ref.nfev, "segments": ref.segments, "switches": ref.switches,
        "solve_time": ref.wall_time,
        "change_at_tighter_tolerance": float(change.max()),
        "amplification": float(growth.max()),
        "amplification_time": float(t[int(np.argmax(growth))]),
        "energy_scale": energy_scale(ref.states, scene),
        "wall_time": time.perf_counter() - start,
    }


# ---------------------------------------------------------------------------------------
# Orchestration


def _task(kind: str, scene: Scene, integrator: str | None, ref: dict | None, cache_dir, ladders=None,
          simulator=None):
    """One unit of work in a worker process (simulator: the user's, for the "yours" kinds)."""
    ladders = ladders or {}
    if kind == "reference":
        return reference_task(scene, cache_dir)
    if kind == "custom":
        return custom_ladder(scene, integrator, ref["states"], ref["energy_scale"],
                             ladders.get("custom", LADDER))
    if kind == "mujoco":
        return mujoco_ladder(scene, integrator, ref["states"], ref["energy_scale"],
                             ladders.get("mujoco", MUJOCO_LADDER))
    if kind == "mujoco_converged":
        return mujoco_converged(scene, ladders.get("mujoco_converged", MUJOCO_CONVERGED_N))
    if kind == "stability_custom":
        from .stability_search import custom_limit
        return custom_limit(scene, integrator, ref["energy_scale"])
    if kind == "stability_mujoco":
        from .stability_search import mujoco_limit
        return mujoco_limit(scene, integrator, ref["energy_scale"])
    if kind == "yours":
        from .yours import yours_ladder
        return yours_ladder(simulator, scene, integrator, ref["states"], ref["energy_scale"],
                            ladders.get("yours", LADDER))
    if kind == "stability_yours":
        from .yours import yours_limit
        return yours_limit(simulator, scene, integrator, ref["energy_scale"])
    raise ValueError(kind)


# Rough relative cost of each kind of task, to start the long ones first.
_WEIGHT = {"mujoco_converged": 40, "yours": 20, "mujoco": 10, "stability_yours": 8, "custom": 5,
           "stability_mujoco": 3, "stability_custom": 1}


def run_sweep(scenes: list[Scene], cache_dir: str | Path | None = None, jobs: int | None = None,
              mujoco: bool = True, stability: bool = True, progress=None,
              ladders: dict | None = None, scheduler: str | None = None, simulator=None) -> list[SceneSweep]:
    """Measure every scene on the executor (compare/executor/): a local Dask cluster of `jobs`
    worker processes (a process pool when Dask is not installed), or the Dask cluster at
    `scheduler`; progress: show progress bars when given
    (any true value); ladders: {"custom": steps per grid interval, "mujoco": ...,
    "mujoco_converged": n, "yours": ...} to replace LADDER, MUJOCO_LADDER and MUJOCO_CONVERGED_N
    (shorter runs in tests); simulator: the user's (compare/usersim), run beside custom_sim and
    MuJoCo with each integrator it does (tools/accuracy/yours.py), its runs and limits "yours"."""
    from ...executor import Task, make_executor

    cache = None if cache_dir is None else str(cache_dir)
    tasks, theirs = [], {}
    for s in scenes:
        if simulator is not None:
            from .yours import integrators_of
            theirs[s.name] = integrators_of(simulator, s)
            tasks += [("yours", s, name) for name in theirs[s.name]]
            if stability:
                tasks += [("stability_yours", s, name) for name in theirs[s.name]]
        tasks += [("custom", s, name) for name in INTEGRATORS]
        if stability:
            tasks += [("stability_custom", s, name) for name in INTEGRATORS]
        if mujoco:
            tasks += [("mujoco", s, name) for name in MUJOCO]
            tasks.append(("mujoco_converged", s, None))
            if stability:
                tasks += [("stability_mujoco", s, name) for name in MUJOCO]
    tasks.sort(key=lambda t: -_WEIGHT[t[0]] * t[1].duration)
    with make_executor("auto", scheduler=scheduler,
                       workers=None if scheduler else (jobs or os.cpu_count() or 1)) as engine:
        references = engine.run(_task, [Task(s.name, ("reference", s, None, None, cache)) for s in scenes],
                                desc="references", progress=bool(progress))
        keyed = {f"{kind}-{s.name}-{integ}": (kind, s.name, integ) for kind, s, integ in tasks}
        done = engine.run(_task, [Task(f"{kind}-{s.name}-{integ}", (kind, s, integ, references[s.name], cache, ladders,
                                                                    simulator if kind.endswith("yours") else None))
                                  for kind, s, integ in tasks], desc="sweep", progress=bool(progress))
    results = {keyed[key]: value for key, value in done.items()}
    out = []
    for s in scenes:
        ref = references[s.name]
        runs = [r for integ in INTEGRATORS for r in results[("custom", s.name, integ)]]
        conv = {}
        if mujoco:
            conv = results[("mujoco_converged", s.name, None)]
            for integ in MUJOCO:
                for r in results[("mujoco", s.name, integ)]:
                    if r.stable:
                        r.error_max_self, r.error_l2_self, _ = position_errors(r.states, conv["states"])
                    runs.append(r)
            conv = dict(conv)
            conv["error_max"], conv["error_l2"], _ = position_errors(conv["states"], ref["states"])
        limits = []
        if stability:
            limits = [results[("stability_custom", s.name, i)] for i in INTEGRATORS]
            if mujoco:
                limits += [results[("stability_mujoco", s.name, i)] for i in MUJOCO]
        yours = {}
        if simulator is not None:
            yours = {"label": simulator.label, "declared": theirs[s.name] != list(INTEGRATORS),
                     "integrators": [], "skipped": {}}
            for integ in theirs[s.name]:
                ladder, why = results[("yours", s.name, integ)]
                if why:
                    yours["skipped"][integ] = why
                    continue
                yours["integrators"].append(integ)
                runs += ladder
                if stability:
                    limits.append(results[("stability_yours", s.name, integ)])
        out.append(SceneSweep(s, ref, runs, conv, limits, yours))
    return out


# ---------------------------------------------------------------------------------------
# The answer to "what is the cheapest way to reach 1 mm here?": ranked by force evaluations
# (then steps), counted, not timed; times only beside them (docs/physics.md#8-accuracy-against-cost)


def _error(run: Run, self_error: bool) -> float:
    return run.error_max_self if self_error else run.error_max


def within(run: Run, runs: list[Run], target: float = TARGET_ERROR, self_error: bool = False) -> bool:
    """run meets the target, and so does every finer stable rung of its integrator: with the
    contact switches falling anywhere inside a step, a fixed step's error jumps about as h
    shrinks, and one lucky step size is not an answer."""
    finer = [r for r in runs if r.simulator == run.simulator and r.integrator == run.integrator
             and r.stable and r.dt <= run.dt]
    return all(_error(r, self_error) <= target for r in finer)


def cost(run: Run) -> tuple[int, int, float]:
    """The ranking key: (force evaluations, steps, -dt); counted, so the same on every rerun."""
    return (run.force_evals, run.steps, -run.dt)


def qualifying(runs: list[Run], target: float = TARGET_ERROR, self_error: bool = False) -> list[Run]:
    """The stable runs `within` target (m)."""
    return [r for r in runs if r.stable and math.isfinite(_error(r, self_error))
            and within(r, runs, target, self_error)]


def cheapest(runs: list[Run], target: float = TARGET_ERROR, self_error: bool = False) -> Run | None:
    """The run with the fewest force evaluations (then steps) that is `within` target (m)."""
    ok = qualifying(runs, target, self_error)
    return min(ok, key=cost) if ok else None


def ranking(runs: list[Run], target: float = TARGET_ERROR, self_error: bool = False) -> list[Run]:
    """Each integrator's cheapest run within target, ordered by cost (fewest force evaluations
    first): one run per integrator and simulator."""
    best = {}
    for r in qualifying(runs, target, self_error):
        key = (r.simulator, r.integrator)
        if key not in best or cost(r) < cost(best[key]):
            best[key] = r
    return sorted(best.values(), key=cost)


def clearly_faster(a: Run, b: Run) -> bool:
    """a took less CPU time than b by more than the spread of either's repeats (False when a
    spread is unknown): only then does the time tell the two apart."""
    spreads = (a.cpu_time_spread, b.cpu_time_spread)
    if not all(math.isfinite(x) for x in spreads):
        return False
    return b.cpu_time - a.cpu_time > max(spreads)


def fastest(runs: list[Run]) -> tuple[Run | None, list[Run]]:
    """Among runs (e.g. a ranking): the one with the least CPU time, and the others that time
    cannot tell from it (not clearly slower)."""
    if not runs:
        return None, []
    win = min(runs, key=lambda r: r.cpu_time)
    return win, [r for r in runs if r is not win and not clearly_faster(win, r)]


def best_error(runs: list[Run], self_error: bool = False) -> Run | None:
    ok = [r for r in runs if r.stable and math.isfinite(_error(r, self_error))]
    return min(ok, key=lambda r: _error(r, self_error)) if ok else None
