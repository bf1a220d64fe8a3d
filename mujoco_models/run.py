"""Run a scene's twin in MuJoCo and return the same Trajectory type as custom_sim.simulate.

MuJoCo's own loop (mujoco.rollout) takes all the steps in C; the timed call comes after a
short warm-up rollout. Each output row of rollout is MuJoCo's full physics state after a step,
[time, qpos (nq), qvel (nv), ...] (fields in the order of their mjtState bits), which frames.py
turns into our [x, y, theta, vx, vy, omega]. The energy is the trajectory files' formula on that
state (custom_sim.energy: kinetic + m g y + sum of k d^2 / 2 over our contact points).
"""
from __future__ import annotations

import time

import mujoco
import numpy as np
from mujoco import rollout

from custom_sim.energy import energy_parts
from custom_sim.integrators import first_unhealthy
from custom_sim.scene import Scene
from custom_sim.simulate import blowup_guard
from custom_sim.trajectory import Trajectory

from .approximations import approximations
from .frames import joint_count, states_from_q
from .geometry import describe
from .spec import build_twin

STAGES = {"Euler": 1, "implicit": 1, "implicitfast": 1, "RK4": 4}  # force evaluations per mj_step
WARMUP_STEPS = 200
FULL_STATE = mujoco.mjtState.mjSTATE_FULLPHYSICS


class MujocoDiverged(RuntimeError):
    """The twin's state blew up: MuJoCo flagged a bad acceleration (and reset the state), or
    the state left the range custom_sim's guard allows (non-finite, too far, too fast, or
    more energy than the scene ever had). The run is void."""


def setup_rollout(scene: Scene, solref: str | None = None, integrator: str | None = None,
                  dt: float | None = None):
    """(twin, model, data, start state, steps): everything mujoco.rollout needs for the scene,
    with the data at the scene's initial state (keyframe 0) and steps = duration / dt."""
    twin = build_twin(scene, solref, integrator=integrator, dt=dt)
    model = twin.spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    start_state = np.empty(mujoco.mj_stateSize(model, FULL_STATE))
    mujoco.mj_getState(model, data, start_state, FULL_STATE)
    return twin, model, data, start_state, max(1, int(round(scene.duration / twin.dt)))


def simulate_mujoco(scene: Scene, solref: str | None = None, integrator: str | None = None,
                    dt: float | None = None) -> Trajectory:
    """Run the scene's twin for its duration. solref: penalty | physical | seed; integrator:
    Euler | RK4 | implicit | implicitfast; dt (s). Defaults: the scene's [mujoco] table."""
    twin, model, data, start_state, n = setup_rollout(scene, solref, integrator, dt)
    rollout.rollout(model, data, start_state, nstep=min(n, WARMUP_STEPS))
    begin = time.perf_counter()
    rows, _ = rollout.rollout(model, data, start_state, nstep=n)
    wall = time.perf_counter() - begin
    nq = joint_count(twin.props)
    rows = np.vstack([start_state[None, :], rows[0]])
    states = states_from_q(twin.props, rows[:, 1:1 + nq], rows[:, 1 + nq:1 + 2 * nq])
    what = f"{scene.name}: MuJoCo ({twin.integrator}, dt = {twin.dt:g} s, solref {twin.contact.mapping})"
    if data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number:
        raise MujocoDiverged(f"{what} met a bad acceleration and reset the state; try a smaller dt")
    step = first_unhealthy(np.ascontiguousarray(states), blowup_guard(scene, twin.props, states[0], applied_input=False))
    if step >= 0:
        raise MujocoDiverged(f"{what} blew up at step {step} (t = {step * twin.dt:.6g} s): the state left "
                             f"custom_sim's healthy range; try a smaller dt")
    ke, pe, ce = energy_parts(scene, twin.props, states)
    params = twin.contact
    meta = {
        "solref_mapping": params.mapping,
        "solref": list(params.solref),
        "solimp": list(params.solimp),
        "solreffriction": list(params.solreffriction),
        "impratio": params.impratio,
        "friction_damping": params.friction_damping,
        "A_hat": params.a_hat,
        "contact_pairs": twin.n_pairs,
        "condim": twin.condim,
        "friction": list(twin.friction),
        "cone": twin.cone,
        "contact": scene.has("contact"),
        "gravity": list(model.opt.gravity),
        "geometry": describe(scene.body, twin.props),
        "inertia": list(twin.inertial.diaginertia),
        "approximations": approximations(twin),
        "ns_per_step": 1e9 * wall / n,
    }
    return Trajectory(
        t=np.arange(n + 1) * twin.dt,
        x=states[:, 0], y=states[:, 1], theta=states[:, 2],
        vx=states[:, 3], vy=states[:, 4], omega=states[:, 5],
        energy_kinetic=ke, energy_gravity=pe, energy_contact=ce,
        simulator="mujoco", integrator=twin.integrator, dt=twin.dt,
        force_evals=n * STAGES[twin.integrator], wall_time=wall, meta=meta,
    )
