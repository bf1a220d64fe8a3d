"""`bench`: what is timed is the scene's real work in both simulators, and the output format.

No timed assertions: speed is measured by `python -m compare bench`, comparing both
simulators in one run. Here: the benchmarked loops reach the same state as the recorded
simulations (so nothing is skipped), and the JSON lines carry the contract's keys.
"""
from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from compare.tools.accuracy.benchmark import (custom_step_runner, linearity, mujoco_setup, mujoco_step_runner)
from compare.cli import main
from compare.scenarios import builtin_names, load
from custom_sim import Stepper, simulate
from short_scene import short_scene

pytest.importorskip("mujoco_models")


@pytest.mark.parametrize("name", ["box_drop", "rolling_circle"])
def test_custom_benchmark_loop_does_the_scene(name):
    """The unrecorded loop ends bit-identical to the recorded simulation: same compiled steps."""
    scene = dataclasses.replace(load(name), duration=0.5)
    traj = simulate(scene)
    stepper = Stepper(scene)
    stepper.advance(scene.steps)
    assert np.array_equal(stepper.state, traj.states()[-1])
    custom_step_runner(scene, scene.steps)()  # runs without recording or error


@pytest.mark.parametrize("name", ["box_drop", "rolling_circle"])
def test_mujoco_benchmark_loops_do_the_scene(name):
    """mj_step with nstep and rollout from the keyframe state reach the state that
    simulate_mujoco records: the timed C loops do the whole scene."""
    import mujoco
    from mujoco import rollout
    from mujoco_models import simulate_mujoco
    from mujoco_models.frames import states_from_q
    from mujoco_models.rigid_body import rigid_body

    scene = dataclasses.replace(load(name), duration=0.5)
    traj = simulate_mujoco(scene)
    model, data, state = mujoco_setup(scene)
    n = traj.steps
    props = rigid_body(scene.body)
    mujoco_step_runner(model, data, state, n, "mj_step")()
    after_mj_step = states_from_q(props, data.qpos, data.qvel)[0]
    assert np.allclose(after_mj_step, traj.states()[-1], rtol=0, atol=1e-12)
    out = np.empty((1, n, state.size))
    rollout.rollout(model, data, state, nstep=n, state=out)
    mujoco.mj_setState(model, data, out[0, -1], mujoco.mjtState.mjSTATE_FULLPHYSICS)
    after_rollout = states_from_q(props, data.qpos, data.qvel)[0]
    assert np.allclose(after_rollout, after_mj_step, rtol=0, atol=1e-12)


def test_bench_json_lines_have_the_contract_keys(capsys):
    assert main(["bench", "elastic_bounce", "point_drop", "--json", "--repeats", "1", "--rounds", "1"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert len(lines) == 2
    for line, name in zip(lines, ["elastic_bounce", "point_drop"]):
        row = json.loads(line)
        assert row["name"] == name
        assert row["ns_per_step_custom"] > 0 and row["ns_per_step_mujoco"] > 0
        assert row["ratio"] == pytest.approx(row["ns_per_step_mujoco"] / row["ns_per_step_custom"])


def test_bench_table_and_linearity(tmp_path, capsys):
    assert main(["bench", str(short_scene(tmp_path, "elastic_bounce", 0.3)), "--repeats", "1", "--rounds", "1"]) == 0
    out = capsys.readouterr().out
    assert "elastic_bounce_short" in out and "ratio" in out   # the table's format, whatever the figures
    lin = linearity(dataclasses.replace(load("point_drop"), duration=0.2), repeats=1)
    assert lin.custom_ratio > 0 and lin.mujoco_ratio > 0   # reported, not asserted: no timed tests


def test_bench_rejects_an_unknown_scene(capsys):
    assert main(["bench", "no_such_scene"]) == 2
    assert "unknown scenario" in capsys.readouterr().err


# The floor and custom_sim step the same law with the same method, in another order of
# operations: their states part by round-off, which these motions keep near eps per step
FLOOR_AGREEMENT = 1e-9   # m, m/s, rad over each scene's whole run


@pytest.mark.parametrize("name", builtin_names())
def test_the_minimal_loop_steps_the_same_law_as_custom_sim(name):
    """bench's floor is only a floor of the same work: over the scene's whole run (every
    landing, bounce and rest) it ends where custom_sim's run does, with the scene's integrator."""
    from compare.tools.accuracy import minimal_loop

    scene = load(name)
    assert minimal_loop.applies(scene)
    floor = minimal_loop.runner(scene)()
    ours = simulate(scene).states()[-1]
    assert np.max(np.abs(floor - ours)) < FLOOR_AGREEMENT, (floor, ours)


def test_the_minimal_loop_of_elastic_bounce_does_its_contacts():
    """Its floor is a few additions per step because the ball flies 98 % of the time, not
    because the compiler dropped the contact: stopped in its first landing it agrees too."""
    from compare.tools.accuracy import minimal_loop

    scene = dataclasses.replace(load("elastic_bounce"), duration=0.46)   # lands at 0.45 s
    ours = simulate(scene).states()
    assert ours[-1, 1] < 0.0 and ours[-1, 4] > ours[-2, 4], "the point is in the ground, pushed up"
    floor = minimal_loop.runner(scene)()
    assert np.max(np.abs(floor - ours[-1])) < FLOOR_AGREEMENT, (floor, ours[-1])
