"""Check `step`: custom_sim holds to round-off under all four integrators on every scene, and
known mistakes, put in one at a time, fail it with the right phase and component."""
from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

import custom_sim
from compare.scenarios import load, load_builtins
from compare.oracle import one_step
from compare.checks.step_check import check_step
from custom_sim.chatter import WATCH_COLUMNS
from custom_sim.integrators import INTEGRATORS, NEWTON_TOL, integrate
from custom_sim.model import build_model, initial_state
from custom_sim.runner import blowup_guard

import seed_box
import sign_box

METHODS = tuple(INTEGRATORS)
# Every scene's first 0.8 s, long enough to reach its contacts (the latest, spinning_box, lands
# after 0.45 s), counted as WINDOW_STEPS steps of WINDOW_DT; scenes with far smaller steps are
# cut at MAX_WINDOW_STEPS of their own (stiff_contact then ends before its landing). The full
# runs are checked by `python -m compare tools step-survey` in CI.
WINDOW_STEPS = 8000
WINDOW_DT = 1e-4           # s
MAX_WINDOW_STEPS = 60_000
SCENES = load_builtins() + load_builtins("stress")


def window(scene, integrator, steps=WINDOW_STEPS):
    """The scene cut to its first steps * WINDOW_DT seconds (at most MAX_WINDOW_STEPS of its own)."""
    span = min(scene.duration, steps * WINDOW_DT, MAX_WINDOW_STEPS * scene.dt)
    return dataclasses.replace(scene, integrator=integrator, duration=span)


def run_custom(scene, props=None):
    """custom_sim's compiled loop, optionally with altered mass properties (a mistake put in)."""
    props = props or custom_sim.mass_properties(scene.body)
    model, points = build_model(scene, props)
    z = initial_state(scene)
    out = np.empty((scene.steps + 1, 6))
    out[0] = z
    counters = np.zeros(4, dtype=np.int64)
    guard = blowup_guard(scene, props, z, applied_input=True)
    integrate(model, points, z, scene.dt, scene.steps, INTEGRATORS[scene.integrator].code,
              np.zeros((1, 3)), out[1:], counters, guard, np.empty((0, WATCH_COLUMNS)))
    return out, counters


def test_newton_tolerance_is_custom_sims():
    """The implicit Euler bound is the Newton tolerance custom_sim solves to."""
    assert one_step.IMPLICIT_SOLVE_TOL == NEWTON_TOL


@pytest.mark.parametrize("integrator", METHODS)
@pytest.mark.parametrize("scene", SCENES, ids=lambda s: s.name)
def test_custom_sim_holds_to_round_off(scene, integrator):
    """Every step of custom_sim is the independent step, to round-off, under every integrator on
    every scene. That includes implicit Euler's touchdowns where its equation has no root (the
    damper engages with c |vc_y| at d = 0 and G jumps over zero): custom_sim lands on the jump's
    exact point and the check judges it there. Every Newton solve converges."""
    sc = window(scene, integrator)
    states, counters = run_custom(sc)
    row = check_step(sc, states, integrator, sc.dt)
    assert int(counters[3]) == 0, "custom_sim counts an unconverged Newton solve"
    d = row.details
    assert row.passed is True, (d["first_step"], d["phase"], d["component"], d.get("first_residual"), d.get("first_bound"))
    assert row.details["bound_ratio_max"] < 1.0


def test_row_is_json_safe_and_names_its_arrays():
    sc = window(load("box_drop"), "semi_implicit_euler", 3000)
    states, _ = run_custom(sc)
    row = check_step(sc, states, "semi_implicit_euler", sc.dt)
    data = row.to_json()
    text = json.dumps(data, allow_nan=False)
    assert "NaN" not in text and row.residual.shape == (sc.steps, 6) and "residual" not in data
    for key in ("name", "isolates", "integrator", "position_error_max", "angle_error_max",
                "tolerance_position", "tolerance_angle", "pass", "reason", "first_step",
                "first_time", "phase", "component", "residual_max"):
        assert key in data, key
    assert row.name == "step" and row.passed is True


def test_unknown_integrator_is_not_judged():
    sc = load("point_drop")
    row = check_step(sc, np.zeros((3, 6)), "verlet", sc.dt)
    assert row.passed is None and "verlet" in row.reason


def test_non_finite_state_fails_and_is_named():
    sc = window(load("point_drop"), "semi_implicit_euler", 200)
    states, _ = run_custom(sc)
    states[150, 4] = np.nan
    row = check_step(sc, states, "semi_implicit_euler", sc.dt)
    assert row.passed is False and row.details["nonfinite_step"] == 150
    json.dumps(row.to_json(), allow_nan=False)


# ---------------------------------------------------------------------------------------
# Mistakes put in, one at a time


def _props(scene, **changes):
    return dataclasses.replace(custom_sim.mass_properties(scene.body), **changes)


def test_wrong_inertia_fails_at_the_first_contact_in_omega():
    sc = window(load("box_drop"), "semi_implicit_euler", 3000)
    props = _props(sc, inertia=1.1 * custom_sim.mass_properties(sc.body).inertia)
    states, _ = run_custom(sc, props)
    row = check_step(sc, states, "semi_implicit_euler", sc.dt)
    assert row.passed is False and row.details["component"] == "omega"
    assert row.details["phase"].startswith("contact at point 0")


def test_missing_contact_point_fails_where_that_corner_touches():
    """box_drop lands on its lower-left corner, point 0: leave it out."""
    sc = window(load("box_drop"), "rk4", 3000)
    props = custom_sim.mass_properties(sc.body)
    states, _ = run_custom(sc, dataclasses.replace(props, points=props.points[1:].copy()))
    row = check_step(sc, states, "rk4", sc.dt)
    assert row.passed is False and row.details["component"] in ("vy", "omega")
    assert "point 0 (-0.1, -0.05)" in row.details["phase"]


def test_explicit_euler_named_semi_implicit_fails_in_flight():
    sc = window(load("point_drop"), "explicit_euler", 500)
    states, _ = run_custom(sc)
    row = check_step(sc, states, "semi_implicit_euler", sc.dt)
    assert row.passed is False and row.details["first_step"] == 1
    assert row.details["phase"] == "flight" and row.details["component"] == "y"


def _box_window(name="box_drop", steps=2500):
    sc = window(load(name), "semi_implicit_euler", steps)
    return sc, initial_state(sc)


def test_the_plain_seed_box_passes():
    """The tests' own seed-style box, without mistakes, is the step (so the failures below are
    the mistakes', not the copy's)."""
    sc, z0 = _box_window()
    row = check_step(sc, seed_box.run(sc, z0, sc.steps), "semi_implicit_euler", sc.dt)
    assert row.passed is True, (row.details["first_step"], row.details["phase"], row.details["component"])


@pytest.mark.parametrize("mistake, phase_start, component", [
    ({"friction_at_com": True}, "contact at point 0", "vx"),
    ({"torque_sign": -1.0}, "contact at point 0", "omega"),
    ({"damping_in_air": True}, "flight", "vy"),
    ({"inertia_factor": 4.0}, "contact at point 0", "omega"),
    ({"position_with_old_velocity": True}, "flight", "y"),
])
def test_seed_box_mistakes_fail(mistake, phase_start, component):
    sc, z0 = _box_window()
    row = check_step(sc, seed_box.run(sc, z0, sc.steps, **mistake), "semi_implicit_euler", sc.dt)
    assert row.passed is False
    assert row.details["phase"].startswith(phase_start), row.details["phase"]
    assert row.details["component"] == component, row.details["component"]


def test_friction_on_com_velocity_shows_while_sliding_and_turning():
    """spinning_box slides while it turns: the slip of its corner is not vx."""
    sc = dataclasses.replace(window(load("spinning_box"), "semi_implicit_euler", 8000))
    z0 = initial_state(sc)
    row = check_step(sc, seed_box.run(sc, z0, sc.steps, friction_at_com=True),
                     "semi_implicit_euler", sc.dt)
    assert row.passed is False and "sliding" in row.details["phase"] and row.details["component"] == "vx"


# A CSV of 10 significant digits (custom_sim.write_csv, "%.10g"): half a unit in the tenth digit.
CSV_RTOL = 5e-10


@pytest.mark.parametrize("name, integrator", [("box_drop", "semi_implicit_euler"), ("rolling_circle", "rk4"),
                                              ("point_drop", "implicit_euler")])
def test_states_read_from_text_hold_to_their_rounding(tmp_path, name, integrator):
    """Rounded to 10 digits the states are no longer bit-exact: the check then holds them to
    their own rounding, and still catches a 10 % inertia error."""
    sc = window(load(name), integrator, 5000)   # through the first contact
    traj = custom_sim.simulate(sc)
    custom_sim.write_csv(traj, tmp_path / "t.csv")
    states = np.loadtxt(tmp_path / "t.csv", delimiter=",", skiprows=1)[:, 1:7]  # row 0: t = 0
    assert check_step(sc, states, integrator, sc.dt).passed is False  # beyond double round-off
    assert check_step(sc, states, integrator, sc.dt, input_rtol=CSV_RTOL).passed is True
    if sc.body.shape != "point":
        props = custom_sim.mass_properties(sc.body)
        wrong, _ = run_custom(sc, dataclasses.replace(props, inertia=1.1 * props.inertia))
        rounded = np.array([[float(f"{v:.10g}") for v in z] for z in wrong])
        assert check_step(sc, rounded, integrator, sc.dt, input_rtol=CSV_RTOL).passed is False


def test_bound_is_tight_a_part_per_billion_in_k_fails():
    """The bound is round-off, not a tolerance: a stiffness off by one part in 1e9 (a force
    change of ~5e-9 N on point_drop's contact) is over it at the first contact step."""
    sc = window(load("point_drop"), "semi_implicit_euler", 4000)
    off = dataclasses.replace(sc, contact=dataclasses.replace(sc.contact, k=sc.contact.k * (1 + 1e-9)))
    states, _ = run_custom(off)
    row = check_step(sc, states, "semi_implicit_euler", sc.dt)
    assert row.passed is False and row.details["phase"].startswith(("contact", "touchdown"))


def test_implicit_step_left_on_the_sign_jump_is_not_judged():
    """box_drop under the bare sign friction, implicit Euler: at t = 1.2272 s the box rocks on
    its two bottom corners, slips of 1e-10 to 1e-9 m/s. Neither custom_sim's Newton nor the
    oracle's finds a root there (both end on the jump, the vertical equation left at 1.3e-7 m/s),
    so the step is undecided: not judged, where it once failed in vy by 2.5e-9 m/s against
    a bound of 1e-10 meant for a root."""
    scene = sign_box.scene()
    row = check_step(scene, np.array([sign_box.STATE, sign_box.NEXT]), "implicit_euler", scene.dt)
    assert row.passed is True, (row.details["component"], row.details.get("first_residual"))
    assert row.details["undecided_steps"] == 1
    assert "not judged" in row.reason
