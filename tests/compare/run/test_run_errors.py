"""No crash reaches the user: a scenario that fails in any way becomes its own error row.

A worker process that dies, an exception inside one scenario (MuJoCo refusing a model, say):
the other scenarios finish, the exit status is 1, the row names the cause in one line, and
nothing half-written is left behind.
"""
import os

import pytest

from compare.run.outcome import one_line, run_one
from compare.run.processes import run_scenes
from compare.scenarios import load
from short_scene import short_scene

DYING = "point_drop_short"


def dying_worker(scene, out, simulator=None):
    """A worker that is killed while running one scene (as a segfault in compiled code would)."""
    if scene.name == DYING:
        os._exit(70)
    return run_one(scene, out, simulator)


def test_a_worker_that_dies_costs_only_its_scenario(tmp_path, monkeypatch):
    scenes = [load(str(short_scene(tmp_path, "point_drop", 0.3))),
              load(str(short_scene(tmp_path, "box_slide", 0.3)))]
    out = tmp_path / "out"
    out.mkdir()
    outcomes = run_scenes(scenes, lambda s: dying_worker(s, str(out)), jobs=2)
    assert outcomes["box_slide_short"].row is not None, outcomes
    status, cause = outcomes[DYING].failure
    assert status == "error" and "exit code 70" in cause, cause
    assert not [p for p in out.iterdir() if p.name.startswith(".")], "no temporary left behind"


def test_an_exception_in_a_scenario_becomes_its_error_row(tmp_path, monkeypatch):
    import mujoco_models

    def refuse(*args, **kwargs):
        raise ValueError("mass and inertia of moving bodies must be larger than mjMINVAL\nsecond line")

    monkeypatch.setattr(mujoco_models, "simulate_mujoco", refuse)
    scene = load(str(short_scene(tmp_path, "point_drop", 0.2)))
    out = tmp_path / "out"
    out.mkdir()
    outcome = run_one(scene, str(out))
    assert outcome.row is None
    status, cause = outcome.failure
    assert status == "error"
    assert cause == "ValueError: mass and inertia of moving bodies must be larger than mjMINVAL"
    assert list(out.iterdir()) == []


@pytest.mark.parametrize("exc, expected", [(ValueError("a\nb"), "ValueError: a"), (RuntimeError(""), "RuntimeError")])
def test_one_line_cause(exc, expected):
    assert one_line(exc) == expected


def test_a_step_that_raises_is_said_once_with_its_scene(tmp_path, capsys):
    """Before: the row's line, then the same words again on stderr as 'error: ...' with no
    scene, the traceback printed apart from both, and '(expected a state ...)' after an
    exception (the step raised: nothing it returned was wrong)."""
    from compare.cli import main

    sim = tmp_path / "raises.py"
    sim.write_text("def step(state, scene, dt):\n    raise ValueError('negative height')\n")
    scene = short_scene(tmp_path, "box_slide", 0.05)
    status = main(["run", str(scene), "--sim", f"{sim}:step", "--out", str(tmp_path / "out"), "--jobs", "1"])
    out, err = capsys.readouterr()
    assert status == 1
    both = out + err
    assert both.count("raised ValueError: negative height") == 1, both
    line = next(x for x in out.splitlines() if "negative height" in x)
    assert line.startswith("box_slide_short") and "(expected" not in line
    assert "box_slide_short: Traceback (your code" in err
