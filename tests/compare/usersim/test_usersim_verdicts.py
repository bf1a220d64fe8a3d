"""The worked example: the seed-style simulator passes `identical` on every built-in scene, the
buggy copy fails it, and the diagnosis names each of its two mistakes."""
import dataclasses
import textwrap
from pathlib import Path

import numpy as np
import pytest

from compare.scenarios import builtin_names, load
from compare.diagnosis import diagnosis, render_markdown
from compare.usersim import load_simulator, run_user
from compare.checks.identical_check import check_identical
from compare.oracle.one_step import Rounding
from compare.checks.roundoff import roundoff_envelope

ROOT = Path(__file__).resolve().parents[3]
SEED = load_simulator(str(ROOT / "examples" / "seed_sim.py") + ":step")
BUGGY = load_simulator(str(ROOT / "examples" / "buggy_sim.py") + ":step")


def identical(sim, scene):
    traj = run_user(sim, scene)
    return check_identical(scene, traj.states(), traj.integrator, scene.dt, traj.meta["rounding"]), traj


@pytest.mark.parametrize("name", builtin_names())
def test_the_seed_style_simulator_is_identical_to_custom_sim(name):
    scene = load(name)
    row, _ = identical(SEED, scene)
    assert row.passed is True, (row.position_error_max, row.tolerance_position, row.reason)
    assert row.name == "identical" and row.integrator == scene.integrator


@pytest.mark.parametrize("name", builtin_names())
def test_the_round_off_envelope_is_far_below_the_motion(name):
    """A check that allowed a thousandth of the motion would let real mistakes through."""
    scene = load(name)
    envelope = roundoff_envelope(scene)
    assert envelope.position < 1e-5 * max(abs(scene.initial.position[1]), 0.1), envelope


@pytest.mark.parametrize("integrator", ["explicit_euler", "semi_implicit_euler", "implicit_euler", "rk4"])
def test_the_envelopes_kernel_with_no_rounding_is_custom_sims_run(integrator):
    """The envelope perturbs custom_sim's own steps: with zero noise its kernel must take the
    very steps of simulate() with that integrator, to the bit (a kernel stepping another method
    would size the envelope of the wrong one)."""
    from custom_sim import simulate
    from custom_sim.model import build_model, initial_state
    from compare.checks.roundoff import _ROUNDED

    scene = dataclasses.replace(load("box_drop"), integrator=integrator, duration=0.2)
    model, points = build_model(scene)
    out = np.empty((scene.steps, 6))
    _ROUNDED[integrator](model, points, initial_state(scene), scene.dt, scene.steps, np.zeros((scene.steps, 9)), out)
    assert np.array_equal(out, simulate(scene).states()[1:])


def test_a_model_difference_of_one_part_in_1e8_fails():
    """The resolution the check has: g off by 1e-8 (relative) in free flight moves a drop by
    g t^2 / 2 * 1e-8 = 5e-9 m before touchdown, above point_drop's envelope of 3e-10 m."""
    scene = load("point_drop")

    class Heavier:
        kind, label = "step", "heavier"
        integrator = SEED.integrator

        def run(self, s):
            from compare.usersim.scene_dict import scene_dict
            sd = scene_dict(s)
            sd["g"] *= 1 + 1e-8
            z = np.array(sd["state0"])
            out = [z]
            for _ in range(s.steps):
                z = SEED.function(z, sd, s.dt)
                out.append(z)
            from compare.usersim.loader import UserRun
            return UserRun(np.array(out), None, 0.0, s.integrator)
    row, _ = identical(Heavier(), scene)
    assert row.passed is False and row.position_error_max > 3 * row.tolerance_position, row


def test_an_integrator_the_harness_does_not_know_is_not_judged():
    scene = dataclasses.replace(load("box_slide"), duration=0.01)
    states = run_user(SEED, scene).states()
    row = check_identical(scene, states, "verlet", scene.dt)
    assert row.passed is None and "verlet" in row.reason and row.tolerance_position is None


@pytest.fixture(scope="module")
def buggy_box_drop():
    scene = load("box_drop")
    traj = run_user(BUGGY, scene)
    return scene, traj, diagnosis(BUGGY, scene, traj.states())


def test_the_buggy_copy_fails_identical(buggy_box_drop):
    scene, traj, _ = buggy_box_drop
    row = check_identical(scene, traj.states(), traj.integrator, scene.dt)
    assert row.passed is False and row.position_error_max > 1e-3


def test_the_diagnosis_names_both_mistakes(buggy_box_drop):
    _, _, diag = buggy_box_drop
    assert [n["name"] for n in diag["named"]] == ["friction_on_com_velocity", "box_inertia_about_corner"]
    assert diag["trajectory"]["step"]["first_step"] == 4188   # the first step from a touching state (row 4187)
    # at touchdown (no slip yet, no spin) only the inertia shows; in flight nothing does
    moments = {m["name"]: m for m in diag["moments"]["moments"]}
    assert moments["flight"]["agrees"] is True
    assert moments["touchdown"]["explained_by"] == ["box_inertia_about_corner"]
    assert moments["touchdown"]["component"] == "omega"
    assert moments["sliding"]["agrees"] is False
    text = render_markdown(diag)
    assert "friction_on_com_velocity" in text and "Algorithm 2, line 8" in text and "I = 1/12 m" in text


def test_each_mistake_alone_where_only_it_acts():
    """The disk has no box inertia: only the friction mistake is left, and named alone."""
    scene = dataclasses.replace(load("rolling_circle"), duration=0.4)
    traj = run_user(BUGGY, scene)
    diag = diagnosis(BUGGY, scene, traj.states())
    assert [n["name"] for n in diag["named"]] == ["friction_on_com_velocity"]


def test_a_correct_simulator_gets_nothing_to_explain():
    scene = dataclasses.replace(load("box_drop"), duration=0.3, dt=1e-4)  # the steps below count 1e-4 s
    diag = diagnosis(SEED, scene, run_user(SEED, scene).states())
    assert diag["named"] == [] and "nothing to explain" in diag["verdict"]
    assert all(m["agrees"] for m in diag["moments"]["moments"])


def test_explicit_euler_in_disguise_is_named(tmp_path):
    path = tmp_path / "disguised.py"
    path.write_text(textwrap.dedent(f"""
        import sys
        sys.path.insert(0, {str(ROOT / 'examples')!r})
        import seed_sim
        def step(state, scene, dt):
            return seed_sim.step(state, dict(scene, integrator="explicit_euler"), dt)
        """))
    sim = load_simulator(f"{path}:step")
    scene = dataclasses.replace(load("box_slide"), duration=0.05)
    traj = run_user(sim, scene)
    assert check_identical(scene, traj.states(), traj.integrator, scene.dt).passed is False
    assert [n["name"] for n in diagnosis(sim, scene, traj.states())["named"]] == ["explicit_euler_in_disguise"]


def test_csv_route_with_ten_digits(tmp_path):
    """A CSV written with 10 significant digits: its rounding is allowed for, the model is not."""
    import json
    import subprocess
    import sys
    scene = dataclasses.replace(load("box_drop"), duration=0.5)
    from compare.usersim.scene_dict import scene_dict
    spec = tmp_path / "box_drop.json"
    spec.write_text(json.dumps(scene_dict(scene)))
    subprocess.run([sys.executable, "write_trajectories.py", str(spec), "--out", str(tmp_path / "runs"),
                    "--digits", "10"], cwd=ROOT / "examples", check=True, capture_output=True)
    files = load_simulator(trajectories=str(tmp_path / "runs"))
    row, traj = identical(files, scene)
    assert traj.meta["rounding"] == Rounding("significant", 10) and row.passed is True, row
    buggy = np.column_stack([traj.t, run_user(BUGGY, scene).states()])
    np.savetxt(tmp_path / "runs" / "box_drop.csv", buggy, delimiter=",", header="t,x,y,theta,vx,vy,omega",
               comments="", fmt="%.10g")
    row, _ = identical(files, scene)
    assert row.passed is False


def test_validate_diagnoses_a_rounded_file_to_its_rounding(tmp_path, capsys):
    """The buggy example's run written with 6 decimals: validate's diagnosis allows for the
    file's rounding as its step check does (which fails first in contact), and names the
    example's two mistakes, not a step of the flight whose only difference is the last decimal."""
    from compare.checks.step_check import check_step
    from compare.cli import main
    text = (ROOT / "scenarios" / "box_drop.toml").read_text().replace("duration = 2.0", "duration = 0.3")
    (tmp_path / "box_drop.toml").write_text(text)
    scene = dataclasses.replace(load("box_drop"), duration=0.3)
    states = run_user(BUGGY, scene).states()
    (tmp_path / "runs").mkdir()
    np.savetxt(tmp_path / "runs" / "box_drop.csv", np.column_stack([np.arange(len(states)) * scene.dt, states]),
               delimiter=",", header="t,x,y,theta,vx,vy,omega", comments="", fmt="%.6f")
    files = load_simulator(trajectories=str(tmp_path / "runs"))
    traj = run_user(files, scene)
    step = check_step(scene, traj.states(), traj.integrator, scene.dt, rounding=traj.meta["rounding"])
    assert step.passed is False and "flight" not in step.details["phase"], step.details
    assert main(["validate", "--trajectories", str(tmp_path / "runs"), str(tmp_path / "box_drop.toml")]) == 1
    line = capsys.readouterr().out.splitlines()[1]
    assert "explained by friction_on_com_velocity" in line and "box_inertia_about_corner" in line, line
    assert "flight" not in line, line


def test_an_unknown_integrator_is_not_diagnosed_but_said(tmp_path):
    path = tmp_path / "verlet.py"
    path.write_text(f"import sys\nsys.path.insert(0, {str(ROOT / 'examples')!r})\nfrom seed_sim import step\n"
                    "INTEGRATOR = 'other:verlet'\n")
    sim = load_simulator(f"{path}:step")
    scene = dataclasses.replace(load("box_slide"), duration=0.02)
    diag = diagnosis(sim, scene, run_user(sim, scene).states())
    assert diag["named"] == [] and "verlet" in diag["verdict"] and "not" in diag["verdict"]


def test_an_unknown_integrator_is_still_compared(tmp_path):
    """Named 'other:verlet', the seed's step is held to nothing it cannot be (no step, no identical
    bound) but still shown against the reference, the dynamics twin (RK4) and MuJoCo."""
    from compare.run.scenario import run_scenario
    path = tmp_path / "verlet.py"
    path.write_text(f"import sys\nsys.path.insert(0, {str(ROOT / 'examples')!r})\nfrom seed_sim import step\n"
                    "INTEGRATOR = 'other:verlet'\n")
    scene = dataclasses.replace(load("box_slide"), duration=0.05)
    result = run_scenario(scene, load_simulator(f"{path}:step"))
    assert result.error is None, result.error
    rows = {c.name: c for c in result.checks}
    assert rows["dynamics"].integrator == "other:verlet" and rows["dynamics"].passed is None
    assert rows["dynamics"].position_error_max < 1e-3   # semi-implicit Euler against RK4 over 0.05 s
    assert rows["reference"].position_error_max is not None and rows["native"].position_error_max is not None
    assert rows["step"].passed is None and rows["identical"].passed is None


def test_validate_command_exit_status(tmp_path, capsys):
    from compare.cli import main

    def validate(argv):
        return main(["validate", *argv])
    text = (ROOT / "scenarios" / "box_drop.toml").read_text().replace("duration = 2.0", "duration = 0.3")
    (tmp_path / "short.toml").write_text(text)
    scene = str(tmp_path / "short.toml")
    assert validate([str(ROOT / "examples" / "seed_sim.py") + ":step", scene]) == 0
    assert validate([str(ROOT / "examples" / "buggy_sim.py") + ":step", scene]) == 1
    out = capsys.readouterr().out
    assert "box_inertia_about_corner" in out and "FAIL" in out
    assert validate([str(tmp_path / "nope.py") + ":step", scene]) == 2
    assert "no such file" in capsys.readouterr().err
