"""The checks as units (compare/checks/check.py, registry.py): one protocol, one table; `run`
walks it all and `validate` the same pipeline with the checks that need no MuJoCo."""
import dataclasses
import re
from pathlib import Path

from compare.checks.case import Case
from compare.checks.registry import CHECKS, without
from compare.checks.result import Result
from compare.cli import main
from compare.run.scenario import collect_runs, judge, run_scenario
from compare.scenarios import load
from compare.usersim import load_simulator

ROOT = Path(__file__).resolve().parents[3]

# A user's step that forgot the ground: gravity alone, semi-implicit Euler.
FORGOT_THE_GROUND = '''
def step(state, scene, dt):
    x, y, th, vx, vy, om = (float(v) for v in state)
    vy -= scene["g"] * dt
    return [x + dt * vx, y + dt * vy, th + dt * om, vx, vy, om]
'''


def test_every_check_keeps_to_the_protocol_in_the_order_of_metrics_json():
    assert list(CHECKS) == ["identical", "step", "dynamics", "contact", "reference", "native", "energy", "ground"]
    for name, check in CHECKS.items():
        assert check.name == name and check.needs <= {"mujoco", "reference"}
        assert callable(check.applies) and callable(check.judge)
    assert list(without("mujoco", "reference")) == ["identical", "step", "energy", "ground"]


def test_validate_judges_what_run_judges_for_the_checks_it_has():
    """The rows validate's walk gives are run's rows of the same checks, to the last key."""
    scene = dataclasses.replace(load("box_slide"), duration=0.05)
    sim = load_simulator(f"{ROOT}/examples/buggy_sim.py:step")
    whole = run_scenario(scene, sim)
    rows, _ = judge(collect_runs(Result(scene), Case(scene), sim), without("mujoco", "reference"))
    assert [r.name for r in rows] == ["identical", "step", "ground"]
    assert [r.to_json() for r in rows] == [r.to_json() for r in whole.checks if r.name in ("identical", "step", "ground")]


def test_validate_fails_a_body_that_falls_through_the_ground_on_its_own_line(tmp_path, capsys):
    """point_drop (0.6 s): the point falls through the ground at about 0.37 s with no force to
    stop it; validate's ground check, which needs no MuJoCo, says so below its columns."""
    (tmp_path / "forgot.py").write_text(FORGOT_THE_GROUND)
    text = (ROOT / "scenarios" / "point_drop.toml").read_text()
    scene = tmp_path / "point_drop.toml"
    scene.write_text("\n".join("duration = 0.6" if line.startswith("duration") else line for line in text.splitlines()))
    code = main(["validate", f"{tmp_path / 'forgot.py'}:step", str(scene)])
    printed = capsys.readouterr().out
    assert code == 1
    sank = r"^ +ground \(semi_implicit_euler\) FAIL: the body sank through the ground: at step \d+ "
    assert re.search(sank, printed, re.MULTILINE), printed


# A user's step whose state turns NaN at its 5th call.
TURNS_NAN = '''
CALLS = [0]

def step(state, scene, dt):
    CALLS[0] += 1
    x, y, th, vx, vy, om = (float(v) for v in state)
    if CALLS[0] >= 5:
        return [x, float("nan"), th, vx, vy, om]
    vy -= scene["g"] * dt
    return [x + dt * vx, y + dt * vy, th + dt * om, vx, vy, om]
'''


def test_the_run_under_test_is_validated_once_where_it_is_collected(tmp_path):
    """A run that turns NaN never reaches a check: the scenario is unstable at that step, with
    no row; and no check but step (whose finite prefix serves the diagnosis's probes, states
    that are not the run under test) tests its states for finite numbers again."""
    import numpy as np
    import pytest

    from compare.run.scenario import valid_states

    (tmp_path / "nan_sim.py").write_text(TURNS_NAN)
    scene = dataclasses.replace(load("point_drop"), duration=0.01)
    result = run_scenario(scene, load_simulator(f"{tmp_path / 'nan_sim.py'}:step"))
    assert result.checks == [] and "returned a non-finite state" in result.error and " at step 5 " in result.error
    states = np.zeros((scene.steps + 1, 6))
    states[37, 1] = np.nan
    with pytest.raises(RuntimeError, match="a run to judge has shape"):
        valid_states(scene, states)
    again = [p.name for p in sorted((ROOT / "compare" / "checks").glob("*_check.py"))
             if "isfinite" in p.read_text() and p.name != "step_check.py"]
    assert again == [], again
