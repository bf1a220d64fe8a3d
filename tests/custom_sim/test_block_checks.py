"""The explicit loop checks its steps a block at a time (integrators.integrate_explicit) and
still stops a run where a loop that checks every step stops it: the same step, state, recorded
states and chatter tracker. The plain loop is written out here from the same step functions."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from compare.scenarios import load
from custom_sim import INTEGRATORS, Stepper, mass_properties
from custom_sim.chatter import CLEARED, TOUCHED, chattering_point
from custom_sim.integrators import (BLOCK_STEPS, NO_BOUNDS, bounds_healthy, euler_step, integrate, is_healthy,
                                    rk4_step, widen)
from custom_sim.model import build_model, initial_state
from custom_sim.runner import POSITION_LIMIT, SPEED_LIMIT, blowup_guard, new_watch


def setup(scene, applied_input):
    props = mass_properties(scene.body)
    model, points = build_model(scene, props)
    z = initial_state(scene)
    return model, points, z, blowup_guard(scene, props, z, applied_input), new_watch(props)


def checked_every_step(scene, ext, applied_input=False):
    """(stop step or -1, states after each step up to it, final state, tracker): step, then
    is_healthy, then the chatter watch, after every step."""
    model, points, z, guard, watch = setup(scene, applied_input)
    counters, work = np.zeros(4, dtype=np.int64), np.zeros((18, 6))
    states = []
    for i in range(scene.steps):
        fx, fy, tau = ext[i if len(ext) > 1 else 0]
        if scene.integrator == "rk4":
            rk4_step(model, points, z, scene.dt, fx, fy, tau, counters, work)
        else:
            euler_step(model, points, z, scene.dt, fx, fy, tau, counters, scene.integrator == "semi_implicit_euler")
        states.append(z.copy())
        if not is_healthy(z, guard) or (model.contact and chattering_point(model, points, z, watch) >= 0):
            return i + 1, np.array(states), z, watch
    return -1, np.array(states), z, watch


def checked_by_blocks(scene, ext, applied_input=False):
    """The same from integrate (the compiled loop), recording every step."""
    model, points, z, guard, watch = setup(scene, applied_input)
    out = np.full((scene.steps, 6), np.nan)
    stop = integrate(model, points, z, scene.dt, scene.steps, INTEGRATORS[scene.integrator].code, ext, out,
                     np.zeros(4, dtype=np.int64), guard, watch)
    return stop, out[:stop if stop >= 0 else scene.steps], z, watch


def assert_same_stop(scene, ext=None, applied_input=False) -> int:
    ext = np.zeros((1, 3)) if ext is None else ext
    a, b = checked_every_step(scene, ext, applied_input), checked_by_blocks(scene, ext, applied_input)
    assert a[0] == b[0], (a[0], b[0])
    for x, y in zip(a[1:], b[1:]):
        assert x.tobytes() == y.tobytes()
    return a[0]


def stiff_drop(scene_factory, integrator):
    """0.01 kg on k = 1e7 N/m at dt = 1e-3 s: flung off by its first step in contact."""
    return scene_factory({"shape": "point", "mass": 0.01}, {"position": [0.0, 0.1]}, duration=0.3, dt=1e-3,
                         integrator=integrator, contact={"k": 1e7, "c": 0.0, "mu": 0.5, "alpha": 100.0})


@pytest.mark.parametrize("integrator", ["explicit_euler", "semi_implicit_euler", "rk4"])
def test_a_blow_up_after_a_flight_stops_at_the_same_step(scene_factory, integrator):
    assert assert_same_stop(stiff_drop(scene_factory, integrator)) > BLOCK_STEPS   # blocks in the air first


def test_chatter_after_a_flight_stops_at_the_same_step_and_point():
    """box_drop at 2e-3 s falls through several unchecked blocks, lands and chatters."""
    assert assert_same_stop(dataclasses.replace(load("box_drop"), dt=2e-3)) > 2 * BLOCK_STEPS


@pytest.mark.parametrize("integrator", ["explicit_euler", "semi_implicit_euler", "rk4"])
@pytest.mark.parametrize("duration, touched", [(0.15, 1.0), (0.4, CLEARED)], ids=["landing", "take-off"])
def test_the_tracker_ends_as_with_every_step_checked(scene_factory, integrator, duration, touched):
    """A point mass dropped from 0.1 m on an undamped frictionless spring touches down at step
    143 of 1e-3 s, inside the third block, and leaves the ground some 22 steps later: a run
    ending 7 steps after the touchdown ends with the point touching, one ending in the air
    after the bounce with its row cleared, as in the plain loop."""
    scene = scene_factory({"shape": "point", "mass": 0.5}, {"position": [0.0, 0.1], "velocity": [0.2, 0.0]},
                          duration=duration, dt=1e-3, integrator=integrator, contact={"c": 0.0},
                          effects=["gravity", "contact"])
    assert assert_same_stop(scene) == -1
    assert checked_by_blocks(scene, np.zeros((1, 3)))[3][0, TOUCHED] == touched


@pytest.mark.parametrize("integrator", ["explicit_euler", "semi_implicit_euler", "rk4"])
def test_a_row_not_yet_cleared_is_cleared_before_a_block_goes_unchecked(scene_factory, integrator):
    """A Stepper call that starts one step after the take-off (the row not yet cleared): the
    next touchdown finds the tracker as in the plain loop, which cleared the row."""
    scene = scene_factory({"shape": "point", "mass": 0.5}, {"position": [0.0, 0.1], "velocity": [0.2, 0.0]},
                          duration=0.8, dt=1e-3, integrator=integrator, contact={"c": 0.0},
                          effects=["gravity", "contact"])
    stop, states, z, watch = checked_every_step(scene, np.zeros((1, 3)), applied_input=True)
    assert stop == -1
    below = states[:, 1] < 0.0
    take_off = int(np.flatnonzero(below[:-1] & ~below[1:])[0]) + 1   # the first state in the air again
    assert below[take_off + 1:].any()                                  # and a second touchdown
    stepper = Stepper(scene)
    stepper.advance(take_off + 1)
    stepper.advance(scene.steps - take_off - 1)
    assert stepper.state.tobytes() == z.tobytes() and stepper.watch.tobytes() == watch.tobytes()


@pytest.mark.parametrize("integrator", ["explicit_euler", "semi_implicit_euler", "rk4"])
def test_a_bad_state_inside_a_block_is_found_though_the_block_ends_healthy(scene_factory, integrator):
    """In the air, a kick to twice the speed limit at step 100 (inside the second block), taken
    back at the next step: the block's last state is healthy, only its bounds show the kick."""
    scene = scene_factory({"shape": "point", "mass": 1.0}, {"position": [0.0, 10.0]}, duration=0.2, dt=1e-3,
                          integrator=integrator)
    kick = 2.0 * SPEED_LIMIT / scene.dt   # N on 1 kg for one step
    ext = np.zeros((scene.steps, 3))
    ext[99, 0], ext[100, 0] = kick, -kick
    stop = assert_same_stop(scene, ext, applied_input=True)
    assert stop == 100 and stop % BLOCK_STEPS
    model, points, _, guard, _ = setup(scene, applied_input=True)
    z = checked_every_step(scene, ext, applied_input=True)[2]
    if integrator == "rk4":
        rk4_step(model, points, z, scene.dt, -kick, 0.0, 0.0, np.zeros(4, dtype=np.int64), np.zeros((18, 6)))
    else:
        euler_step(model, points, z, scene.dt, -kick, 0.0, 0.0, np.zeros(4, dtype=np.int64),
                   integrator == "semi_implicit_euler")
    assert is_healthy(z, guard)   # the step after the kick is healthy again


def test_the_bounds_of_healthy_states_pass_only_if_every_state_does():
    """bounds_healthy(bounds of a set) implies is_healthy of each state in it, over random sets
    around every limit (the energy's among them); and sets well inside pass."""
    rng = np.random.default_rng(7)
    for g in (9.81, -9.81):   # the schema's g >= 0, and the other side
        guard = (2.0, 0.01, g, -0.1, 50.0, POSITION_LIMIT, SPEED_LIMIT)
        passed = 0
        for _ in range(3000):
            scale = rng.choice([1.0, 5.0, 10.0, 1e5, 1e6])
            states = rng.normal(0.0, scale, size=(int(rng.integers(1, 8)), 6))
            bounds = NO_BOUNDS
            for z in states:
                bounds = widen(bounds, z)
            if bounds_healthy(bounds, guard):
                passed += 1
                assert all(is_healthy(z, guard) for z in states), states
        assert passed > 300
    # speeds of a few m/s at a few m: kinetic and potential energy well below the limit
    guard = (2.0, 0.01, 9.81, -0.1, 50.0, POSITION_LIMIT, SPEED_LIMIT)
    calm = rng.uniform(-2.0, 2.0, size=(BLOCK_STEPS, 6))
    bounds = NO_BOUNDS
    for z in calm:
        bounds = widen(bounds, z)
    assert bounds_healthy(bounds, guard)
