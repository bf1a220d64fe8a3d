"""compare.judge and compare.identify on real runs: the seed's step passes, the buggy example
fails with the diagnosis naming its two mistakes, nothing is written unless asked, the lines
are `run`'s own, and identify's objects are exactly what `identify --json` prints."""
from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

import compare
from short_scene import short_scene

ROOT = Path(__file__).resolve().parents[3]
SEED = str(ROOT / "examples" / "seed_sim.py")
BUGGY = str(ROOT / "examples" / "buggy_sim.py")
# box_drop to 0.25 s: the buggy example's first wrong step is 4188 (t = 0.2094 s), at touchdown
DURATION = 0.25


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    return short_scene(tmp_path_factory.mktemp("scene"), "box_drop", DURATION)


@pytest.fixture(scope="module")
def buggy(scene, tmp_path_factory):
    """The buggy example judged from a working folder of its own, with nothing asked to be written."""
    here = tmp_path_factory.mktemp("cwd")
    temp = tmp_path_factory.mktemp("temp")   # its own temporary folder: other tests run beside it
    old, old_temp = os.getcwd(), tempfile.tempdir
    os.chdir(here)
    tempfile.tempdir = str(temp)
    try:
        judgement = compare.judge(BUGGY + ":step", str(scene), jobs=1)
    finally:
        os.chdir(old)
        tempfile.tempdir = old_temp
    return judgement, sorted(here.iterdir()), set(temp.iterdir())


def test_the_buggy_example_fails_and_the_diagnosis_names_its_mistakes(buggy):
    judgement, _, _ = buggy
    assert not judgement.passed and judgement.exit_status == 1
    scene = judgement["box_drop_short"]
    assert scene.status is compare.Status.FAILED
    assert {m.name for m in scene.diagnosis.named} == {"friction_on_com_velocity", "box_inertia_about_corner"}
    assert "friction_on_com_velocity" in judgement.diagnosis
    failed = {c.name for c in scene.failed_checks}
    assert {"identical", "step", "dynamics"} <= failed
    step = next(c for c in scene.checks if c.name == "step")
    assert step.difference > step.tolerance and step.unit in ("m", "rad")
    assert "at step 4188" in step.text          # the first step whose torque the mistakes change
    assert judgement.lines[0].startswith("box_drop_short       FAIL  ")


def test_judge_writes_nothing_unless_asked(buggy):
    _, written, left = buggy
    assert written == [] and left == set()
    assert buggy[0].report is None


@pytest.mark.slow
def test_a_function_object_passes_and_out_writes_the_report_run_writes(scene, tmp_path):
    sys.path.insert(0, str(ROOT / "examples"))
    try:
        import seed_sim
    finally:
        sys.path.remove(str(ROOT / "examples"))
    judgement = compare.judge(seed_sim.step, [scene], out=tmp_path / "report", jobs=1)
    assert judgement.passed and judgement.exit_status == 0
    assert judgement.lines == ("box_drop_short       pass  5 checks within tolerance",)
    assert judgement.report == (tmp_path / "report" / "index.md").resolve()
    metrics = json.loads((tmp_path / "report" / "box_drop_short" / "metrics.json").read_text())
    assert metrics["status"] == judgement["box_drop_short"].status.value == "pass"
    assert [c["name"] for c in metrics["checks"]] == [c.name for c in judgement["box_drop_short"].checks]


@pytest.mark.slow
def test_run_prints_the_lines_and_exits_with_the_status_judge_returns(buggy, scene, tmp_path):
    out = subprocess.run([sys.executable, "-m", "compare", "run", str(scene), "--sim", BUGGY + ":step",
                          "--out", str(tmp_path), "--jobs", "1"], capture_output=True, text=True, cwd=ROOT)
    assert out.returncode == buggy[0].exit_status == 1
    assert out.stdout.splitlines()[:-1] == list(buggy[0].lines)
    assert out.stdout.splitlines()[-1] == f"report: {tmp_path / 'index.md'}"


@pytest.mark.slow
def test_identify_gives_what_identify_json_prints():
    out = subprocess.run([sys.executable, "-m", "compare", "identify", SEED + ":step", "box_drop", "--json"],
                         capture_output=True, text=True, cwd=ROOT, check=True)
    (found,) = compare.identify(SEED + ":step", "box_drop")
    printed = json.loads(out.stdout)
    assert found.to_json().keys() == printed.keys()
    assert {**found.to_json(), "seconds": None} == {**printed, "seconds": None}   # all but the time it took
    assert (found.normal.law, found.friction.law, found.integrator.law) == ("linear", "tanh", "semi_implicit_euler")
    assert found.normal.k == pytest.approx(1e4, rel=1e-9) and found.matches


def test_bad_input_raises_one_clear_error_before_anything_runs(tmp_path):
    with pytest.raises(compare.SceneError, match="no_such_scene: unknown scenario"):
        compare.judge(SEED + ":step", "no_such_scene", out=tmp_path / "r")
    with pytest.raises(compare.BadInput, match="timeout = 0: expected a positive number"):
        compare.judge(SEED + ":step", "box_drop", timeout=0)
    with pytest.raises(compare.BadInput, match="no such file"):
        compare.identify("nowhere.py:step", "box_drop")
    assert not (tmp_path / "r").exists()


def test_a_scene_the_code_does_not_do_is_skipped_with_its_reason():
    box_only = str(ROOT / "tests" / "outsiders" / "box_only_shapes.py") + ":step"   # SHAPES = ("box",)
    judgement = compare.judge(box_only, "rolling_circle", jobs=1)
    scene = judgement["rolling_circle"]
    assert scene.status is compare.Status.SKIPPED and "circle" in scene.reason and scene.checks == ()
    assert judgement.lines == (f"{'rolling_circle':<20} skipped  {scene.reason}",)
    assert not judgement.passed          # every scene skipped: nothing was judged
    (found,) = compare.identify(box_only, "rolling_circle")
    assert found.skipped == scene.reason and found.normal is None
