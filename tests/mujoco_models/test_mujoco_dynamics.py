"""The dynamics twin: MuJoCo integrating the seed's law from a passive-force callback.

Stage first (the callback's generalised force from one state, against the law by hand), then
the run's contract (Trajectory, counts, energy from MuJoCo), the callback's hygiene (restored,
inert for other models, safe in worker processes) and the switches of the attribution ladder."""
import dataclasses
import math
import multiprocessing

import mujoco
import numpy as np
import pytest
from mujoco import rollout
from numba import cfunc, types

from compare.scenarios import load
from custom_sim import parse_scene
from mujoco_models import simulate_dynamics, simulate_mujoco
from mujoco_models.frames import qpos_qvel
from mujoco_models.passive import installed, law_parameters
from mujoco_models.rigid_body import rigid_body
from mujoco_models.sites import contact_below_site
from mujoco_models.spec import build_twin

# The callback's force and the one by hand are the same few products and sums in another
# order: a relative few ulp of the largest term.
FORCE_REL = 1e-13


def short(scene, duration):
    return dataclasses.replace(scene, duration=duration)


def passive_force(scene, state, **switches):
    """qfrc_passive of the dynamics twin at `state` [x, y, theta, vx, vy, omega]."""
    twin = build_twin(scene, pairs="none")
    model = twin.spec.compile()
    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:] = qpos_qvel(twin.props, state)
    params = law_parameters(scene, twin.props, contact_below_site(scene.body),
                            native_normal=switches.get("native_normal", False),
                            friction_at=switches.get("friction_at", "corner"))
    with installed(model, data, params):
        mujoco.mj_forward(model, data)
    return data.qfrc_passive.copy()


def law_by_hand(scene, state, lift=0.0):
    """(Fx, Fy, tau) of the seed's law at the state, by hand: every corner below ground, friction
    on the slip of the point lifted by lift * depth (0: the corner)."""
    rb = rigid_body(scene.body)
    x, y, th, vx, vy, om = state
    ct = scene.contact
    fx = fy = tau = 0.0
    c, s = (math.cos(th), math.sin(th)) if rb.points_rotate else (1.0, 0.0)
    for lx, ly in rb.points:
        rx, ry = c * lx - s * ly, s * lx + c * ly
        d = -(y + ry)
        if d <= 0:
            continue
        vn = vy + om * rx
        fn = ct.k * d + ct.c * max(0.0, -vn) if ct.damping_law == "compression" else max(0.0, ct.k * d - ct.c * vn)
        ryf = ry + lift * d
        ft = -ct.mu * fn * math.tanh(ct.alpha * (vx - om * ryf)) if scene.has("friction") else 0.0
        fx, fy = fx + ft, fy + fn
        tau += rx * fn - ryf * ft
        if scene.has("rolling_friction"):
            tau -= ct.mu_roll * fn * math.tanh(ct.roll_sharpness * om)
    return np.array([fx, fy, tau])


@pytest.mark.parametrize("name,state", [
    ("box_drop", [0.3, 0.08, 0.4, 0.7, -1.2, 3.0]),        # one corner down, sliding and turning
    ("t_shape_drop", [0.0, 0.05, 0.3, -0.4, -0.5, -2.0]),  # COM off the geometry origin
    ("rolling_circle", [0.0, 0.0995, 1.1, 1.5, -0.2, 4.0]),  # the point below the centre, any angle
    ("point_drop", [0.2, 0.049, 0.0, 0.5, -0.3, 0.0]),
    ("box_slide", [0.0, 0.0497, 0.0, 2.0, 0.1, 0.0]),       # compression law: leaving, undamped
])
def test_callback_force_is_the_law_by_hand(name, state):
    scene = load(name)
    got = passive_force(scene, state)
    want = law_by_hand(scene, state)
    assert np.any(want != 0.0), "the state touches the ground"
    scale = np.max(np.abs(want))
    assert got == pytest.approx(want[:len(got)], rel=FORCE_REL, abs=FORCE_REL * scale), \
        f"{name}: callback {got} against {want} (N, N, N m)"


def test_friction_at_the_midpoint_moves_the_lever_by_half_the_depth():
    scene, state = load("box_drop"), [0.3, 0.08, 0.4, 0.7, -1.2, 3.0]
    corner = passive_force(scene, state)
    mid = passive_force(scene, state, friction_at="midpoint")
    assert mid == pytest.approx(law_by_hand(scene, state, lift=0.5), rel=FORCE_REL, abs=1e-12)
    assert abs(mid[2] - corner[2]) > 1e-4, "the torque changes"


def test_native_normal_leaves_the_normal_force_to_mujoco():
    scene, state = load("box_drop"), [0.3, 0.08, 0.4, 0.7, -1.2, 3.0]
    f = passive_force(scene, state, native_normal=True)
    fx, fy, tau = law_by_hand(scene, state)
    assert f[0] == pytest.approx(fx, rel=FORCE_REL), "friction stays ours"
    assert abs(f[1]) < 1e-12 * abs(fy), "no normal force from the callback"


def test_no_contact_effect_no_force():
    scene = dataclasses.replace(load("box_drop"), effects=("gravity",))
    assert np.all(passive_force(scene, [0.0, 0.0, 0.4, 1.0, -1.0, 1.0]) == 0.0)


def test_trajectory_contract():
    scene = short(load("box_drop"), 0.05)
    for integrator, stages in (("Euler", 1), ("RK4", 4), ("rk4", 4)):
        tr = simulate_dynamics(scene, integrator)
        assert tr.simulator == "mujoco_dynamics" and tr.integrator in ("Euler", "RK4")
        assert tr.steps == scene.steps and tr.dt == scene.dt
        assert tr.force_evals == scene.steps * stages, "the law is evaluated once per force evaluation"
        assert tr.wall_time > 0 and tr.meta["contact_pairs"] == 0 and tr.meta["contact_sites"] == 4
    assert simulate_dynamics(scene, "Euler", 5e-4).steps == 100
    with pytest.raises(ValueError, match="implicit integrators leave passive forces"):
        simulate_dynamics(scene, "implicit")


def test_energy_is_mujocos_and_the_sites_depths():
    """kinetic + m g y + k d^2 / 2 by hand on the twin's states; and the sensor rows are
    mj_energyPos / mj_energyVel of the same state on a fresh MjData."""
    scene = short(load("box_drop"), 0.35)
    tr = simulate_dynamics(scene)
    rb = rigid_body(scene.body)
    k = scene.contact.k
    twin = build_twin(scene, pairs="none")
    model = twin.spec.compile()
    touched = 0
    for i in range(0, tr.steps + 1, 211):
        x, y, th, vx, vy, om = tr.states()[i]
        depth = [max(0.0, -(y + math.sin(th) * lx + math.cos(th) * ly)) for lx, ly in rb.points]
        touched += any(depth)
        expected = (0.5 * rb.mass * (vx * vx + vy * vy) + 0.5 * rb.inertia * om * om + rb.mass * 9.81 * y
                    + sum(0.5 * k * d * d for d in depth))
        assert tr.energy[i] == pytest.approx(expected, rel=1e-12, abs=1e-12), f"row {i}"
        data = mujoco.MjData(model)
        data.qpos[:], data.qvel[:] = qpos_qvel(twin.props, tr.states()[i])
        mujoco.mj_forward(model, data)
        mujoco.mj_energyPos(model, data)
        mujoco.mj_energyVel(model, data)
        assert (tr.energy_gravity[i], tr.energy_kinetic[i]) == pytest.approx(tuple(data.energy), rel=1e-12, abs=1e-15)
    assert touched


@cfunc(types.void(types.voidptr, types.voidptr))
def _someone_elses(m, d):
    """A compiled callback another part of the process installed (does nothing)."""
    return


def test_callback_is_restored_and_inert_for_other_models():
    mujoco.set_mjcb_passive(_someone_elses.ctypes)
    try:
        simulate_dynamics(short(load("box_drop"), 0.01))
        assert mujoco.get_mjcb_passive() is _someone_elses.ctypes, "the previous callback is back"
        # while ours is installed, a data it does not know gets no force
        twin = build_twin(load("box_drop"), pairs="none")
        model = twin.spec.compile()
        data, other = mujoco.MjData(model), mujoco.MjData(model)
        for d in (data, other):
            d.qpos[:], d.qvel[:] = qpos_qvel(twin.props, [0, 0.0, 0.4, 0, -1, 0])
        params = law_parameters(load("box_drop"), twin.props, 0.0, native_normal=False, friction_at="corner")
        with installed(model, data, params):
            mujoco.mj_forward(model, other)
            mujoco.mj_forward(model, data)
        assert np.all(other.qfrc_passive == 0.0) and np.any(data.qfrc_passive != 0.0)
    finally:
        mujoco.set_mjcb_passive(None)
    simulate_dynamics(short(load("box_drop"), 0.01))
    assert mujoco.get_mjcb_passive() is None


def _worker(name):
    return simulate_dynamics(short(load(name), 0.3)).states()


def test_worker_processes_install_their_own():
    """The same run in a worker process (forked after the parent installed and removed the
    callback, as `run`'s pool does) is bit for bit the parent's. A spawned worker, which loads
    the callback from numba's cache, gives the same; it is left out here for the 5 s a fresh
    interpreter takes."""
    here = _worker("box_drop")
    with multiprocessing.get_context("fork").Pool(1) as pool:
        there = pool.map(_worker, ["box_drop"])[0]
    assert np.array_equal(here, there)


def test_native_normal_without_friction_is_the_native_twin():
    """With friction off the switch leaves nothing to the callback: the native twin exactly."""
    scene = short(load("elastic_bounce"), 1.0)
    a, b = simulate_dynamics(scene, native_normal=True), simulate_mujoco(scene, integrator="Euler")
    assert np.array_equal(a.states(), b.states())
    assert np.allclose(a.energy, b.energy, rtol=0, atol=1e-12)


@pytest.mark.parametrize("name, integrator", [("box_drop", "Euler"), ("t_shape_drop", "RK4")])
def test_skipping_the_collision_stage_of_a_twin_without_pairs_changes_no_bit(name, integrator):
    """A twin without contact pairs has no geom that can collide, and skips MuJoCo's collision
    stage (mjDSBL_CONTACT): its states and sensors through a landing are those of the same
    model with the stage run, to the bit. A twin with pairs keeps the stage."""
    scene = short(load(name), 0.5)
    twin = build_twin(scene, integrator=integrator, pairs="none")
    skipped = twin.spec.compile()
    assert skipped.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_CONTACT
    full = twin.spec.compile()
    full.opt.disableflags &= ~int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
    params = law_parameters(scene, twin.props, contact_below_site(scene.body), native_normal=False,
                            friction_at="corner")
    runs = []
    for model in (skipped, full):
        data = mujoco.MjData(model)
        mujoco.mj_resetDataKeyframe(model, data, 0)
        start = np.empty(mujoco.mj_stateSize(model, mujoco.mjtState.mjSTATE_FULLPHYSICS))
        mujoco.mj_getState(model, data, start, mujoco.mjtState.mjSTATE_FULLPHYSICS)
        with installed(model, data, params):
            runs.append(rollout.rollout(model, data, start, nstep=scene.steps))
    assert np.array_equal(runs[0][0], runs[1][0]) and np.array_equal(runs[0][1], runs[1][1])
    assert np.ptp(runs[0][1]) > 0   # the sensors moved: the body fell and landed
    native = build_twin(scene).spec.compile()
    assert not native.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_CONTACT


def test_unknown_switch_values_are_refused():
    with pytest.raises(ValueError, match="friction_at"):
        simulate_dynamics(short(load("box_drop"), 0.01), friction_at="centre")


def test_gravity_only_is_ballistic():
    """No contact effect: x = v t, y = y0 - g t^2 / 2 up to the Euler step's O(h) term."""
    scene = parse_scene({"duration": 0.2, "dt": 1e-4, "effects": ["gravity"],
                         "body": {"shape": "box", "mass": 0.7, "size": [0.2, 0.1]},
                         "initial": {"position": [0, 1], "velocity": [1.0, 2.0], "angular_velocity": 3.0}},
                        file="<test>")
    tr = simulate_dynamics(scene, "RK4")
    t = tr.t
    assert tr.x == pytest.approx(t, abs=1e-12)
    assert tr.y == pytest.approx(1 + 2 * t - 0.5 * 9.81 * t * t, abs=1e-12)
    assert tr.theta == pytest.approx(3 * t, abs=1e-12)


def test_a_dynamics_run_that_blows_up_raises():
    """k = 1e8 N/m on 1 kg at dt = 1e-3 s: h wn = 10, far beyond Euler's 2; the twin's own
    guard (MuJoCo's energy above the lowest pose) voids the run."""
    from mujoco_models import MujocoDiverged

    scene = parse_scene({
        "duration": 0.5, "dt": 1e-3, "effects": ["gravity", "contact"], "body": {"shape": "point", "mass": 1.0},
        "contact": {"k": 1e8, "c": 0.0, "damping_law": "linear"}, "initial": {"position": [0, 0.1]}}, file="<test>")
    with pytest.raises(MujocoDiverged, match="blew up"):
        simulate_dynamics(scene)
