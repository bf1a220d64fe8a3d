"""A diagnosis that never points the wrong way (issue 32, item 7), on a newcomer's box: the
seed's step with Hunt-Crossley and smooth Coulomb, correct except the friction torque's sign
(tests/outsiders/hc_box.py), and its bug-free copy.

- no catalogued mistake is printed unless it explains every probed step (no partial match);
- the torque residual is read as r x Ft with the opposite sign, at every disagreeing moment;
- the run gains energy against the scene's law where custom_sim under the same law loses it;
- the bug-free copy gets no mistake named and no finding.
"""
from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from compare.oracle.reference import Equations
from compare.scenarios import load
from compare.diagnosis import diagnosis, render_markdown
from compare.usersim import load_simulator, run_user

OUTSIDER = Path(__file__).resolve().parents[2] / "outsiders" / "hc_box.py"

# A spinning box landing on a Hunt-Crossley ground (dissipation 2 s/m) with smooth Coulomb
# friction: it lands on a corner at 0.345 s and slides while it turns.
SCENE = """
description = "Spinning box landing on a Hunt-Crossley ground with smooth Coulomb friction"
duration = 0.5
dt = 2e-5
integrator = "semi_implicit_euler"
effects = ["gravity", "contact", "friction"]

[body]
shape = "box"
mass = 0.7
size = [0.2, 0.1]

[contact]
k = 1e4
damping_law = "hunt_crossley"
dissipation = 2.0
friction_law = "smooth_coulomb"
mu = 0.4
alpha = 100.0

[initial]
position = [0.0, 0.35]
velocity = [1.5, 1.0]
angle = 0.0
angular_velocity = 12.0
"""


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    path = tmp_path_factory.mktemp("hc") / "hc_spin.toml"
    path.write_text(SCENE)
    return load(str(path))


def _diagnose(scene, function):
    sim = load_simulator(f"{OUTSIDER}:{function}")
    return sim, diagnosis(sim, scene, run_user(sim, scene).states())


@pytest.fixture(scope="module")
def buggy(scene):
    return _diagnose(scene, "step")


def test_the_friction_torque_sign_is_read_from_the_residual(scene, buggy):
    """Before: 'no catalogued mistake explains the residual', the torque left unread. The
    residual at each disagreeing moment is -2 x sum(-r_y Ft): checked against the outsider's own
    two steps (the buggy minus the fixed one, I domega / dt), not the harness's reference."""
    sim, diag = buggy
    assert diag["named"] == []
    assert "the friction torque (r x Ft) has the opposite sign at every moment your step disagrees" in diag["verdict"]
    fixed = load_simulator(f"{OUTSIDER}:step_fixed")
    inertia = Equations.from_scene(scene).inertia
    off = [e for e in diag["moments"]["moments"] if not e["agrees"]]
    assert off, "the box slides while it turns: some moment disagrees"
    for e in off:
        z = np.array(e["state"])
        torque = inertia * (sim.call(z, _sd(scene), scene.dt)[5] - fixed.call(z, _sd(scene), scene.dt)[5]) / scene.dt
        assert e["force"]["torque"] == pytest.approx(torque, rel=1e-6), e["name"]
        assert e["force"]["torque"] == pytest.approx(-2.0 * e["force"]["torque_parts"]["friction"], rel=1e-3)
        assert e["force"]["Fx"] is None and e["force"]["Fy"] is None   # no force residual: none printed


def test_the_energy_gain_is_said_with_both_figures(buggy):
    """Before: no line said the buggy box gains energy on a damped scene."""
    _, diag = buggy
    gain = diag["energy_gain"]
    assert gain is not None and gain["user"] > gain["margin"] > 0.0 > gain["custom"]
    assert f"gains {gain['user']:.3g} J" in diag["verdict"] and f"loses {-gain['custom']:.3g} J" in diag["verdict"]


def test_no_partial_match_is_printed(buggy):
    """Before: 'corners_not_rotated explains all but 2 of 5 steps' for code whose corners turn."""
    _, diag = buggy
    text = diag["verdict"] + render_markdown(diag)
    assert "explains all but" not in text and "not named" not in text.lower()
    for entry in diag["not_named"]:
        assert entry["name"] not in text


def test_the_bug_free_copy_gets_nothing_named(scene):
    _, diag = _diagnose(scene, "step_fixed")
    assert diag["named"] == [] and diag["energy_gain"] is None and diag["not_named"] == []
    assert diag["verdict"].startswith("every step agrees with the reference step to round-off"), diag["verdict"]


def _sd(scene):
    from compare.usersim.scene_dict import scene_dict
    return scene_dict(scene)


# The newcomer's buggy step under a Hunt-Crossley dissipation of its own (4 s/m, the scene's 2):
# two faults at once, one the torque (no inertia reproduces it), one the normal force's law.
OTHER_DISSIPATION = f'''
import importlib.util
_spec = importlib.util.spec_from_file_location("hc_box_source", {str(OUTSIDER)!r})
_hc = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_hc)


def step(state, scene, dt):
    return _hc.step(state, {{**scene, "contact": {{**scene["contact"], "dissipation": 4.0}}}}, dt)
'''


def test_an_effect_is_named_where_its_reading_does_not_rest_on_what_failed(scene, tmp_path):
    """Before: no law at all, since the body (the torques) failed; the normal force is read from
    vy at the points where contact acts, which the torque does not enter."""
    from compare.diagnosis.laws import law_findings

    path = tmp_path / "hc_other.py"
    path.write_text(OTHER_DISSIPATION)
    sim = load_simulator(f"{path}:step")
    found = law_findings(sim, scene, None)
    assert [f["effect"] for f in found] == ["normal"], found
    assert found[0]["law"] == "hunt_crossley" and "dissipation 4 s/m" in found[0]["text"], found[0]["text"]


def test_an_effect_whose_reading_rests_on_what_failed_is_not_read():
    """Synthetic identify answers: the contact points wrong leave nothing read; the inertia wrong
    leaves the normal force and friction read, the rolling resistance not."""
    from compare.diagnosis.laws import findings

    scene = load("rolling_circle")
    entry = {"exercised": True, "law": "tanh", "mu": 0.3, "alpha": 100.0, "mu_roll": 0.01, "roll_sharpness": 10.0}
    result = {"integrator": {"name": scene.integrator}, "body": {"points_match": True},
              "matches_scene": {"integrator": True, "gravity": True, "normal": True, "friction": False,
                                "rolling": False, "body": False},
              "friction": entry, "rolling": {**entry, "law": "tanh"}}
    out = {f["effect"]: f for f in findings(result, scene, scene.integrator)}
    assert out["friction"]["law"] == "tanh" and "mu 0.3" in out["friction"]["text"]
    assert out["rolling"].get("unread") and "inertia" in out["rolling"]["text"]
    result["body"]["points_match"] = False
    assert all(f.get("unread") for f in findings(result, scene, scene.integrator))


def test_no_minus_zero_and_no_infinite_ratio_in_the_words():
    """Before: 'contact at point 0 (+0, -0)' for a point touching at its centre, and a residual
    over a round-off of 0 (a point mass's theta) shown as 1e+300 round-offs."""
    import numpy as np

    from compare.checks.step_check import _point_name
    from compare.oracle.reference import Equations
    from compare.diagnosis.diagnose import _ratio

    scene = load("elastic_bounce")
    eq = dataclasses.replace(Equations.from_scene(scene), points=((0.0, -0.0),))
    assert _point_name(eq, 0) == "0 (+0, +0)"
    assert _ratio(float(np.float64(1e300))) == "any (round-off 0)" and _ratio(2.5) == "2.5"
