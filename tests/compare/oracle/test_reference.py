"""The reference solution: the same equations as custom_sim, solved far more accurately.

Checked against things it did not produce: custom_sim's compiled force law at the same state
(stage by stage), analytic motions (free fall, an undamped bounce returning to its height, a
sliding disk ending at 2/3 of its speed), its own change when the tolerance is tightened,
and custom_sim's RK4 at a small step.
"""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from compare.oracle.reference import (REFERENCE_ATOL, REFERENCE_RTOL, Equations, cached_reference,
                               initial_mode, right_hand_side, solve_reference)
from compare.scenarios import load, load_builtins
from compare.tools.accuracy.workprecision import custom_grid_run, grid_times, position_errors
from custom_sim.forces import accelerations
from custom_sim.model import build_model

# Two evaluations of the same formulas in double precision, differently ordered: a few ulps
# of the largest term (k d ~ 1e2 N on 1 kg), relative.
RHS_RELATIVE = 1e-12
# The sweep's smallest measured errors are near 1e-7 m (RK4 at 2 us on the rolling disk);
# the reference must move far less than that when its tolerance is tightened 100-fold.
CONVERGED = 1e-8             # m
# Free fall and a frictionless bounce are integrated by DOP853 at rtol 1e-11: the error over
# a second stays within a few 1e-11 of quantities of order 1.
ANALYTIC = 1e-9              # m or m/s
# RK4 on a box sliding on its two lower corners (no contact switch, smooth tanh friction):
# global error O(h^4), about 1e-12 m at h = 1e-5 s. More than 1e-9 m would mean the two
# codes solve different equations.
RK4_SMOOTH = 1e-9            # m


def random_states(scene, rng, n=200):
    """States near the ground: heights around the contact depth, any angle and velocity."""
    z = np.empty((n, 6))
    z[:, 0] = rng.uniform(-1, 1, n)
    z[:, 1] = rng.uniform(-0.05, 0.2, n)
    z[:, 2] = rng.uniform(-np.pi, np.pi, n) if scene.body.shape != "point" else 0.0
    z[:, 3:5] = rng.normal(0, 2, (n, 2))
    z[:, 5] = rng.normal(0, 10, n) if scene.body.shape != "point" else 0.0
    return z


@pytest.mark.parametrize("scene", load_builtins(), ids=lambda s: s.name)
def test_right_hand_side_matches_custom_sim_force_law(scene):
    """Stage by stage: the reference's accelerations equal custom_sim's compiled ones at the
    same state, in the mode that state is in."""
    eq = Equations.from_scene(scene)
    model, points = build_model(scene)
    rng = np.random.default_rng(5)
    for z in random_states(scene, rng):
        ours = np.array(accelerations(model, points, z, 0.0, 0.0, 0.0))
        ref = right_hand_side(eq, initial_mode(eq, z))(0.0, z)[3:]
        scale = max(1.0, np.max(np.abs(ours)))
        assert np.allclose(ref, ours, rtol=0, atol=RHS_RELATIVE * scale), (z, ref, ours)
        assert np.array_equal(ref.shape, (3,))


def test_free_fall_is_a_parabola(scene_factory):
    scene = scene_factory({"shape": "box", "mass": 1.0, "size": [0.2, 0.1]},
                       {"position": [0.0, 5.0], "velocity": [1.0, 2.0], "angle": 0.3, "angular_velocity": 4.0},
                       effects=["gravity"], duration=1.0)
    t = np.linspace(0, 1, 11)
    ref = solve_reference(scene, t)
    exact = np.column_stack([t, 5 + 2 * t - 9.81 * t ** 2 / 2, 0.3 + 4 * t])
    assert np.max(np.abs(ref.states[:, :3] - exact)) < ANALYTIC


def test_undamped_bounce_returns_to_its_height():
    """elastic_bounce: no damping, no friction; energy is conserved, so after each bounce the
    point rises back to 1 m, and the contact switches are located where d = 0."""
    scene = load("elastic_bounce")
    t_fall = np.sqrt(2 * 1.0 / scene.g)
    wn = np.sqrt(scene.contact.k / scene.body.mass)
    # apex after the first bounce: two falls plus the time in the spring (half a period of the
    # spring plus the gravity offset: at most pi/wn + 2 g / (wn^2 v) = 0.032 s; found below)
    t = np.linspace(0, 2.2 * t_fall + np.pi / wn, 4001)
    ref = solve_reference(scene, t)
    assert ref.switches["touch"] >= 2
    after = t > t_fall + np.pi / wn
    apex = np.max(ref.states[after, 1])
    assert abs(apex - 1.0) < 1e-6, f"apex after the bounce {apex} m (expected 1 m: energy conserved)"
    energy = 0.5 * ref.states[:, 4] ** 2 + scene.g * ref.states[:, 1]
    free = ref.states[:, 1] > 0
    assert np.max(np.abs(energy[free] - scene.g * 1.0)) < ANALYTIC * 10


def test_sliding_disk_ends_rolling_at_two_thirds():
    """A disk launched sliding at v0 without spin rolls at v0 / (1 + I/(m R^2)) = 2 v0 / 3."""
    scene = dataclasses.replace(load("rolling_circle"), effects=("gravity", "contact", "friction"))
    ref = solve_reference(scene, np.linspace(0, 1.0, 11))
    v0, R = scene.initial.velocity[0], scene.body.radius
    vx, omega = ref.states[-1, 3], ref.states[-1, 5]
    # tanh friction keeps a slip of order (force needed) / (mu Fn alpha): none at constant speed
    assert abs(vx - 2 * v0 / 3) < 1e-6, vx
    assert abs(vx + omega * R) < 1e-6, (vx, omega)


@pytest.mark.parametrize("law", ["tanh", "sign"])
def test_rolling_resistance_decelerates_a_rolling_disk(law):
    """Rolling resistance mu_roll Fn on a rolling disk: deceleration 2 mu_roll g / (3 R)
    (docs/physics.md), under the scene's tanh(roll_sharpness omega) and under the seed's
    sign(omega) with its switch located as an event."""
    base = load("rolling_circle")
    if law == "sign":
        base = dataclasses.replace(base, contact=dataclasses.replace(
            base.contact, roll_law="sign", roll_sharpness=None))
    R, v0 = base.body.radius, 1.0
    scene = dataclasses.replace(base, initial=dataclasses.replace(
        base.initial, velocity=(v0, 0.0), angular_velocity=-v0 / R))
    t = np.linspace(0.0, 1.0, 11)
    ref = solve_reference(scene, t)
    decel = 2 * base.contact.mu_roll * base.g / (3 * R)
    # after a transient of ~0.05 s in which the tanh friction builds the slip it needs to pass
    # the braking force on (2 mu_roll / (3 R mu alpha) = 0.4 mm/s), the speed falls linearly;
    # the disk spins far above custom_sim's regularisation (|omega| ~ 10 rad/s)
    slope = -np.polyfit(t[2:], ref.states[2:, 3], 1)[0]
    assert abs(slope / decel - 1) < 1e-4, (slope, decel)


@pytest.mark.parametrize("name", ["box_drop", "point_drop", "rolling_circle", "t_shape_drop"])
def test_reference_converged(name):
    """Tightening the tolerance 100-fold changes the solution far less than any measured error."""
    scene = load(name)
    t = grid_times(scene)
    ref = solve_reference(scene, t)
    tight = solve_reference(scene, t, rtol=REFERENCE_RTOL / 100, atol=REFERENCE_ATOL / 100)
    change = np.max(np.hypot(*(ref.states[:, :2] - tight.states[:, :2]).T))
    assert change < CONVERGED, f"{name}: reference moved {change:.3g} m at a 100x tighter tolerance"


def test_agrees_with_custom_rk4_at_a_small_step():
    """box_slide: no contact switch (both lower corners stay in), so RK4 is fourth order and
    at h = 1e-5 s must agree with the reference to round-off-level accuracy."""
    scene = load("box_slide")
    ref = solve_reference(scene, grid_times(scene))
    states, _ = custom_grid_run(scene, "rk4", 1e-5)
    err, _, angle = position_errors(states, ref.states)
    assert err < RK4_SMOOTH, f"max position difference {err:.3g} m"
    assert angle < RK4_SMOOTH * 10, f"max angle difference {angle:.3g} rad"


def test_agrees_with_custom_rk4_through_impacts():
    """point_drop: at each landing the compression law's damping switches on with a jump
    c |vy| = 200 N, which a fixed step cannot locate: RK4 drops to first order there. Its
    distance from the reference must halve (within the scatter of where the impact falls
    inside a step) as h halves, towards the reference and not towards something else."""
    scene = dataclasses.replace(load("point_drop"), duration=0.8)  # first landing and rebound
    ref = solve_reference(scene, grid_times(scene))
    errors = [position_errors(custom_grid_run(scene, "rk4", dt)[0], ref.states)[0] for dt in (4e-5, 1e-5)]
    assert errors[1] < errors[0] / 2, errors
    assert errors[1] < 1e-4, errors


def test_cache_returns_the_same_solution(tmp_path):
    scene = dataclasses.replace(load("point_drop"), duration=0.5)
    t = grid_times(scene)
    first = cached_reference(scene, t, tmp_path)
    assert len(list(tmp_path.glob("reference_point_drop_*.npz"))) == 1
    again = cached_reference(scene, t, tmp_path)
    assert np.array_equal(first.states, again.states)
    other = cached_reference(dataclasses.replace(scene, g=9.0), t, tmp_path)
    assert not np.array_equal(first.states, other.states)
