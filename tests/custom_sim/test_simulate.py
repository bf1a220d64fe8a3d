"""Whole runs: determinism, counts of force evaluations, divergence (CSV files: test_trajectory_csv.py)."""
import dataclasses
import hashlib

import numpy as np
import pytest

from custom_sim import INTEGRATORS, SimulationDiverged, Stepper, load_scene, simulate
from compare.scenarios import builtin_paths


@pytest.mark.parametrize("path", builtin_paths(), ids=lambda p: p.stem)
def test_same_scene_twice_is_bit_identical(path):
    scene = load_scene(path)
    a, b = simulate(scene), simulate(scene)
    digest = [hashlib.sha256(t.states().tobytes()).hexdigest() for t in (a, b)]
    assert digest[0] == digest[1]


@pytest.mark.parametrize("integrator", list(INTEGRATORS))
def test_force_evaluations_are_counted(integrator):
    scene = dataclasses.replace(load_scene("scenarios/box_drop.toml"), integrator=integrator, duration=0.3)
    tr = simulate(scene)
    per_step = INTEGRATORS[integrator].evals_per_step
    if per_step is None:  # implicit Euler: predictor and its residual, then >= 1 residual per iteration
        assert tr.force_evals >= 2 * scene.steps + tr.newton_iterations
    else:
        assert tr.force_evals == per_step * scene.steps


def test_stepper_reproduces_simulate():
    scene = dataclasses.replace(load_scene("scenarios/t_shape_drop.toml"), duration=0.5)
    tr = simulate(scene)
    stepper = Stepper(scene)
    for _ in range(10):
        stepper.advance(scene.steps // 10)
    assert np.array_equal(stepper.state, tr.states()[-1])


def stiff_drop(scene_factory, dt, integrator="semi_implicit_euler"):
    """0.01 kg on k = 1e7 N/m: wn = 3.2e4 rad/s, so semi-implicit Euler needs dt < 6e-5 s."""
    return scene_factory({"shape": "point", "mass": 0.01}, {"position": [0.0, 0.1]}, duration=0.3, dt=dt,
                         integrator=integrator, contact={"k": 1e7, "c": 0.0, "mu": 0.5, "alpha": 100.0})


@pytest.mark.parametrize("integrator", ["explicit_euler", "semi_implicit_euler", "rk4"])
def test_divergence_stops_with_step_state_and_a_stable_step(scene_factory, integrator):
    scene = stiff_drop(scene_factory, 1e-3, integrator)
    with pytest.raises(SimulationDiverged) as info:
        simulate(scene)
    err = info.value
    # the first step in contact flings the body off with far more energy than it had
    touchdown = int(np.sqrt(2 * 0.1 / 9.81) / scene.dt)
    assert touchdown <= err.step <= touchdown + 3, err.step
    assert err.stable_dt < scene.dt
    assert f"step {err.step}" in str(err) and "stable step" in str(err)
    if integrator != "explicit_euler":  # undamped: explicit Euler has no stable step
        # the suggestion holds: linear theory promises stability, not accuracy (at h wn = 1.8
        # each landing mid-step still costs or gains O(1) of the energy), so it must complete
        simulate(dataclasses.replace(scene, dt=err.stable_dt * 0.9))


def test_a_large_but_bounded_step_is_reported_as_chatter_not_blow_up():
    """Unilateral contact keeps an over-large step bounded: no blow-up, but the slip of the
    resting box flips every step (custom_sim/chatter.py), which is reported as instability."""
    from custom_sim import SimulationChattered

    scene = dataclasses.replace(load_scene("scenarios/box_drop.toml"), dt=2e-3)
    with pytest.raises(SimulationChattered) as info:
        simulate(scene)
    assert np.all(np.isfinite(info.value.state)) and info.value.quantity == "slip velocity"


def test_the_blow_up_check_decides_as_its_plain_definition():
    """is_healthy leaves the finiteness of x, y and the velocities to their finite limits (a NaN
    or inf fails the comparison) and skips the energy under no energy limit: on states at and
    around every limit, non-finite in each component, it decides as the plain definition does."""
    import itertools

    from custom_sim.integrators import is_healthy
    from custom_sim.runner import POSITION_LIMIT, SPEED_LIMIT

    def plain(z, guard):
        mass, inertia, g, y_low, energy_limit, position_limit, speed_limit = guard
        x, y, theta, vx, vy, om = z
        with np.errstate(invalid="ignore"):   # inf - inf: a NaN energy, which fails the test below
            energy = 0.5 * mass * (vx * vx + vy * vy) + 0.5 * inertia * om * om + mass * g * (y - y_low)
        return bool(np.all(np.isfinite(z)) and abs(x) <= position_limit and abs(y) <= position_limit
                    and max(abs(vx), abs(vy), abs(om)) <= speed_limit and energy <= energy_limit)

    positions = (-0.05, POSITION_LIMIT, -np.nextafter(POSITION_LIMIT, np.inf), np.nan, -np.inf)
    speeds = (3.0, -SPEED_LIMIT, np.nextafter(SPEED_LIMIT, np.inf), np.nan, np.inf)
    angles = (1e300, np.nan, -np.inf)
    checked = 0
    for energy_limit in (50.0, np.inf):
        guard = (2.0, 0.01, 9.81, -0.1, energy_limit, POSITION_LIMIT, SPEED_LIMIT)
        for z in itertools.product(positions, positions, angles, speeds, speeds, speeds):
            assert is_healthy(np.array(z), guard) == plain(np.array(z), guard), (z, energy_limit)
            checked += 1
    assert checked > 10_000
