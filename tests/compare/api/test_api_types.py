"""The API's result types (compare/api/), built from metrics.json rows made here by hand: the
status, the exit status, the check rows, the diagnosis, the lines `run` prints; and what
`import compare` costs and resolves to. No scenario runs."""
from __future__ import annotations

import subprocess
import sys
import types
from pathlib import Path

import pytest

import compare
from compare.api.check import Check
from compare.api.diagnosis import Diagnosis
from compare.api.identification import Identification
from compare.api.judgement import Judgement
from compare.api.status import Status, exit_status
from compare.api.subject import CallableStep, simulator_of
from compare.run.lines import verdict_line

ROOT = Path(__file__).resolve().parents[3]


def check_row(name, pos, tol_p, ang, tol_a, passed, reason="why"):
    return {"name": name, "isolates": "", "integrator": "rk4", "position_error_max": pos, "angle_error_max": ang,
            "tolerance_position": tol_p, "tolerance_angle": tol_a, "pass": passed, "reason": reason}


def metrics(name, checks, diagnosis=None, warnings=()):
    passed = all(c["pass"] is not False for c in checks) and any(c["pass"] is not None for c in checks)
    status = "pass" if passed else ("FAIL" if any(c["pass"] is False for c in checks) else "not judged")
    return {"name": name, "checks": checks, "pass": passed, "status": status, "diagnosis": diagnosis,
            "warnings": list(warnings)}


def test_status_words_are_the_rows_words_and_an_unknown_word_is_never_a_pass():
    assert [Status.of(w) for w in ("pass", "FAIL", "not judged", "error", "unstable", "timeout", "skipped")] == [
        Status.PASSED, Status.FAILED, Status.NOT_JUDGED, Status.ERROR, Status.UNSTABLE, Status.TIMEOUT,
        Status.SKIPPED]
    assert Status.of("exploded") is Status.ERROR


@pytest.mark.parametrize("statuses, code", [
    ([Status.PASSED, Status.PASSED], 0),
    ([Status.PASSED, Status.FAILED], 1),
    ([Status.PASSED, Status.NOT_JUDGED], 1),
    ([Status.PASSED, Status.TIMEOUT], 1),
    ([Status.PASSED, Status.SKIPPED], 0),    # a skipped scene does not fail a run ...
    ([Status.SKIPPED, Status.SKIPPED], 1),   # ... but a run where every scene was skipped exits 1
    ([], 1),                                 # never 0 when nothing was judged
])
def test_exit_status(statuses, code):
    assert exit_status(statuses) == code


def test_a_check_reports_the_quantity_furthest_outside_its_tolerance_in_its_unit():
    # position 2e-3 m against 1e-3 m (2 x), angle 5e-2 rad against 1e-2 rad (5 x): the angle
    row = check_row("dynamics", 2e-3, 1e-3, 5e-2, 1e-2, False)
    c = Check.from_row(row)
    assert (c.quantity, c.difference, c.tolerance, c.unit, c.passed) == ("angle", 5e-2, 1e-2, "rad", False)
    assert c.label == "dynamics (rk4)"
    assert c.text == "dynamics (rk4): position 2.000e-03 m (tolerance 1.000e-03 m), angle 5.000e-02 rad (tolerance 1.000e-02 rad)"
    shown = Check.from_row(check_row("reference", 3e-5, None, 1e-4, None, None, "shown, not judged"))
    assert (shown.quantity, shown.difference, shown.tolerance, shown.unit, shown.passed, shown.text) == (
        "position", 3e-5, None, "m", None, "")
    assert shown.reason == "shown, not judged"


def test_a_judgement_prints_run_s_lines_and_says_what_failed():
    law = {"effect": "friction", "law": "sign", "text": "friction: sign, not the scene's tanh"}
    failing = metrics("box_drop", [check_row("step", 1e-3, 1e-9, 0.0, 1e-9, False)],
                      {"verdict": "explained by x (line 8)", "named": [{"name": "x", "seed_line": "line 8",
                                                                        "description": "d"}], "laws": [law]})
    passing = metrics("point_drop", [check_row("step", 0.0, 1e-9, 0.0, 1e-9, True)], {"verdict": "nothing"},
                      ["dt above the limit"])
    j = Judgement.of_report([passing, failing], [("t_shape_drop", "timeout", "stopped after 5 s")])
    assert j.lines == (verdict_line(passing), verdict_line(failing), f"{'':<20} law   {law['text']}",
                       f"{'t_shape_drop':<20} timeout: stopped after 5 s")
    assert j.statuses == {"point_drop": Status.PASSED, "box_drop": Status.FAILED, "t_shape_drop": Status.TIMEOUT}
    assert not j.passed and j.exit_status == 1
    assert j["t_shape_drop"].reason == "stopped after 5 s" and j["t_shape_drop"].checks == ()
    assert j["point_drop"].warnings == ("point_drop: dt above the limit",)
    assert j["box_drop"].diagnosis.named[0].name == "x"
    assert j["box_drop"].failed_checks[0].unit == "m"
    # only the scenes that did not pass carry their diagnosis into the judgement's
    assert j.diagnosis == (f"{'box_drop':<20} diagnosis: explained by x (line 8)\n"
                           f"{'':<20} law   friction: sign, not the scene's tanh")
    with pytest.raises(KeyError, match="no_such: no such scene in this judgement"):
        j["no_such"]
    assert Judgement.of_report([passing], []).passed


def test_a_skipped_scene_is_its_reason_and_fails_nothing_unless_every_scene_was_skipped():
    passing = metrics("point_drop", [check_row("step", 0.0, 1e-9, 0.0, 1e-9, True)])
    j = Judgement.of_report([passing], [("rolling_circle", "skipped", "SHAPES = ('box',) has no circle")])
    assert j.lines[1] == f"{'rolling_circle':<20} skipped  SHAPES = ('box',) has no circle"
    assert j["rolling_circle"].status is Status.SKIPPED and j["rolling_circle"].reason.startswith("SHAPES")
    assert j.passed
    assert not Judgement.of_report([], [("rolling_circle", "skipped", "no circles")]).passed


def test_the_results_are_frozen():
    j = Judgement.of_report([metrics("a", [check_row("step", 0.0, 1e-9, 0.0, 1e-9, True)])], [])
    with pytest.raises(AttributeError):
        j.scenes[0].status = Status.FAILED
    with pytest.raises(TypeError):
        j.scenes[0].checks[0].data["pass"] = False
    assert Diagnosis.from_json(None) is None


def test_an_identification_reads_identify_s_json_as_attributes_and_gives_it_back_whole():
    result = {"scene": "box_drop", "integrator": {"name": "rk4", "residual": 1e-12},
              "gravity": {"g": 9.81, "residual": 0.0},
              "normal": {"law": "linear", "k": 1e4, "c": 20.0, "residual": 2e-11},
              "friction": {"law": None, "residual": 3.0, "closest": {"law": "tanh", "residual": 3.0}},
              "rolling": {"exercised": False, "law": None, "why": "not listed"},
              "body": {"mass": 2.0, "inertia": float("nan"), "contact_points": [[0.1, 0.0]], "residual": 0.0},
              "matches_scene": {"normal": True, "friction": False}}
    ident = Identification.from_result(result)
    assert (ident.scene, ident.integrator.law, ident.normal.law, ident.normal.k, ident.gravity.g) == (
        "box_drop", "rk4", "linear", 1e4, 9.81)
    assert ident.friction.law is None and ident.friction.closest["law"] == "tanh"
    assert not ident.rolling.exercised and ident.normal.exercised
    assert ident.body.inertia is None          # non-finite numbers are null, as identify --json prints them
    assert ident.normal.dissipation is None    # a key the entry lacks
    assert not ident.matches
    assert ident.to_json() == {**result, "body": {**result["body"], "inertia": None}}


def test_a_skipped_scene_s_identification_is_its_reason():
    ident = Identification.from_result({"scene": "rolling_circle", "skipped": "SHAPES = ('box',)"})
    assert ident.skipped == "SHAPES = ('box',)" and ident.normal is None and ident.matches
    assert ident.to_json() == {"scene": "rolling_circle", "skipped": "SHAPES = ('box',)"}


def test_a_function_object_is_a_step_function_and_anything_else_is_bad_input():
    def step(state, scene, dt):
        return state

    sim = simulator_of(step)
    assert isinstance(sim, CallableStep) and sim.kind == "step" and sim.spec.endswith("step")
    assert simulator_of(sim) is sim           # a simulator object (compare.Process) is taken as it is
    with pytest.raises(compare.BadInput, match=r"cannot be called with 3 arguments"):
        simulator_of(lambda scene: scene)
    with pytest.raises(compare.BadInput, match=r"sim = 42: expected \"MODULE:FUNCTION\""):
        simulator_of(42)
    with pytest.raises(compare.BadInput, match=r"no such file"):
        simulator_of("no_such_file.py:step")


def test_a_function_object_s_module_declares_its_integrator_and_shapes_as_a_named_one_does(monkeypatch):
    from compare.scenarios import load

    module = types.ModuleType("box_only_user_module")
    module.SHAPES, module.INTEGRATOR = ("box",), "rk4"
    exec("def step(state, scene, dt):\n    return state\n", module.__dict__)
    module.step.__module__ = module.__name__
    monkeypatch.setitem(sys.modules, module.__name__, module)
    sim = simulator_of(module.step)
    circle, box = load("rolling_circle"), load("box_drop")
    assert sim.skip_reason(circle) == "a circle body, not in the module's SHAPES = ('box',)"
    assert sim.skip_reason(box) is None and sim.integrator_for(box) == "rk4"
    plain = simulator_of(lambda state, scene, dt: state)
    assert plain.skip_reason(circle) is None and plain.integrator_for(box) == box.integrator


def test_compare_process_is_the_process_simulator_where_the_harness_has_one(monkeypatch):
    fake = types.ModuleType("compare.usersim.process")
    fake.Process = type("Process", (), {})
    monkeypatch.setitem(sys.modules, "compare.usersim.process", fake)
    monkeypatch.delitem(compare.__dict__, "Process", raising=False)
    assert compare.Process is fake.Process
    monkeypatch.delitem(compare.__dict__, "Process")


def test_compare_identify_is_the_api_function_and_the_package_stays_apart():
    import compare.identification.report   # noqa: F401 - the identification package, imported beside it
    from compare.api.identify import identify_scenes

    assert compare.identify is identify_scenes
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        _ = compare.nothing


def test_import_compare_imports_nothing_else():
    code = "import sys, compare; print(sorted(m for m in sys.modules if m.split('.')[0] in " \
           "('compare', 'scene_types', 'custom_sim', 'mujoco_models', 'numpy')))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True)
    assert out.stdout.strip() == "['compare']"
