"""An outsider written in the complex plane (tests/outsiders/complex_plane.py), run as a new user
would: it leaves out the rolling resistance (found, not planned) and always steps semi-implicit
Euler. The diagnosis names the missing torque, says the energy it keeps, and a flight step that
differs only in its position update is said as no force (issue 32, items 7 and 11)."""
from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from compare.scenarios import load
from compare.diagnosis import diagnosis
from compare.usersim import load_simulator, run_user

OUTSIDER = Path(__file__).resolve().parents[2] / "outsiders" / "complex_plane.py"


@pytest.fixture(scope="module")
def sim():
    return load_simulator(f"{OUTSIDER}:step")


def _diagnose(sim, name, duration):
    scene = dataclasses.replace(load(name), duration=duration)
    return diagnosis(sim, scene, run_user(sim, scene).states())


def test_the_missing_rolling_resistance_is_named(sim):
    diag = _diagnose(sim, "rolling_circle", 0.3)
    assert [n["name"] for n in diag["named"]] == ["rolling_resistance_missing"], diag["verdict"]
    assert diag["verdict"].startswith("explained by rolling_resistance_missing")


def test_a_position_only_difference_is_no_force(sim):
    """spinning_box asks RK4; the outsider steps semi-implicit Euler: in flight its velocities are
    RK4's (a constant g), its positions not. Before: 'a force of Fx +0 N, Fy +0 N, torque +0 N m'."""
    diag = _diagnose(sim, "spinning_box", 0.05)
    assert "no force: your velocities agree" in diag["verdict"], diag["verdict"]
    assert "+0 N" not in diag["verdict"] and "a force of no force" not in diag["verdict"]
    assert diag["force"]["Fx"] is None and diag["force"]["Fy"] is None and diag["force"]["torque"] is None


def test_it_agrees_where_it_follows_the_scene(sim):
    diag = _diagnose(sim, "box_drop", 0.3)
    assert diag["verdict"].startswith("every step agrees"), diag["verdict"]


def test_the_method_the_step_really_is_is_named_with_how_to_declare_it(sim):
    """spinning_box asks RK4 and the outsider declares no integrator: every step of its run is
    semi-implicit Euler's to round-off (the step check under that method passes), so the diagnosis
    names that method and says how to declare it (issue 32, item 5)."""
    diag = _diagnose(sim, "spinning_box", 0.05)
    assert ("your step is semi_implicit_euler: every step agrees with semi_implicit_euler's to round-off "
            "(the scene asks rk4 and your code declares none)") in diag["verdict"], diag["verdict"]
    assert 'INTEGRATOR = "semi_implicit_euler"' in diag["verdict"]
    # where the step is the scene's method (box_drop asks semi-implicit Euler) nothing is said
    assert "your step is" not in _diagnose(sim, "box_drop", 0.3)["verdict"]
