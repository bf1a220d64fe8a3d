"""The simulator under test brought in three ways, and every bad input named in one line."""
import dataclasses
import textwrap
from pathlib import Path

import numpy as np
import pytest

import compare.commands.scene as scene_command
from compare.cli import BadInput, main
from compare.scenarios import load
from compare.usersim import UserCodeError, load_simulator, run_user, scene_dict
from custom_sim import simulate

ROOT = Path(__file__).resolve().parent.parent
SEED = str(ROOT / "examples" / "seed_sim.py")


@pytest.fixture(scope="module")
def scene():
    return dataclasses.replace(load("box_drop"), duration=0.01, dt=1e-4)   # 100 steps


def module(tmp_path, body, name="user_sim"):
    path = tmp_path / f"{name}.py"
    path.write_text(textwrap.dedent(body))
    return str(path)


def fails(sim_or_spec, scene, whole=False):
    with pytest.raises(BadInput) as err:
        sim = load_simulator(sim_or_spec, whole) if isinstance(sim_or_spec, str) else sim_or_spec
        run_user(sim, scene)
    message = str(err.value)
    assert "\n" not in message
    return message, getattr(err.value, "details", "")


def test_step_function_by_path_and_by_dotted_name(scene, monkeypatch):
    by_path = run_user(load_simulator(SEED + ":step"), scene)
    monkeypatch.syspath_prepend(str(ROOT / "examples"))
    by_name = run_user(load_simulator("seed_sim:step"), scene)
    assert np.array_equal(by_path.states(), by_name.states())
    assert by_path.simulator == "user" and by_path.wall_time > 0 and by_path.states().shape == (101, 6)
    # the harness's energy from the states: the same formula as custom_sim's, on the same states
    ours = simulate(scene)
    assert np.allclose(by_path.energy, ours.energy, rtol=1e-12, atol=1e-12)


def test_whole_function_and_its_energy_column(tmp_path, scene):
    spec = module(tmp_path, f"""
        import numpy as np, sys
        sys.path.insert(0, {str(ROOT / 'examples')!r})
        from seed_sim import step
        INTEGRATOR = "semi_implicit_euler"
        def simulate(scene):
            z = np.array(scene["state0"]); rows = [np.append(z, 1.0)]
            for i in range(scene["steps"]):
                z = step(z, scene, scene["dt"]); rows.append(np.append(z, 1.0))
            return np.array(rows)
        """) + ":simulate"
    traj = run_user(load_simulator(spec, whole=True), scene)
    assert traj.meta["energy_source"] == "user" and np.allclose(traj.energy, 1.0)
    assert np.array_equal(traj.states(), run_user(load_simulator(SEED + ":step"), scene).states())


def test_module_that_does_not_import(tmp_path, scene):
    spec = module(tmp_path, "import numpy\nx = 1 / 0\n") + ":step"
    message, details = fails(spec, scene)
    assert "user_sim.py" in message and "ZeroDivisionError" in message and "expected a module that imports" in message
    assert "user_sim.py" in details and "compare/usersim" not in details and "importlib" not in details
    message, _ = fails(module(tmp_path, "def step(:\n", "broken") + ":step", scene)
    assert "broken.py" in message and "SyntaxError" in message
    message, _ = fails(str(tmp_path / "nowhere.py") + ":step", scene)
    assert "nowhere.py" in message and "no such file" in message
    message, _ = fails("no_such_module_here:step", scene)
    assert "no module named 'no_such_module_here'" in message


def test_missing_function_and_bad_spec(tmp_path, scene):
    message, _ = fails(module(tmp_path, "def stepp(s, sc, dt):\n    return s\n") + ":step", scene)
    assert "has no function 'step'" in message and "stepp" in message and "step(state, scene, dt)" in message
    message, _ = fails(SEED, scene)
    assert "expected MODULE:FUNCTION" in message
    message, _ = fails(module(tmp_path, "step = 3\n", "notfn") + ":step", scene)
    assert "is a int, not a function" in message


def test_a_function_that_raises_shows_only_its_own_frames(tmp_path, scene):
    spec = module(tmp_path, """
        import numpy as np
        def helper(z):
            if z[4] < -0.02:
                raise ValueError("went too fast")
            return z
        def step(state, scene, dt):
            z = np.array(state); z[4] -= 9.81 * dt; z[1] += z[4] * dt
            return helper(z)
        """) + ":step"
    message, details = fails(spec, scene)
    assert "at step 21 (t = 0.0021 s" in message and "ValueError: went too fast" in message and "from state [" in message
    assert details.count("user_sim.py") == 2 and "helper" in details and "compare" not in details
    assert details.splitlines()[-1] == "ValueError: went too fast"


@pytest.mark.parametrize("returned, says", [
    ("state[:5]", "returned shape (5,) at step 1 (expected shape (6,)"),
    ("np.reshape(state, (6, 1))", "returned shape (6, 1) at step 1"),
    ("None", "returned shape () at step 1"),
    ("'abc'", "returned str at step 1"),
    ("np.where(state[1] < 0.2999, np.nan, state)", "returned a non-finite state"),
])
def test_wrong_shape_or_nan(tmp_path, scene, returned, says):
    spec = module(tmp_path, f"""
        import numpy as np
        def step(state, scene, dt):
            state = np.array(state); state[4] -= 9.81 * dt; state[1] += state[4] * dt
            return {returned}
        """) + ":step"
    message, _ = fails(spec, scene)
    assert says in message and "user_sim.py:step" in message


def test_nan_names_the_step_and_the_state_before(tmp_path, scene):
    spec = module(tmp_path, """
        import numpy as np
        def step(state, scene, dt):
            z = np.array(state, dtype=float); z[1] -= 1e-3
            return z if z[1] > 0.295 else z * np.nan
        """) + ":step"
    message, _ = fails(spec, scene)
    assert "non-finite state" in message and "at step 5 (t = 0.0005 s) from [0, 0.296, 0.4" in message


def test_whole_function_wrong_shape_nan_or_start(tmp_path, scene):
    cases = {"np.zeros((scene['steps'], 6))": "returned shape (100, 6)",
             "np.full((scene['steps'] + 1, 6), np.nan)": "returned a non-finite row 0",
             "np.zeros((scene['steps'] + 1, 6))": "not the scene's initial state"}
    for i, (value, says) in enumerate(cases.items()):
        spec = module(tmp_path, f"import numpy as np\ndef simulate(scene):\n    return {value}\n", f"w{i}") + ":simulate"
        message, _ = fails(spec, scene, whole=True)
        assert says in message and "expected" in message


def write_csv(folder, scene, header="t,x,y,theta,vx,vy,omega", rows=None, edit=None):
    folder.mkdir(exist_ok=True)
    states = simulate(scene).states()
    data = np.column_stack([np.arange(len(states)) * scene.dt, states]) if rows is None else rows
    lines = [header] + [",".join(repr(float(v)) for v in r) for r in data]
    if edit:
        lines = edit(lines)
    (folder / f"{scene.name}.csv").write_text("\n".join(lines) + "\n")
    return str(folder)


def test_trajectories_folder_passes_through(tmp_path, scene):
    traj = run_user(load_simulator(trajectories=write_csv(tmp_path / "ok", scene)), scene)
    assert np.array_equal(traj.states(), simulate(scene).states())
    assert traj.meta["written_digits"] is None and traj.meta["wall_time_known"] is False
    # columns in another order, an extra column: read by name
    folder = tmp_path / "reordered"
    states = simulate(scene).states()
    rows = np.column_stack([states[:, 5], np.zeros(len(states)), np.arange(len(states)) * scene.dt, states[:, :5]])
    write_csv(folder, scene, header="omega,extra,t,x,y,theta,vx,vy", rows=rows)
    assert np.array_equal(run_user(load_simulator(trajectories=str(folder)), scene).states(), states)


def test_bad_csv_files(tmp_path, scene):
    ok = np.column_stack([np.arange(scene.steps + 1) * scene.dt, simulate(scene).states()])
    cases = {
        "missing column": (dict(header="t,x,y,theta,vx,vy"), ["omega", "missing column"]),
        "not a number": (dict(edit=lambda ls: ls[:5] + [ls[5].replace(ls[5].split(",")[3], "abc", 1)] + ls[6:]),
                         ["row 6", "(theta)", "'abc' is not a number"]),
        "no t = 0 row": (dict(rows=ok[1:]), ["row 2", "t = 0 row, the initial state, is missing"]),
        "another dt": (dict(rows=np.column_stack([ok[:, 0] * 2, ok[:, 1:]])), ["row 3, column t", "time grid"]),
        "too few rows": (dict(rows=ok[:50]), ["50 data rows", "expected 101 rows"]),
    }
    for i, (case, (kw, says)) in enumerate(cases.items()):
        folder = write_csv(tmp_path / f"c{i}", scene, **kw)
        message, _ = fails(load_simulator(trajectories=folder), scene)
        assert f"c{i}/box_drop.csv" in message, case
        for s in says:
            assert s in message, (case, message)
    message, _ = fails(load_simulator(trajectories=str(tmp_path / "c0")), dataclasses.replace(scene, name="other"))
    assert "other.csv: no such file" in message
    with pytest.raises(BadInput, match="no such folder"):
        load_simulator(trajectories=str(tmp_path / "absent"))


def test_the_command_line_prints_the_traceback_once_then_one_line(monkeypatch, capsys, tmp_path, scene):
    spec = module(tmp_path, "def step(state, scene, dt):\n    return state[7]\n") + ":step"

    def fake_main(args):
        run_user(load_simulator(spec), scene)
    monkeypatch.setattr(scene_command, "main", fake_main)
    assert main(["scene", "box_drop"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[0].startswith("Traceback (your code") and sum("Traceback" in line for line in err) == 1
    assert err[-1].startswith("error: ") and "IndexError" in err[-1] and "at step 1" in err[-1]
    assert not any("compare/" in line for line in err[:-1])


def test_a_simulator_pickles_for_the_process_pool(scene):
    import pickle
    sim = pickle.loads(pickle.dumps(load_simulator(SEED + ":step")))
    assert sim.call(scene_dict(scene)["state0"], scene_dict(scene), scene.dt).shape == (6,)


def test_a_step_returning_lists_or_changing_its_input_in_place(tmp_path, scene):
    """Both record the same states as the worked example's fresh arrays."""
    want = run_user(load_simulator(SEED + ":step"), scene).states()
    for name, body in {"as_list": "return list(seed_sim.step(state, scene, dt))",
                       "in_place": "state[:] = seed_sim.step(state, scene, dt)\n    return state"}.items():
        spec = module(tmp_path, f"import sys\nsys.path.insert(0, {str(ROOT / 'examples')!r})\nimport seed_sim\n"
                                f"def step(state, scene, dt):\n    {body}\n", name) + ":step"
        assert np.array_equal(run_user(load_simulator(spec), scene).states(), want), name
    spec = module(tmp_path, "def step(state, scene, dt):\n    z = [state[0], state[1] - 1e-5, *state[2:6]]\n"
                            "    return z if z[1] > 0.2999 else z + [0.0]\n", "longer") + ":step"
    message, _ = fails(spec, scene)
    assert "another length at a later step" in message


def test_an_energy_column_and_a_declared_integrator_are_taken(tmp_path, scene):
    folder = tmp_path / "with_energy"
    states = simulate(scene).states()
    rows = np.column_stack([np.arange(len(states)) * scene.dt, states, np.full(len(states), 2.5)])
    write_csv(folder, scene, header="t,x,y,theta,vx,vy,omega,energy", rows=rows)
    (folder / "simulator.toml").write_text('integrator = "verlet"\n')
    traj = run_user(load_simulator(trajectories=str(folder)), scene)
    assert traj.meta["energy_source"] == "user" and np.allclose(traj.energy, 2.5)
    assert traj.integrator == "verlet"


def test_the_error_survives_a_process_pool():
    import pickle
    err = pickle.loads(pickle.dumps(UserCodeError("one line", "Traceback ...")))
    assert isinstance(err, BadInput) and str(err) == "one line" and err.details == "Traceback ..."


def test_run_refuses_a_bad_simulator_before_writing_anything(tmp_path, capsys):
    bad = module(tmp_path, "def step(state, scene, dt):\n    return state[9]\n", "bad")
    for flags in (["--sim", bad + ":step"], ["--sim", str(tmp_path / "absent.py") + ":step"],
                  ["--trajectories", str(tmp_path)], ["--whole"]):
        out = tmp_path / "out"
        assert main(["run", "box_slide", "--out", str(out), *flags]) == 2, flags
        err = capsys.readouterr().err.strip().splitlines()
        assert err[-1].startswith("error: ") and not out.exists(), flags
