"""The pytest plugin (compare/pytest_plugin.py) as a user meets it: a test folder outside the
repository, `pytest -p compare.pytest_plugin --contact-sim ...` (the entry point registers the
same module once the package is installed), one test per scene, the verdict and the diagnosis
in pytest's output and in its JUnit file; without --contact-sim, nothing added."""
from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from short_scene import short_scene

pytest_plugins = ["pytester"]

ROOT = Path(__file__).resolve().parents[3]
PLUGIN = ("-p", "compare.pytest_plugin")
# box_drop to 0.25 s: the buggy example's first wrong step is 4188 (t = 0.2094 s), at touchdown
DURATION = 0.25

USER_TEST = '''
def test_my_own_check(contact_harness):   # the fixture: the API, with the command line's choices
    assert contact_harness.sim.endswith(":step") and contact_harness.scenes == ("box_drop_short.toml",)
    assert callable(contact_harness.judge) and callable(contact_harness.identify)
'''


@pytest.fixture
def user(pytester, monkeypatch, tmp_path_factory):
    """A user's test folder (pytester's, outside the repository) holding a short box_drop; the
    harness's cache in a folder of this test's own, so the second run reuses the first's
    scene-only work; entry points not loaded (the plugin comes by -p, installed or not)."""
    short_scene(pytester.path, "box_drop", DURATION)
    monkeypatch.setenv("CONTACT_HARNESS_CACHE", str(tmp_path_factory.mktemp("cache")))
    monkeypatch.setenv("PYTEST_DISABLE_PLUGIN_AUTOLOAD", "1")
    monkeypatch.setenv("PYTHONPATH", str(ROOT))
    pytester.makepyfile(test_mine=USER_TEST)
    return pytester


# A judgement made by hand (no scenario runs): the plugin's mapping of each status to pytest's outcome
FAKE_JUDGE = '''
from compare.api.harness import Harness
from compare.api.judgement import Judgement

ROW = {"name": "box_drop", "pass": False, "status": "FAIL", "warnings": [],
       "diagnosis": {"verdict": "explained by box_inertia_about_corner", "named": [], "laws": []},
       "checks": [{"name": "step", "integrator": "rk4", "position_error_max": 1e-3, "angle_error_max": 0.0,
                   "tolerance_position": 1e-9, "tolerance_angle": 1e-9, "pass": False, "reason": ""}]}
SEEN = []


def judge(self, sim=None, scenes=None, **options):
    SEEN.append(list(scenes))
    assert len(SEEN) == 1, "judged once per session"
    return Judgement.of_report([ROW], [("rolling_circle", "skipped", "SHAPES = ('box',): no circle"),
                                       ("point_drop", "error", "my_sim.py:step at step 3 raised ZeroDivisionError")])


Harness.judge = judge
'''


def test_each_status_is_pytest_s_outcome_a_skip_with_its_reason(pytester, monkeypatch):
    monkeypatch.setenv("PYTEST_DISABLE_PLUGIN_AUTOLOAD", "1")
    monkeypatch.setenv("PYTHONPATH", str(ROOT))
    pytester.makeconftest(FAKE_JUDGE)
    result = pytester.runpytest_subprocess(*PLUGIN, "--contact-sim", "my_sim.py:step", "--contact-scenes",
                                           "box_drop,rolling_circle,point_drop", "-rs")
    result.assert_outcomes(failed=2, skipped=1)
    result.stdout.fnmatch_lines(["*_ contact-sim::box_drop _*",
                                 "box_drop             FAIL  step (rk4): *",
                                 "diagnosis: explained by box_inertia_about_corner",
                                 "*_ contact-sim::point_drop _*",
                                 "point_drop           error: my_sim.py:step at step 3 raised ZeroDivisionError",
                                 "SKIPPED ?1? *scenarios/rolling_circle.toml:?: SHAPES = ('box',): no circle"])


def test_without_contact_sim_the_plugin_adds_nothing(pytester, monkeypatch):
    monkeypatch.setenv("PYTEST_DISABLE_PLUGIN_AUTOLOAD", "1")
    monkeypatch.setenv("PYTHONPATH", str(ROOT))
    pytester.makepyfile(test_plain="def test_one():\n    pass\n")
    result = pytester.runpytest_subprocess(*PLUGIN, "--collect-only", "-q")
    assert result.ret == 0
    assert [line for line in result.outlines if "::" in line] == ["test_plain.py::test_one"]
    assert "contact-sim" not in result.stdout.str()


@pytest.mark.slow   # two judgements of a short scene in fresh processes: some 10 s of CPU
def test_a_user_s_tests_pass_on_the_seed_and_fail_on_the_buggy_example_with_the_diagnosis(user):
    common = (*PLUGIN, "--contact-scenes", "box_drop_short.toml", "-rA")
    passed = user.runpytest_subprocess(*common, "--contact-sim", str(ROOT / "examples" / "seed_sim.py") + ":step")
    passed.assert_outcomes(passed=2)
    assert passed.ret == 0
    passed.stdout.fnmatch_lines(["*contact-sim: *seed_sim.py:step on box_drop_short.toml*",
                                 "PASSED contact-sim::box_drop_short"])

    failed = user.runpytest_subprocess(*common, "--contact-sim", str(ROOT / "examples" / "buggy_sim.py") + ":step",
                                       "--junitxml", "junit.xml")
    failed.assert_outcomes(passed=1, failed=1)
    assert failed.ret == 1
    failed.stdout.fnmatch_lines(["*_ contact-sim::box_drop_short _*",
                                 "box_drop_short       FAIL  identical (semi_implicit_euler): *",
                                 "diagnosis: explained by friction_on_com_velocity *box_inertia_about_corner*",
                                 "FAILED contact-sim::box_drop_short - box_drop_short       FAIL  *"])
    suite = ET.parse(user.path / "junit.xml").getroot().find("testsuite")
    assert (suite.get("tests"), suite.get("failures"), suite.get("errors")) == ("2", "1", "0")
    case = next(c for c in suite.iter("testcase") if c.get("classname") == "contact-sim")
    assert case.get("name") == "box_drop_short"
    message = case.find("failure").get("message")
    assert message.startswith("box_drop_short       FAIL  identical (semi_implicit_euler)")
    assert "diagnosis: explained by friction_on_com_velocity" in message


def test_an_unknown_scene_is_one_line_at_collection_and_a_missing_module_fails_each_test(user):
    result = user.runpytest_subprocess(*PLUGIN, "--contact-sim", "x.py:step", "--contact-scenes", "no_such_scene")
    assert result.ret == 2
    result.stdout.fnmatch_lines(["--contact-scenes: no_such_scene: unknown scenario (expected a built-in name*"])
    assert "Traceback" not in result.stdout.str()
    result = user.runpytest_subprocess(*PLUGIN, "--contact-sim", "x.py:step", "--contact-scenes",
                                       "box_drop_short.toml", "-k", "contact")
    result.assert_outcomes(failed=1, deselected=1)
    result.stdout.fnmatch_lines(["--sim x.py: no such file (expected a path to a .py file or a dotted module name)"])
