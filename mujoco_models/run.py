"""Run a scene's twin in MuJoCo and return the same Trajectory type as custom_sim.simulate.

MuJoCo's own loop (mujoco.rollout) takes all the steps in C; the timed call comes after a
short warm-up rollout. Each output row of rollout is MuJoCo's full physics state after a step,
[time, qpos (nq), qvel (nv), ...] (fields in the order of their mjtState bits), which frames.py
turns into our [x, y, theta, vx, vy, omega]. The energy is the trajectory files' formula (docs/report-files.md) on MuJoCo's
state, from MuJoCo's own sensors (energy.py: its kinetic and potential energy, and k d^2 / 2
over its contact distances). A run is void when MuJoCo flags a bad acceleration or the
twin's own guard (guard.py) finds the state blown up.
"""
from __future__ import annotations

import time

import mujoco
import numpy as np
from mujoco import rollout

from scene_types.errors import Diverged
from scene_types.schema import Scene
from scene_types.trajectory import Trajectory

from .approximations import approximations
from .energy import energy_parts, final_sensors
from .frames import joint_count, states_from_q
from .geometry import describe
from .guard import first_blowup
from .sites import contact_below_site
from .spec import Twin, compiled_twin

STAGES = {"Euler": 1, "implicit": 1, "implicitfast": 1, "RK4": 4}  # force evaluations per mj_step
WARMUP_STEPS = 200
FULL_STATE = mujoco.mjtState.mjSTATE_FULLPHYSICS


class MujocoDiverged(Diverged):
    """The twin's state blew up: MuJoCo flagged a bad acceleration (and reset the state), or
    the state left the range the twin's guard allows (guard.py: non-finite, too far, too fast,
    or more energy than the scene ever had). The run is void."""


def setup_rollout(scene: Scene, solref: str | None = None, integrator: str | None = None,
                  dt: float | None = None, pairs: str = "native"):
    """(twin, model, data, start state, steps): everything mujoco.rollout needs for the scene,
    with the data at the scene's initial state (keyframe 0) and steps = duration / dt."""
    twin, model = compiled_twin(scene, solref, integrator=integrator, dt=dt, pairs=pairs)
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    start_state = np.empty(mujoco.mj_stateSize(model, FULL_STATE))
    mujoco.mj_getState(model, data, start_state, FULL_STATE)
    return twin, model, data, start_state, max(1, int(round(scene.duration / twin.dt)))


def rollout_ns_per_step(model, data, start_state: np.ndarray, n: int, repeats: int) -> float:
    """CPU ns per mj_step of n-step rollouts from start_state: the fastest of `repeats`, after a
    warm-up (benchmarks; the thread's CPU time, so other processes' load falls outside it)."""
    rollout.rollout(model, data, start_state, nstep=min(n, WARMUP_STEPS))
    best = np.inf
    for _ in range(repeats):
        begin = time.thread_time()
        rollout.rollout(model, data, start_state, nstep=n)
        best = min(best, time.thread_time() - begin)
    return 1e9 * best / n


def timed_rollout(model, data, start_state: np.ndarray, n: int, before_timed=None):
    """(rows (n + 1, nstate) full physics states from the start, sensor rows (n + 1, nsensordata)
    of the same states, wall time s of the n steps). A warm-up rollout runs first;
    before_timed() is called between it and the timed one."""
    rollout.rollout(model, data, start_state, nstep=min(n, WARMUP_STEPS))
    if before_timed is not None:
        before_timed()
    begin = time.perf_counter()
    rows, sensors = rollout.rollout(model, data, start_state, nstep=n)
    wall = time.perf_counter() - begin
    rows = np.vstack([start_state[None, :], rows[0]])
    return rows, sensors[0], wall


def trajectory_from(twin: Twin, model, data, rows: np.ndarray, sensors: np.ndarray, wall: float,
                    simulator: str, force_evals: int, meta: dict) -> Trajectory:
    """The Trajectory of a twin's rollout (timed_rollout's rows and sensor rows), its energy
    from MuJoCo's sensors, after the blow-up checks; raises MujocoDiverged."""
    scene = twin.scene
    sensors = np.vstack([sensors, final_sensors(model, data, rows[-1])])
    nq = joint_count(twin.props)
    states = states_from_q(twin.props, rows[:, 1:1 + nq], rows[:, 1 + nq:1 + 2 * nq])
    twin_name = "dynamics twin" if simulator == "mujoco_dynamics" else f"native twin, solref {twin.contact.mapping}"
    what = f"{scene.name}: MuJoCo's {twin_name} ({twin.integrator}, dt = {twin.dt:g} s)"
    if data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number:
        raise MujocoDiverged(f"{what} met a bad acceleration and reset the state; try a smaller dt")
    k = scene.contact.k if scene.has("contact") else 0.0
    ke, pe, ce = energy_parts(twin.sensors, sensors, k, contact_below_site(scene.body))
    g = -float(model.opt.gravity[2])
    step = first_blowup(states, ke, pe, twin.props, g)
    if step >= 0:
        raise MujocoDiverged(f"{what} blew up at step {step} (t = {step * twin.dt:.6g} s): the state left "
                             f"the healthy range; try a smaller dt")
    n = len(states) - 1
    meta = dict(meta, ns_per_step=1e9 * wall / n)
    return Trajectory(
        t=np.arange(n + 1) * twin.dt,
        x=states[:, 0], y=states[:, 1], theta=states[:, 2],
        vx=states[:, 3], vy=states[:, 4], omega=states[:, 5],
        energy_kinetic=ke, energy_gravity=pe, energy_contact=ce,
        simulator=simulator, integrator=twin.integrator, dt=twin.dt,
        force_evals=force_evals, wall_time=wall, meta=meta,
    )


def simulate_mujoco(scene: Scene, solref: str | None = None, integrator: str | None = None,
                    dt: float | None = None) -> Trajectory:
    """Run the scene's twin for its duration. solref: penalty | physical | seed; integrator:
    Euler | RK4 | implicit | implicitfast; dt (s). Defaults: the scene's [mujoco] table."""
    twin, model, data, start_state, n = setup_rollout(scene, solref, integrator, dt)
    rows, sensors, wall = timed_rollout(model, data, start_state, n)
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
    }
    return trajectory_from(twin, model, data, rows, sensors, wall, "mujoco",
                           n * STAGES[twin.integrator], meta)
