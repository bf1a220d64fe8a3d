"""Under `run --law`, the run line and index.md name the law judged and every effect where it
differs from the scene's, with the parameters that differ (issue 32, item 6); the page's law
lines print no force component of round-off (item 11)."""
from __future__ import annotations

import dataclasses

from compare.checks.law_difference import judged_law_words, law_lines
from compare.checks.row import CheckRow
from compare.report.pages import index_page
from compare.run.lines import verdict_line
from compare.scenarios import load
from scene_types.law_file import with_law

SCENE_FRICTION = {"friction_law": "tanh", "mu": 0.5, "alpha": 100.0}
# an identified alpha carries its fit's round-off: equal to the scene's as printed
JUDGED_FRICTION = {"friction_law": "smooth_coulomb", "mu": 0.4, "alpha": 100.00000000000003}


def _contact(**friction):
    base = {"k": 1e4, "c": 20.0, "damping_law": "linear", "dissipation": 0.0, "mu_roll": 0.0, "roll_law": "tanh",
            "roll_sharpness": None}
    return {**base, **friction}


def _row(passed: bool, law_from="identified") -> dict:
    step = CheckRow("step", "", "semi_implicit_euler", position_error_max=0.0, tolerance_position=1e-15,
                    passed=passed, reason="r")
    return {"name": "box_slide", "pass": passed, "checks": [step.to_json()], "shape": "box",
            "law": {"from": law_from, "judged": _contact(**JUDGED_FRICTION), "scene": _contact(**SCENE_FRICTION),
                    "differences": [{"effect": "friction"}]}}


def test_a_pass_under_the_identified_law_names_it_and_each_effect_that_differs():
    """Before: 'box_slide  pass  1 checks within tolerance', the law judged named nowhere."""
    line = verdict_line(_row(True))
    assert line == ("box_slide            pass under the identified law: friction smooth_coulomb mu 0.4, the "
                    "scene asks tanh mu 0.5 (see the page)"), line
    assert len(line) <= 160


def test_a_fail_under_a_law_file_names_the_file():
    line = verdict_line(_row(False, "laws/mine.toml"))
    assert line.startswith("box_slide            FAIL under the law of laws/mine.toml: friction smooth_coulomb mu 0.4")


def test_the_scenes_own_law_adds_nothing():
    row = _row(True)
    row["law"] = {"from": "scene", "judged": _contact(**SCENE_FRICTION)}
    assert judged_law_words(row["law"]) is None
    assert verdict_line(row) == "box_slide            pass  1 checks within tolerance"


def test_index_md_names_the_law_judged():
    row = _row(True)
    row.update(energy_balance={"custom_sim": {"residual_end": 0.0, "dissipated": {"friction": 1.0}},
                               "mujoco": {"residual_end": 0.0}},
               integrator="semi_implicit_euler", dt=1e-4, position_error_max=0.0, position_error_rms=0.0,
               angle_error_max=0.0, wall_time_custom=0.1, wall_time_mujoco=0.1)
    text = index_page([row], [])
    assert ("- [box_slide](box_slide/index.md): judged under the identified law: friction smooth_coulomb mu 0.4, "
            "the scene asks tanh mu 0.5") in text


def test_the_pages_law_lines_print_no_component_of_round_off():
    """Before: 'force (+1.2, -0) N, torque -3.95e-319 N m' for a friction difference."""
    scene = load("box_slide")
    judged = with_law(scene, dataclasses.replace(scene.contact, mu=0.4), "identified")
    lines = law_lines(judged, [{"effect": "friction", "step": 3, "t": 3e-4, "force": [1.25, -0.0, -3.95e-319],
                                "largest": 1.25, "unit": "N"}])
    text = "\n".join(lines)
    assert "force (+1.25, 0) N, torque 0 N m" in text and "-0" not in text and "e-319" not in text


def test_a_parameter_the_family_does_not_take_is_not_said():
    """Hunt-Crossley takes no c, the linear law no dissipation: 'hunt_crossley dissipation 2 s/m,
    the scene asks linear c 20 N s/m', not 'c 0 N s/m dissipation 2 s/m'."""
    law = {"from": "laws/hc.toml", "differences": [{"effect": "normal"}],
           "judged": _contact(**SCENE_FRICTION, damping_law="hunt_crossley", c=0.0, dissipation=2.0),
           "scene": _contact(**SCENE_FRICTION)}
    assert judged_law_words(law) == ("the law of laws/hc.toml: normal hunt_crossley dissipation 2 s/m, "
                                     "the scene asks linear c 20 N s/m")
