"""The comparison's metrics and events on trajectories whose answers are known."""
import dataclasses
import math

import numpy as np
import pytest

from custom_sim import Trajectory, load_scene, simulate
from compare.checks import events, metrics, native_check


def trajectory(t, x, y, theta=None, simulator="custom", dt=None, **energy):
    z = np.zeros_like(t)
    theta = z if theta is None else theta
    vx, vy = np.gradient(x, t), np.gradient(y, t)
    return Trajectory(t=t, x=x, y=y, theta=theta, vx=vx, vy=vy, omega=np.gradient(theta, t),
                      energy_kinetic=energy.get("kinetic", z), energy_gravity=energy.get("gravity", z),
                      energy_contact=energy.get("contact", z), simulator=simulator, dt=dt or t[1] - t[0])


def test_position_error_of_a_known_offset():
    t = np.linspace(0, 1, 1001)
    a = trajectory(t, np.sin(t), np.cos(t))
    b = trajectory(t, np.sin(t) + 3e-3 * t, np.cos(t) - 4e-3 * t, theta=0.01 * t)
    m = metrics.compare(a, b)
    assert m["position_error_max"] == pytest.approx(5e-3, rel=1e-12)  # 3-4-5 at t = 1
    assert m["position_error_rms"] == pytest.approx(5e-3 / math.sqrt(3), rel=1e-3)  # rms of a ramp
    assert m["angle_error_max"] == pytest.approx(0.01, rel=1e-12)
    assert m["time_of_position_error_max"] == 1.0


def test_different_steps_are_compared_on_the_coarser_grid():
    """A straight line sampled at two rates: linear interpolation is exact, the error is 0."""
    fine = np.linspace(0, 1, 10001)
    coarse = np.linspace(0, 1, 101)
    a = trajectory(fine, 2 * fine, 1 + fine)
    b = trajectory(coarse, 2 * coarse, 1 + coarse, simulator="mujoco")
    assert len(metrics.common_grid(a, b)) == 101
    assert metrics.compare(a, b)["position_error_max"] < 1e-14


def test_energy_drift():
    t = np.linspace(0, 1, 11)
    tr = trajectory(t, t, t, kinetic=np.linspace(2.0, 1.5, 11))
    assert metrics.energy_drift(tr) == pytest.approx(-0.5)


def test_bounce_events_of_a_synthetic_ball():
    """Ballistic arcs with restitution 0.5 from 1 m: apexes 0.25, 0.0625, 0.015625 m, with a
    10 ms contact phase below the ground between arcs."""
    g, e, dt, tc = 9.81, 0.5, 1e-5, 0.01
    ts, ys, t0 = [], [], 0.0
    fall = math.sqrt(2 / g)
    tt = np.arange(0, fall, dt)
    ts.append(tt)
    ys.append(1.0 - 0.5 * g * tt**2)
    v = g * fall
    t0 = fall
    for _ in range(4):
        tt = np.arange(0, tc, dt)
        ts.append(t0 + tt)
        ys.append(-1e-3 * np.sin(np.pi * tt / tc))
        t0 += tc
        v *= e
        tt = np.arange(0, 2 * v / g, dt)
        ts.append(t0 + tt)
        ys.append(v * tt - 0.5 * g * tt**2)
        t0 += 2 * v / g
    t, y = np.concatenate(ts), np.concatenate(ys)
    contact = np.where(y < 0, 0.5 * 1e4 * y**2, 0.0)
    tr = trajectory(t, np.zeros_like(t), y, contact=contact)
    apex = [h for _, h in events.bounce_apexes(tr)]
    # sampling at dt puts an apex within g dt^2 / 8 of the true one
    assert apex == pytest.approx([0.25, 0.0625, 0.015625], rel=1e-6)
    assert events.restitutions(tr) == pytest.approx([0.5, 0.5, 0.5], rel=1e-4)
    assert events.first_contact_time(tr) == pytest.approx(fall, abs=2 * dt)


def test_rest_and_rolling_times_of_the_simulator():
    scene = load_scene("scenarios/rolling_circle.toml")
    tr = simulate(dataclasses.replace(scene, duration=1.0))
    ev = events.events(scene, tr)
    # slide ends at v0 / (3 mu g) = 0.227 s (tests/test_friction.py checks the physics)
    assert ev["rolling_time"] == pytest.approx(2.0 / (3 * 0.3 * 9.81), rel=0.05)
    assert ev["rest_time"] is None
    slide = load_scene("scenarios/box_slide.toml")
    tr = simulate(slide)
    # friction stops it at v0 / (mu g) = 0.408 s: |vx| < REST_SPEED 2 ms earlier
    stop = tr.t[np.argmax(np.abs(tr.vx) < events.REST_SPEED)]
    assert stop == pytest.approx(2.0 / (0.5 * 9.81) - events.REST_SPEED / (0.5 * 9.81), abs=1e-3)
    # then it rocks on its corner springs; the pitch (wn = sqrt(2 k (w/2)^2 / I) = 219 rad/s)
    # decays at zeta wn = c (w/2)^2 / I = 48 1/s: below REST_SPIN within a few 1/48 s
    rest = events.events(slide, tr)["rest_time"]
    assert stop <= rest <= stop + 5 / 48


def test_full_comparison_is_not_judged_unless_the_scene_sets_a_tolerance():
    """With every effect on, no upper bound: the native row is shown, not judged; a [tolerance]
    in the scene file is the user's own bound and is judged."""
    point = load_scene("scenarios/point_drop.toml")
    far = {"position_error_max": 1e3, "angle_error_max": 1e3}
    row = native_check.native_row(point, far)
    assert row.passed is None and row.reason.startswith("not judged")
    own = dataclasses.replace(point, tolerance=dataclasses.replace(point.tolerance, position=0.01, reason="lab"))
    row = native_check.native_row(own, {"position_error_max": 0.009, "angle_error_max": 5.0})
    assert row.passed is True and row.tolerance_position == 0.01 and "lab" in row.reason
    assert native_check.native_row(own, {"position_error_max": 0.011, "angle_error_max": 0.0}).passed is False
