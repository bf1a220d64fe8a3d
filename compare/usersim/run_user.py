"""A user's run as the harness's Trajectory, beside custom_sim's and MuJoCo's."""
from __future__ import annotations

import numpy as np

from custom_sim import Scene, Trajectory, mass_properties, stable_step
from custom_sim.energy import energy_parts
from custom_sim.integrators import first_unhealthy
from custom_sim.runner import blowup_guard, state_text

from .errors import UserDiverged
from .loader import UserRun


def as_trajectory(run: UserRun, scene: Scene, label: str, kind: str) -> Trajectory:
    """The states with the harness's energy (the scene model's formula on the user's states);
    an energy the user supplied replaces the total: kinetic and gravitational stay the
    harness's, the contact part is the remainder (meta says so)."""
    states = run.states
    ke, pe, ce = energy_parts(scene, mass_properties(scene.body), states)
    meta = {"kind": kind, "label": label, "energy_source": "harness",
            "wall_time_known": run.wall_time is not None, "rounding": run.rounding,
            "integrator_declared": run.integrator}
    if run.energy is not None:
        ce = run.energy - ke - pe
        meta["energy_source"] = "user"
    return Trajectory(
        t=np.arange(len(states)) * scene.dt,
        x=states[:, 0], y=states[:, 1], theta=states[:, 2],
        vx=states[:, 3], vy=states[:, 4], omega=states[:, 5],
        energy_kinetic=ke, energy_gravity=pe, energy_contact=ce,
        simulator="user", integrator=run.integrator, dt=scene.dt,
        force_evals=0, wall_time=run.wall_time or 0.0, meta=meta)


def check_healthy(run: UserRun, scene: Scene, label: str) -> None:
    """UserDiverged where the user's states leave custom_sim's healthy range (a position or
    speed beyond its limits, or more energy than the scene could ever have), with the step, the
    state and the step custom_sim's theory calls stable for the integrator declared."""
    states = run.states
    bad = int(first_unhealthy(states, blowup_guard(scene, mass_properties(scene.body), states[0],
                                                   applied_input=False)))
    if bad < 0:
        return
    try:
        integrator, step = run.integrator, stable_step(scene, run.integrator)
    except (KeyError, ValueError):
        integrator, step = scene.integrator, stable_step(scene)
    if step == float("inf"):
        limit = f"; for {integrator} custom_sim's theory puts no limit on the step for this scene"
    elif step > 0.0:
        limit = f"; for {integrator} custom_sim's theory gives a stable step below {step:.3g} s for this scene"
    else:
        limit = f"; for {integrator} no step is stable for this scene: {step.reason}"
    raise UserDiverged(f"{label} diverged at step {bad} (t = {bad * scene.dt:.6g} s, dt = {scene.dt:g} s): "
                       f"state {state_text(states[bad])} is beyond the healthy range (|x|, |y| up to 1e6 m, "
                       f"speeds up to 1e5, energy at most 10 times the start){limit}")


def run_user(simulator, scene: Scene) -> Trajectory:
    """Run `scene` with the simulator under test (from load_simulator). Raises UserCodeError
    (bad input) for a fault of the protocol, UserFault for a fault of this scene's run."""
    run = simulator.run(scene)
    check_healthy(run, scene, simulator.label)
    return as_trajectory(run, scene, simulator.label, simulator.kind)
