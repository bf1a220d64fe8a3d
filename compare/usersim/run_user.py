"""A user's run as the harness's Trajectory, beside custom_sim's and MuJoCo's."""
from __future__ import annotations

import numpy as np

from custom_sim import Scene, Trajectory, mass_properties
from custom_sim.energy import energy_parts

from .loader import UserRun


def as_trajectory(run: UserRun, scene: Scene, label: str, kind: str) -> Trajectory:
    """The states with the harness's energy (the scene model's formula on the user's states);
    an energy the user supplied replaces the total: kinetic and gravitational stay the
    harness's, the contact part is the remainder (meta says so)."""
    states = run.states
    ke, pe, ce = energy_parts(scene, mass_properties(scene.body), states)
    meta = {"kind": kind, "label": label, "energy_source": "harness",
            "wall_time_known": run.wall_time is not None, "written_digits": run.written_digits,
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


def run_user(simulator, scene: Scene) -> Trajectory:
    """Run `scene` with the simulator under test (from load_simulator). Raises UserCodeError
    (bad input) for any fault of the user's code or files."""
    return as_trajectory(simulator.run(scene), scene, simulator.label, simulator.kind)
