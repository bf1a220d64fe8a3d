"""One typed result (compare/checks/summary.py, status.py): one Status for every layer, one
exit status, metrics.json read back by one function, a step failure typed."""
import dataclasses
import json
from pathlib import Path

from compare.checks.case import Case
from compare.checks.result import Result, metrics_json
from compare.checks.status import Status, exit_status, of_rows
from compare.checks.summary import StepFailure, read_summary
from compare.run.lines import failure_text
from compare.run.scenario import run_scenario
from compare.scenarios import load
from compare.usersim import load_simulator

ROOT = Path(__file__).resolve().parents[3]


def test_one_status_for_the_checks_the_run_and_the_api():
    import compare.api.status as api
    assert api.Status is Status and api.exit_status is exit_status
    assert Status.PASSED == "pass" and json.dumps(Status.FAILED) == '"FAIL"'
    assert exit_status([Status.SKIPPED]) == 1 and exit_status([Status.PASSED, Status.SKIPPED]) == 0
    assert exit_status([Status.PASSED, Status.NOT_JUDGED]) == 1
    assert of_rows([]) is Status.NOT_JUDGED


def test_the_buggy_example_read_back_from_its_metrics_json():
    """box_slide (0.05 s) under the buggy example: the Summary read from the dict metrics.json
    holds (through JSON) has the scene's status as an enum, its rows, and its step failure typed,
    the step and component the row's details name; the verdict line tells it in those words."""
    scene = dataclasses.replace(load("box_slide"), duration=0.05)
    result = run_scenario(scene, load_simulator(f"{ROOT}/examples/buggy_sim.py:step"))
    assert result.status is Status.FAILED
    row = json.loads(json.dumps(metrics_json(result)))
    summary = read_summary(row)
    assert summary.status is Status.FAILED and not summary.passed
    assert [c.to_json() for c in summary.checks] == row["checks"]
    assert summary.failed_checks == tuple(row["failed_checks"])
    step = next(c for c in summary.checks if c.name == "step")
    failure = StepFailure.of(step)
    d = row["checks"][[c["name"] for c in row["checks"]].index("step")]
    assert (failure.step, failure.time, failure.component, failure.residual, failure.bound) == \
        (d["first_step"], d["first_time"], d["component"], d["first_residual"], d["first_bound"])
    assert failure.residual > failure.bound and failure.time == failure.step * scene.dt
    assert failure_text(step) == f"step (semi_implicit_euler): {failure.describe()}"


def test_a_scene_with_no_rows_is_not_judged_and_a_skipped_one_skipped():
    scene = load("point_drop")
    result = Result(scene, case=Case(scene))
    assert result.status is Status.NOT_JUDGED
    result.skipped = "no points"
    assert result.status is Status.SKIPPED
