"""Run a scene: the seed's loop (contact points, contact forces, integrate), compiled.

    simulate(scene) -> Trajectory      the whole run, every step recorded
    Stepper(scene).advance(n, force)   a running simulation driven step by step (the game)
"""
from __future__ import annotations

import math
import time

import numpy as np

from .bodies import mass_properties
from .chatter import FLAG, QUANTITY, WATCH_COLUMNS, unsolved_stick
from .energy import energy_parts
from .integrators import (FORCE_EVALS, INTEGRATORS, NEWTON_FAILS, NEWTON_ITERS, NEWTON_MAX,
                          integrate)
from .model import build_model, initial_state
from scene_types.errors import Diverged
from scene_types.schema import Scene
from scene_types.state import STATE_COMPONENTS
from .stability import stable_step
from scene_types.trajectory import Trajectory

# A state beyond these has blown up: far above anything a scene's energy allows (the
# fastest stress scene hits the ground at 30 m/s and spins at 100 rad/s).
POSITION_LIMIT = 1e6   # m
SPEED_LIMIT = 1e5      # m/s and rad/s
# Without applied input every effect conserves or dissipates energy, so kinetic plus
# gravitational energy above the lowest pose never exceeds its start E0. Explicit Euler gains
# some per bounce (a few per cent on elastic_bounce); ten times E0 is only reached by an
# instability (an over-stiff contact that flings the body off in one step).
ENERGY_GROWTH_LIMIT = 10.0
# J: the budget's floor, for a body that starts at rest on its lowest pose (E0 = 0).
ENERGY_FLOOR = 1.0


def blowup_guard(scene: Scene, props, z0: np.ndarray, applied_input: bool) -> tuple:
    """The thresholds is_healthy checks (see integrators.py); no energy limit under input."""
    g = scene.g if scene.has("gravity") else 0.0
    y_low = -float(np.max(np.hypot(props.points[:, 0], props.points[:, 1])))  # COM on the ground
    mass, inertia = props.mass, props.inertia
    x, y, theta, vx, vy, om = z0
    e0 = 0.5 * mass * (vx * vx + vy * vy) + 0.5 * inertia * om * om + mass * g * (y - y_low)
    limit = np.inf if applied_input else ENERGY_GROWTH_LIMIT * max(e0, ENERGY_FLOOR * mass)
    return (mass, inertia, g, y_low, limit, POSITION_LIMIT, SPEED_LIMIT)


class SimulationDiverged(Diverged):
    """The state left the healthy range: carries the step, the state and a stable step."""

    def __init__(self, scene: Scene, integrator: str, dt: float, step: int, state: np.ndarray):
        self.scene, self.integrator, self.dt, self.step, self.state = scene, integrator, dt, step, state
        self.stable_dt = stable_step(scene, integrator)
        super().__init__(f"{scene.name}: {integrator} {self.what()} at step {step} (t = {step * dt:.6g} s) "
                         f"with dt = {dt:g} s; state {state_text(state)}. {advice(self.stable_dt, scene, integrator)}")

    def what(self) -> str:
        return "diverged"


class SimulationChattered(SimulationDiverged):
    """A contact point chattered (custom_sim/chatter.py): a bounded instability, reported like a
    blow-up. point: the contact point's index in mass_properties(scene.body).points;
    quantity: "slip velocity" or "normal velocity"."""

    def __init__(self, scene: Scene, integrator: str, dt: float, step: int, state: np.ndarray,
                 point: int, quantity: str):
        self.point, self.quantity = point, quantity
        super().__init__(scene, integrator, dt, step, state)

    def what(self) -> str:
        return f"chattered (contact point {self.point}: its {self.quantity} flips sign every step)"


def advice(stable_dt, scene: Scene | None = None, integrator: str | None = None) -> str:
    """The sentence that says which step to take instead: theory's stable step, or, where it is
    0 for the law (a bare sign law under an explicit method), that no step is (its reason); where
    theory puts no limit (inf: implicit Euler), that, and under a bare sign law why implicit Euler
    chatters all the same (chatter.unsolved_stick)."""
    if stable_dt == 0.0 and "no step size is stable" in stable_dt.reason:
        return f"No step size is stable for this law: {stable_dt.reason} (see docs/contact-laws.md)."
    if stable_dt == math.inf:
        why = unsolved_stick(scene, integrator) if scene is not None else None
        if why:
            return f"{why[0].upper()}{why[1:]} (see docs/contact-laws.md)."
        return "Theory puts no limit on the step for this scene (see custom_sim/stability.py)."
    return (f"Theory gives a stable step below {stable_dt:.3g} s for this scene "
            f"(see custom_sim/stability.py).")


def state_text(state) -> str:
    return ", ".join(f"{n}={v:.4g}" for n, v in zip(STATE_COMPONENTS, state))


def new_watch(props) -> np.ndarray:
    """A fresh chatter tracker for the body's contact points (see chatter.py)."""
    return np.zeros((len(props.points), WATCH_COLUMNS))


def failure(scene: Scene, step: int, state: np.ndarray, watch: np.ndarray) -> SimulationDiverged:
    """The exception for a run that integrate stopped at `step`: chatter if a point is flagged."""
    flagged = np.flatnonzero(watch[:, FLAG]) if len(watch) else np.zeros(0, dtype=np.int64)
    if len(flagged):
        p = int(flagged[0])
        return SimulationChattered(scene, scene.integrator, scene.dt, step, state, p,
                                   QUANTITY[float(watch[p, FLAG])])
    return SimulationDiverged(scene, scene.integrator, scene.dt, step, state)


def _external(external, n: int) -> np.ndarray:
    if external is None:
        return np.zeros((1, 3))
    ext = np.ascontiguousarray(external, dtype=np.float64)
    if ext.shape == (3,):
        return ext.reshape(1, 3)
    if ext.shape != (n, 3):
        raise ValueError(f"external force must have shape (3,) or ({n}, 3), got {ext.shape}")
    return ext


def simulate(scene: Scene, external=None) -> Trajectory:
    """Run `scene` for its duration with its integrator; external = applied (Fx N, Fy N, tau N m),
    constant (3,) or per step (steps, 3). Raises SimulationDiverged if the state blows up,
    SimulationChattered (a SimulationDiverged) if a contact point chatters."""
    method = INTEGRATORS[scene.integrator]
    props = mass_properties(scene.body)
    model, points = build_model(scene, props)
    n = scene.steps
    ext = _external(external, n)
    z = initial_state(scene)
    out = np.empty((n + 1, 6))
    out[0] = z
    counters = np.zeros(4, dtype=np.int64)
    guard = blowup_guard(scene, props, z, applied_input=bool(np.any(ext != 0.0)))
    watch = new_watch(props)
    # compile (or load from cache) before timing: a run of zero steps
    integrate(model, points, z.copy(), scene.dt, 0, method.code, ext, out[1:1], counters, guard, watch)
    start = time.perf_counter()
    failed = integrate(model, points, z, scene.dt, n, method.code, ext, out[1:], counters, guard, watch)
    wall = time.perf_counter() - start
    if failed >= 0:
        raise failure(scene, int(failed), z.copy(), watch)
    ke, pe, ce = energy_parts(scene, props, out)
    return Trajectory(
        t=np.arange(n + 1) * scene.dt,
        x=out[:, 0], y=out[:, 1], theta=out[:, 2], vx=out[:, 3], vy=out[:, 4], omega=out[:, 5],
        energy_kinetic=ke, energy_gravity=pe, energy_contact=ce,
        simulator="custom", integrator=scene.integrator, dt=scene.dt,
        force_evals=int(counters[FORCE_EVALS]), newton_iterations=int(counters[NEWTON_ITERS]),
        wall_time=wall,
        meta={"newton_max_iterations": int(counters[NEWTON_MAX]),
              "newton_unconverged_steps": int(counters[NEWTON_FAILS])},
    )


class Stepper:
    """A simulation advanced a few steps at a time with a chosen applied force (the game's loop).

    state: [x, y, theta, vx, vy, omega]; steps: steps taken so far. watch_chatter: stop on
    chatter (custom_sim/chatter.py) as on a blow-up; False only for a loop that must go on.
    """

    def __init__(self, scene: Scene, watch_chatter: bool = True):
        self.scene = scene
        self.props = mass_properties(scene.body)
        self.model, self.points = build_model(scene, self.props)
        self.method = INTEGRATORS[scene.integrator]
        self.state = initial_state(scene)
        self.steps = 0
        self.counters = np.zeros(4, dtype=np.int64)
        self.guard = blowup_guard(scene, self.props, self.state, applied_input=True)
        self.watch = new_watch(self.props) if watch_chatter else np.empty((0, WATCH_COLUMNS))
        self._none = np.empty((0, 6))

    def advance(self, n: int, force=(0.0, 0.0, 0.0)) -> np.ndarray:
        """Take n steps with the applied (Fx N, Fy N, tau N m) held constant; returns the state."""
        ext = np.asarray(force, dtype=np.float64).reshape(1, 3)
        failed = integrate(self.model, self.points, self.state, self.scene.dt, n, self.method.code,
                           ext, self._none, self.counters, self.guard, self.watch)
        if failed >= 0:
            raise failure(self.scene, self.steps + int(failed), self.state.copy(), self.watch)
        self.steps += n
        return self.state

    def reset(self, state) -> None:
        self.state = np.array(state, dtype=np.float64)
        self.watch[:] = 0.0
        self.steps = 0
