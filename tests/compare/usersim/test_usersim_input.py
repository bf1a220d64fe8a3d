"""The simulator under test brought in three ways, and every bad input named in one line."""
import dataclasses
import textwrap
from pathlib import Path

import numpy as np
import pytest

from compare.cli import main
from scene_types import BadInput
from compare.scenarios import load
from compare.usersim import UserCodeError, UserFault, load_simulator, run_user, scene_dict
from custom_sim import simulate

ROOT = Path(__file__).resolve().parents[3]
SEED = str(ROOT / "examples" / "seed_sim.py")


@pytest.fixture(scope="module")
def scene():
    return dataclasses.replace(load("box_drop"), duration=0.01, dt=1e-4)   # 100 steps


def module(tmp_path, body, name="user_sim"):
    path = tmp_path / f"{name}.py"
    path.write_text(textwrap.dedent(body))
    return str(path)


def fails(sim_or_spec, scene, whole=False, error=BadInput):
    """The one-line message (and the user's traceback) of `error` raised running the simulator:
    BadInput for the protocol, UserFault for a fault of this scene's run (see faults)."""
    with pytest.raises(error) as err:
        sim = load_simulator(sim_or_spec, whole) if isinstance(sim_or_spec, str) else sim_or_spec
        run_user(sim, scene)
    message = str(err.value)
    assert "\n" not in message
    return message, getattr(err.value, "details", "")


def faults(sim_or_spec, scene, whole=False):
    """An exception or a NaN in one scene's run: UserFault (the scene's row), not bad input."""
    return fails(sim_or_spec, scene, whole, UserFault)


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
    assert "user_sim.py" in message and "ZeroDivisionError" in message
    assert "(expected" not in message   # it raised: nothing it returned was wrong
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
    message, details = faults(spec, scene)
    assert "at step 21 (t = 0.0021 s" in message and "ValueError: went too fast" in message and "from state [" in message
    assert details.count("user_sim.py") == 2 and "helper" in details and "compare" not in details
    assert details.splitlines()[-1] == "ValueError: went too fast"


@pytest.mark.parametrize("returned, says", [
    ("state[:5]", "at step 1 returned an array of shape (5,)"),
    ("np.reshape(state, (6, 1))", "at step 1 returned an array of shape (6, 1)"),
    ("None", "at step 1 returned None"),
    ("'abc'", "at step 1 returned a str 'abc'"),
    ("np.where(state[1] < 0.2999, np.nan, state)", "returned a non-finite state"),
])
def test_wrong_shape_or_nan(tmp_path, scene, returned, says):
    spec = module(tmp_path, f"""
        import numpy as np
        def step(state, scene, dt):
            state = np.array(state); state[4] -= 9.81 * dt; state[1] += state[4] * dt
            return {returned}
        """) + ":step"
    message, _ = faults(spec, scene) if "non-finite" in says else fails(spec, scene)
    assert says in message and "user_sim.py:step" in message


def test_nan_names_the_step_and_the_state_before(tmp_path, scene):
    spec = module(tmp_path, """
        import numpy as np
        def step(state, scene, dt):
            z = np.array(state, dtype=float); z[1] -= 1e-3
            return z if z[1] > 0.295 else z * np.nan
        """) + ":step"
    message, _ = faults(spec, scene)
    assert "non-finite state" in message and "at step 5 (t = 0.0005 s) from [0, 0.296, 0.4" in message


def test_whole_function_wrong_shape_nan_or_start(tmp_path, scene):
    cases = {"np.zeros((scene['steps'], 6))": "returned shape (100, 6), one row short: the t = 0 row",
             "np.zeros((6, scene['steps'] + 1))": "returned shape (6, 101), its transpose",
             "np.zeros((scene['steps'] + 2, 7))": "returned shape (102, 7), one row too many",
             "np.full((scene['steps'] + 1, 6), np.nan)": "returned a non-finite row 0",
             "np.zeros((scene['steps'] + 1, 6))": "not the scene's initial state"}
    for i, (value, says) in enumerate(cases.items()):
        spec = module(tmp_path, f"import numpy as np\ndef simulate(scene):\n    return {value}\n", f"w{i}") + ":simulate"
        message, _ = (faults if "non-finite" in says else fails)(spec, scene, whole=True)
        assert says in message and "expected" in message


@pytest.mark.parametrize("body, whole, says", [
    ("def step(state, scene, dt):\n    return state\n", True,
     "step(state, scene, dt) cannot be called with 1 argument (missing a required argument: 'scene'); "
     "expected simulate(scene) -> array (steps + 1, 6) (a step function? drop --whole)"),
    ("def step(scene):\n    return None\n", False,
     "step(scene) cannot be called with 3 arguments (too many positional arguments); expected "
     "step(state, scene, dt) -> state (a whole run, simulate(scene)? add --whole)"),
])
def test_a_function_of_the_other_kind_is_bad_input_before_any_call(tmp_path, capsys, body, whole, says):
    """--whole given a step function (or a whole run without it) is the command line's slip:
    exit 2 naming the function and the flag, nothing written (called, it would have been the
    scene's error row, exit 1)."""
    spec = module(tmp_path, body) + ":step"
    out = tmp_path / "out"
    code = main(["run", "point_drop", "--sim", spec, "--out", str(out), *(["--whole"] if whole else [])])
    err = capsys.readouterr().err
    assert code == 2 and says in err and not out.exists(), err
    # a function with defaults or *args that can take the call is accepted
    assert load_simulator(module(tmp_path, "def step(state, scene, dt=0.0, *more):\n    return state\n", "ok")
                          + ":step") is not None


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
    assert traj.meta["rounding"] is None and traj.meta["wall_time_known"] is False
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


def test_the_command_line_prints_the_traceback_once_then_one_line(capsys, tmp_path):
    spec = module(tmp_path, "def step(state, scene, dt):\n    return state[7]\n") + ":step"
    assert main(["validate", spec, "box_slide"]) == 1
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    # the traceback under its scene's name (issue 32, item 11: each per-scene error with its scene)
    assert err[0].startswith("box_slide: Traceback (your code") and sum("Traceback" in line for line in err) == 1
    assert err[-1].startswith("IndexError")
    assert not any("compare/" in line for line in err)
    line = next(x for x in captured.out.splitlines() if x.startswith("box_slide"))
    assert "error:" in line and "IndexError" in line and "at step 1" in line
    assert "(expected" not in line   # it raised: nothing it returned was wrong


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
    assert "at step 10 returned a list of 7 items" in message


def test_an_energy_column_and_a_declared_integrator_are_taken(tmp_path, scene):
    folder = tmp_path / "with_energy"
    states = simulate(scene).states()
    rows = np.column_stack([np.arange(len(states)) * scene.dt, states, np.full(len(states), 2.5)])
    write_csv(folder, scene, header="t,x,y,theta,vx,vy,omega,energy", rows=rows)
    (folder / "simulator.toml").write_text('integrator = "other:verlet"\n')
    traj = run_user(load_simulator(trajectories=str(folder)), scene)
    assert traj.meta["energy_source"] == "user" and np.allclose(traj.energy, 2.5)
    assert traj.integrator == "other:verlet"
    (folder / "simulator.toml").write_text('integrator = "verlet"\n')
    with pytest.raises(BadInput, match="not an integrator the harness knows"):
        run_user(load_simulator(trajectories=str(folder)), scene)


def test_the_error_survives_a_process_pool():
    import pickle
    err = pickle.loads(pickle.dumps(UserCodeError("one line", "Traceback ...")))
    assert isinstance(err, BadInput) and str(err) == "one line" and err.details == "Traceback ..."


def test_run_refuses_a_bad_simulator_before_writing_anything(tmp_path, capsys):
    bad = module(tmp_path, "def step(state, scene, dt):\n    return None\n", "bad")
    for flags in (["--sim", bad + ":step"], ["--sim", str(tmp_path / "absent.py") + ":step"],
                  ["--trajectories", str(tmp_path)], ["--whole"]):
        out = tmp_path / "out"
        assert main(["run", "box_slide", "--out", str(out), *flags]) == 2, flags
        err = capsys.readouterr().err.strip().splitlines()
        assert err[-1].startswith("error: ") and not out.exists(), flags


# ---------------------------------------------------------------------------------------
# A CSV's own rounding (fixed decimals or significant digits) and its encoding

def rounded_folder(folder, scene, fmt, states=None, time_fmt=None):
    """scene.csv as a C or numpy writer would give it: every column in `fmt` (the t column in
    time_fmt when given), from custom_sim's run (or `states`)."""
    folder.mkdir(parents=True, exist_ok=True)
    states = simulate(scene).states() if states is None else states
    t = np.arange(len(states)) * scene.dt
    lines = ["t,x,y,theta,vx,vy,omega"]
    for ti, z in zip(t, states):
        lines.append(",".join([(time_fmt or fmt) % ti] + [fmt % v for v in z]))
    (folder / f"{scene.name}.csv").write_text("\n".join(lines) + "\n")
    return str(folder)


def checked(folder, scene):
    from compare.checks.identical_check import check_identical
    from compare.checks.step_check import check_step

    traj = run_user(load_simulator(trajectories=folder), scene)
    rounding = traj.meta["rounding"]
    same = check_identical(scene, traj.states(), traj.integrator, scene.dt, rounding)
    step = check_step(scene, traj.states(), traj.integrator, scene.dt, rounding=rounding)
    return same, step, rounding


# box_slide starts sliding on its face (a stiff contact and friction from the first step);
# point_drop falls and lands at t = 0.33 s (the stiff amplification of a touchdown)
ROUNDED_SCENES = {"box_slide": 0.1, "point_drop": 0.4}


@pytest.mark.parametrize("name", list(ROUNDED_SCENES))
@pytest.mark.parametrize("fmt, kind, digits", [("%.6f", "decimals", 6), ("%.9f", "decimals", 9),
                                               ("%.8g", "significant", 8), ("%.6g", "significant", 6)])
def test_a_correct_csv_written_with_fixed_decimals_or_few_digits_passes(tmp_path, name, fmt, kind, digits):
    """The file's rounding is found from its text and allowed for, absolute (%.6f writes
    y = 0.0497548 as 0.049755 and a vx of 1e-8 as 0.000000) or relative (%.8g)."""
    from compare.oracle.one_step import Rounding

    scene = dataclasses.replace(load(name), duration=ROUNDED_SCENES[name])
    same, step, rounding = checked(rounded_folder(tmp_path / "runs", scene, fmt), scene)
    assert rounding == Rounding(kind, digits)
    assert same.passed is True, same
    assert step.passed is True, step
    assert rounding.describe() in same.reason and rounding.describe() in step.reason


@pytest.mark.parametrize("fmt", ["%.17g", "%.6f"])
def test_a_wrong_simulator_still_fails_whatever_the_digits(tmp_path, fmt):
    """g 1 % off: the rounding allowance does not hide a model difference."""
    scene = dataclasses.replace(load("box_slide"), duration=0.1)
    wrong = simulate(dataclasses.replace(scene, g=scene.g * 1.01)).states()
    same, step, rounding = checked(rounded_folder(tmp_path / "runs", scene, fmt, states=wrong), scene)
    assert (rounding is None) == (fmt == "%.17g")
    assert same.passed is False and step.passed is False, (same, step)


def test_rounding_coarser_than_the_motion_is_not_judged(tmp_path):
    """One decimal (5 cm) on a box that moves 2 cm: neither check can tell a mistake from the
    rounding, and each says so instead of passing."""
    scene = dataclasses.replace(load("box_slide"), duration=0.01)
    same, step, rounding = checked(rounded_folder(tmp_path / "runs", scene, "%.1f", time_fmt="%.17g"), scene)
    assert rounding.kind == "decimals" and rounding.digits == 1
    for row in (same, step):
        assert row.passed is None and row.reason.startswith("not judged") and "rounding" in row.reason, row
        assert row.tolerance_position is None


def test_the_rounding_is_read_from_the_text():
    from compare.usersim.csv_files import rounding_of_text
    from compare.oracle.one_step import Rounding

    head = "t,x,y,theta,vx,vy,omega\n"
    assert rounding_of_text(head + "0.000000,0.000000,0.300000,0.400000,0.000000,0.000000,0.000000\n"
                                   "0.000050,12.345678,0.299999,0.400000,0.000000,-0.000491,0.000000\n") \
        == Rounding("decimals", 6)
    assert rounding_of_text(head + "0,0,0.3,0.4,0,0,0\n5e-05,1.2345679e-08,0.29999998,0.4,0,-0.0004905,0\n") \
        == Rounding("significant", 8)
    full = ",".join(repr(v) for v in (5e-05, 0.1 + 0.2, 0.29999997547499997, 0.4, 1 / 3, -0.0004905, 2 / 3))
    assert rounding_of_text(head + "0,0,0.3,0.4,0,0,0\n" + full + "\n") is None
    # an absolute half unit: a value below it written as zero is still within it
    assert Rounding("decimals", 6).half_unit([1e-8, 100.0]).tolist() == [5e-7, 5e-7]
    assert Rounding("significant", 8).half_unit([2.0]).tolist() == [1e-7]


@pytest.mark.parametrize("encoding, accepted", [("utf-8-sig", True), ("utf-16", False), ("utf-16-le", False),
                                                ("utf-32", False)])
def test_a_csv_with_a_byte_order_mark_is_read_another_encoding_is_named(tmp_path, scene, encoding, accepted):
    folder = tmp_path / "runs"
    path = Path(write_csv(folder, scene)) / f"{scene.name}.csv"
    path.write_bytes(path.read_text().encode(encoding))
    sim = load_simulator(trajectories=str(folder))
    if accepted:
        assert np.array_equal(run_user(sim, scene).states(), simulate(scene).states())
        return
    message, _ = fails(sim, scene)
    assert message.startswith(str(path)) and "expected UTF-8 text" in message, message


def test_a_coarse_file_still_fails_where_it_is_off_beyond_its_rounding(tmp_path):
    """"Not judged" replaces only a pass: a file off by far more than its rounding (x jumping a
    metre a step, written at one decimal) still fails both checks."""
    scene = dataclasses.replace(load("box_slide"), duration=0.01)
    wrong = simulate(scene).states()
    wrong[:, 0] += np.arange(len(wrong)) * 1.0
    same, step, _ = checked(rounded_folder(tmp_path / "runs", scene, "%.1f", states=wrong, time_fmt="%.17g"), scene)
    assert same.passed is False and step.passed is False, (same, step)
