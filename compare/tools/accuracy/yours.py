"""The simulator a user brings (--sim) in the sweep: its runs over the ladder, its stable step.

    integrators_of(sim, scene)                the integrators it is run with
    yours_ladder(sim, scene, integrator, ...) -> [Run]   error against the reference, wall and CPU time
    yours_limit(sim, scene, integrator, scale) -> StabilityLimit   the same bisection as custom_sim's
    run_verdict(scene, states, scale)         stable as custom_sim's search calls it, from states alone

`sim` is anything with run(scene) -> UserRun and integrator_for(scene) (compare/usersim: a
StepFunction, a WholeFunction, a process). Every run goes through sim.run, which imports the
module afresh (as `run` does), so a step that keeps state starts each trial clean; with --whole
the scene dict's dt is the rung's. The user's code counts no force evaluations: its runs carry
none (None in results.json), never an invented figure.
"""
from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass

import numpy as np
from numba import njit

from custom_sim import INTEGRATORS, Scene, mass_properties
from custom_sim.chatter import FLAG, QUANTITY, WATCH_COLUMNS, chattering_point
from custom_sim.energy import energy_parts
from custom_sim.integrators import first_unhealthy
from custom_sim.model import build_model
from custom_sim.runner import blowup_guard

from .stability_search import (
    MIN_STEP,
    StabilityLimit,
    energy_verdict,
    largest_stable_step,
)
from .workprecision import (
    GRID,
    LADDER,
    MAX_REPEATS,
    MIN_REPEATS,
    RUN_BUDGET,
    TIMING_BUDGET,
    Run,
    grid_times,
    grid_verdict,
    position_errors,
    steps_for,
)

YOURS = "yours"          # the simulator's name in the runs, the limits and results.json
# The stability search's finest step for the user's code: a run of at most this many steps (a
# Python step of 10-100 us makes it 2-20 s); custom_sim's compiled search goes to MIN_STEP.
MAX_STEPS = 200_000


def integrators_of(sim, scene: Scene) -> list[str]:
    """The integrators the user's code is run with: the one its module declares (INTEGRATOR),
    else each of custom_sim's, handed to it as scene["integrator"]."""
    declared = [sim.integrator_for(dataclasses.replace(scene, integrator=i)) for i in INTEGRATORS]
    return list(INTEGRATORS) if declared == list(INTEGRATORS) else [declared[0]]


def variant(scene: Scene, integrator: str, dt: float) -> Scene:
    """The scene as the user's code receives it on a rung: that integrator (when the harness
    knows it) and step dt (s)."""
    return dataclasses.replace(scene, integrator=integrator if integrator in INTEGRATORS else scene.integrator, dt=dt)


@dataclass(frozen=True)
class Trial:
    """One run of the user's code: states (steps + 1, 6), or None with `fault` (its one line)
    or `skip` (why the code does not do this integrator or scene: NotImplementedError, SHAPES, a
    process's skip); cpu and wall time (s) of the call, from the fresh import to the last state. A
    wrong return met after the first steps (the commands probe those) is kept as a fault too: the
    run's note names it."""

    states: np.ndarray | None
    fault: str
    cpu: float
    wall: float
    skip: str = ""

    @property
    def skipped(self) -> bool:
        return bool(self.skip)

    @property
    def reason(self) -> str:
        """What the code said when it declined."""
        return self.skip


def trial(sim, scene: Scene) -> Trial:
    """sim.run(scene), timed; a fault of the user's run (UserFault) is kept as its line. The CPU
    time is this thread's: for a simulator in another process it is its wall time."""
    from ...usersim.errors import SceneSkipped, UserCodeError, UserFault

    w0, c0 = time.perf_counter(), time.thread_time()
    try:
        run = sim.run(scene)
    except SceneSkipped as exc:
        return Trial(None, "", math.nan, math.nan, skip=exc.reason)
    except (UserFault, UserCodeError) as exc:
        return Trial(None, str(exc).splitlines()[0], math.nan, math.nan)
    cpu, wall = time.thread_time() - c0, time.perf_counter() - w0
    if getattr(sim, "kind", "") not in ("step", "whole"):
        cpu = wall
    return Trial(run.states, "", cpu, wall)


@njit(cache=True)
def _first_chatter(model, points, states, watch):
    """The first row of states (T, 6) at which custom_sim's chatter tracker flags a point, or -1."""
    for i in range(1, states.shape[0]):
        if chattering_point(model, points, states[i], watch) >= 0:
            return i
    return -1


def blowup_or_chatter(scene: Scene, states: np.ndarray) -> str:
    """Why a run is unstable by custom_sim's own stops (its healthy range, then its chatter
    tracker, custom_sim/chatter.py), found in the states after the fact, in the words
    stability_search.failure_reason uses; "" when neither fires."""
    props = mass_properties(scene.body)
    bad = int(first_unhealthy(states, blowup_guard(scene, props, states[0], applied_input=False)))
    model, points = build_model(scene, props)
    watch = np.zeros((len(points), WATCH_COLUMNS))
    chatter = int(_first_chatter(model, points, np.ascontiguousarray(states), watch)) if model.contact else -1
    if bad >= 0 and (chatter < 0 or bad <= chatter):
        return f"diverged at step {bad}"
    if chatter >= 0:
        p = int(np.flatnonzero(watch[:, FLAG])[0])
        return f"chatter: point {p} {QUANTITY[float(watch[p, FLAG])]} at step {chatter}"
    return ""


def run_verdict(scene: Scene, states: np.ndarray, scale: float) -> tuple[bool, str]:
    """(stable, reason) of a user's run as custom_stable decides custom_sim's: no blow-up, no
    chatter, no energy growth at quiet samples (scale: the motion's largest kinetic energy, J)."""
    why = blowup_or_chatter(scene, states)
    if why:
        return False, why
    ke, pe, ce = energy_parts(scene, mass_properties(scene.body), states)
    return energy_verdict(ke + pe + ce, ce, scale)


def yours_stable(sim, scene: Scene, integrator: str, h: float, scale: float) -> tuple[bool, str]:
    """Is the user's code stable on the scene with step h (s)? A fault of its run (an exception,
    a NaN) is a blow-up, named by its line."""
    sc = variant(scene, integrator, h)
    t = trial(sim, sc)
    if t.states is None:
        return False, f"blow-up: {t.fault}"
    return run_verdict(sc, t.states, scale)


def yours_limit(sim, scene: Scene, integrator: str, scale: float, **bisection) -> StabilityLimit:
    """The largest stable step of the user's code: stability_search's bisection and scan, the
    same as custom_sim's, down to no step finer than MAX_STEPS allow. An integrator its code
    does not do (NotImplementedError) gives h_max nan and the reason."""
    first = trial(sim, variant(scene, integrator, scene.dt))
    if first.skipped:
        return StabilityLimit(YOURS, integrator, math.nan, reason=first.reason)
    bisection.setdefault("min_step", max(MIN_STEP, scene.duration / MAX_STEPS))
    return largest_stable_step(lambda h: yours_stable(sim, scene, integrator, h, scale), scene.dt,
                               simulator=YOURS, integrator=integrator, **bisection)


def residual(scene: Scene, states: np.ndarray, integrator: str) -> tuple[float, float]:
    """(R(end), max |R|) J of the user's run (compare/energy), its work by the declared
    integrator's rule (the trapezoid rule for one the harness does not know)."""
    from ...energy import balance
    r = balance(scene, np.arange(len(states)) * scene.dt, states, integrator if integrator in INTEGRATORS else None).R
    return float(r[-1]), float(np.max(np.abs(r)))


def yours_ladder(sim, scene: Scene, integrator: str, ref_states: np.ndarray, scale: float,
                 ladder=LADDER) -> tuple[list[Run], str]:
    """The user's code over the ladder (dt = GRID / n), coarse to fine, until a run would exceed
    RUN_BUDGET: ([Run], "") or ([], reason) when it does not do this integrator (raised
    NotImplementedError). Each run is timed again from a fresh import until the timings add up
    to TIMING_BUDGET (MIN_REPEATS to MAX_REPEATS timings, the first run's included)."""
    runs, last, dt_prev = [], None, None
    for n in ladder:
        dt = GRID / n
        if last is not None and last * (dt_prev / dt) > RUN_BUDGET:
            break
        dt_prev = dt
        sc = variant(scene, integrator, dt)
        run = Run(YOURS, integrator, dt, steps_for(scene, dt), force_evals=None)
        first = trial(sim, sc)
        if first.skipped:
            return [], first.reason
        if first.states is None:
            run.stable, run.note = False, f"blow-up: {first.fault}"
            runs.append(run)
            continue
        why = blowup_or_chatter(sc, first.states)
        grid = first.states[::n][:len(grid_times(scene))]
        run.stable, run.note = (False, why) if why else grid_verdict(scene, grid, scale)
        if run.stable:
            run.error_max, run.error_l2, run.angle_error_max = position_errors(grid, ref_states)
            timings = [first]
            while len(timings) < MIN_REPEATS or (sum(t.wall for t in timings) < TIMING_BUDGET
                                                 and len(timings) < MAX_REPEATS):
                again = trial(sim, sc)
                if again.states is None:
                    break
                timings.append(again)
            cpu = [t.cpu for t in timings]
            run.cpu_time, run.wall_time = min(cpu), min(t.wall for t in timings)
            run.repeats, run.cpu_time_spread = len(timings), max(cpu) - min(cpu)
            run.residual_end, run.residual_max = residual(sc, first.states, integrator)
            run.states = grid
            last = run.wall_time
        runs.append(run)
    return runs, ""
