"""`study --sim`: the user's code runs every point beside custom_sim, each run from a fresh import.

One local Dask cluster of one worker process serves the module: every run of the study goes
through the same process, as a module that kept state between runs would notice.
"""
from __future__ import annotations

import math

import pytest

pytest.importorskip("distributed")

from compare.cli import main  # noqa: E402
from compare.tools.study import table  # noqa: E402
from compare.tools.study.fields import SceneSource  # noqa: E402

pytestmark = pytest.mark.xdist_group("dask_cluster")

# A box in free fall, never near the ground (it falls 0.44 m from 10 m in 0.3 s).
SCENE = """
duration = 0.3
dt = 1e-3
[body]
shape = "box"
mass = 1.0
size = [0.2, 0.1]
[initial]
position = [0.0, 10.0]
velocity = [0.5, 1.0]
angular_velocity = 2.0
"""

# The motion in closed form, in a sibling file: x, y, theta at time t (m, m, rad) and the velocities.
FALL = '''
def state_at(state0, g, t):
    x, y, th, vx, vy, om = state0
    return [x + vx * t, y + vy * t - 0.5 * g * t * t, th + om * t, vx, vy - g * t, om]
'''

# A step that keeps state: it counts its calls and answers the closed form at count * dt, right
# only when every run starts from a fresh import. Per integrator, one way of not answering.
STEP = '''
import numpy as np
from fall import state_at

CALLS = [0]

def step(state, scene, dt):
    CALLS[0] += 1
    name = scene["integrator"]
    if name == "rk4":
        raise NotImplementedError("rk4 is not written here")
    if name == "explicit_euler":
        raise ValueError("boom")
    if name == "implicit_euler":
        return [float("nan")] * 6
    return state_at(scene["state0"], scene["g"], CALLS[0] * dt)
'''

# m: the converged reference follows a parabola to its own error tolerance, far below what a
# step that restarted its count at the wrong time (an error of 0.3 s of fall, metres) shows
FREE_FALL_AGREEMENT = 1e-8
# m: the twin and custom_sim's semi-implicit Euler agree on a free fall to round-off of 300 steps
TWIN_AGREEMENT = 1e-9
MASSES = (1.0, 2.0, 3.0)   # free fall does not depend on the mass: three points, one motion


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("user")
    (folder / "fall.py").write_text(FALL)
    (folder / "stateful_sim.py").write_text(STEP)
    (folder / "free_fall.toml").write_text(SCENE)
    return folder


@pytest.fixture(scope="module")
def study(files, tmp_path_factory):
    """The study's rows and what it printed (one run of the command for the module)."""
    import contextlib
    import io

    out = tmp_path_factory.mktemp("study")
    err, printed = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(printed):
        code = main(["study", str(files / "free_fall.toml"), "--vary", f"body.mass={','.join(map(str, MASSES))}",
                     "--sim", f"{files / 'stateful_sim.py'}:step", "--workers", "1", "--dashboard", "--out", str(out)])
    return code, table.read_csv(out / "study.csv"), err.getvalue() + printed.getvalue(), out


def test_a_step_that_keeps_state_is_judged_from_a_fresh_import_at_every_run(study):
    code, rows, _, _ = study
    assert code == 0
    mine = [r for r in rows if r["simulator"] == "yours" and r["integrator"] == "semi_implicit_euler"]
    assert [float(r["body.mass"]) for r in mine] == list(MASSES)
    for r in mine:
        assert r["status"] == "ok", r["note"]
        assert float(r["position_error_max"]) < FREE_FALL_AGREEMENT, (
            f"body.mass={r['body.mass']}: error {r['position_error_max']} m against the reference")
        assert float(r["wall_time"]) > 0 and r["force_evals"] == ""


def test_the_twin_is_measured_against_the_users_runs_too(study):
    """MuJoCo's twin steps semi-implicit Euler, as custom_sim's does: on a parabola both lag it by
    the same g dt t / 2, so your closed form's distance to the twin is custom_sim's error."""
    _, rows, _, _ = study
    for mass in MASSES:
        at = [r for r in rows if float(r["body.mass"]) == mass and r["integrator"] == "semi_implicit_euler"]
        mine = next(r for r in at if r["simulator"] == "yours")
        ours = next(r for r in at if r["simulator"] == "custom_sim")
        assert abs(float(mine["twin_position_error_max"]) - float(ours["position_error_max"])) < TWIN_AGREEMENT, (
            mine["twin_position_error_max"], ours["position_error_max"])


def test_custom_sim_runs_beside_and_the_columns_are_added_after_the_contract(study):
    _, rows, _, _ = study
    assert list(rows[0])[:10] == ["body.mass", "integrator", "stable", "position_error_max",
                                  "twin_position_error_max", "wall_time", "force_evals", "status",
                                  "stable_step_theory", "note"]
    assert list(rows[0])[-1] == "simulator"
    ours = [r for r in rows if r["simulator"] == "custom_sim"]
    assert len(ours) == 4 * len(MASSES) and all(r["status"] == "ok" for r in ours)
    # custom_sim's semi-implicit Euler on a parabola: error g dt t / 2 at most (m), far above the closed form's
    sie = [float(r["position_error_max"]) for r in ours if r["integrator"] == "semi_implicit_euler"]
    assert all(1e-5 < e <= 9.81 * 1e-3 * 0.3 / 2 * 1.01 for e in sie), sie


def test_what_the_users_code_does_not_do_is_said_per_run(study):
    """A NotImplementedError is skipped, an exception failed, a NaN unstable; each with its reason."""
    _, rows, err, out = study
    by = {}
    for r in rows:
        if r["simulator"] == "yours":
            by.setdefault(r["integrator"], []).append(r)
    assert {r["status"] for r in by["rk4"]} == {"skipped"}
    assert all("rk4 is not written here" in r["note"] for r in by["rk4"])
    assert {r["status"] for r in by["explicit_euler"]} == {"failed"}
    assert all("ValueError: boom" in r["note"] for r in by["explicit_euler"])
    assert {r["status"] for r in by["implicit_euler"]} == {"unstable"}
    assert all("non-finite" in r["note"] and r["stable"] == "false" for r in by["implicit_euler"])
    assert "Traceback" not in err
    assert "dashboard: http://127.0.0.1:" in err, "--dashboard prints where it opened the dashboard"
    assert "yours: 3 run(s) failed, the first: " in err and "ValueError: boom" in err
    index = (out / "index.md").read_text()
    assert "stateful_sim.py:step" in index and "fall.py, stateful_sim.py" in index
    assert "Yours (`simulator` = yours): unstable where" in index


@pytest.mark.parametrize("argv, message", [
    (["--sim", "no_such_file.py:step"], "no such file"),
    (["--whole"], "--whole: expected it with --sim"),
    (["--law", "identified"], "--law identified: not in a study"),
    (["--scheduler", "tcp://127.0.0.1:1", "--dashboard"], "--dashboard: the cluster given by --scheduler"),
    (["--scheduler", "tls://127.0.0.1:1"], "no TLS settings for the client; expected the dask config"),
])
def test_bad_input_exits_2_with_one_line_and_writes_nothing(files, tmp_path, capsys, argv, message):
    out = tmp_path / "out"
    code = main(["study", str(files / "free_fall.toml"), "--vary", "body.mass=1,2", *argv, "--out", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and message in err[0], err
    assert not out.exists()


def test_a_law_file_is_laid_over_the_scene_and_the_varied_fields_over_it(files, tmp_path):
    law = tmp_path / "law.toml"
    law.write_text("[contact]\nk = 5e4\nc = 7.0\nfriction_law = \"sign\"\n")
    source = SceneSource.read(files / "free_fall.toml").under_law(str(law))
    from compare.tools.study.fields import parse_vary
    vary = parse_vary("contact.k=1e4,2e4")
    scene = source.varied([vary], (2e4,))
    assert (scene.contact.k, scene.contact.c, scene.contact.friction_law) == (2e4, 7.0, "sign")
    assert scene.law_from == str(law)
    assert source.scene.contact.k == 5e4 and not math.isnan(source.scene.contact.mu)


# A program in "another language" (Python here, so that no compiler is needed): the closed form
# on the step protocol, counting the steps since its last `scene` line; it does semi-implicit
# Euler's integrator name only.
PROCESS = '''
import sys
sys.path.insert(0, sys.argv[1])
import json
from fall import state_at
sd, n = None, 0
for line in sys.stdin:
    word, _, rest = line.partition(" ")
    if word == "scene":
        sd, n = json.loads(rest), 0
        print("ready semi_implicit_euler", flush=True)
    elif word == "step":
        n += 1
        dt = float(rest.split()[0])
        print(" ".join(repr(v) for v in state_at(sd["state0"], sd["g"], n * dt)), flush=True)
'''


def test_a_process_runs_every_point_through_the_step_protocol(files, tmp_path, capsys):
    """`study --sim-process`: the command is started for the runs, each from its scene line; the
    integrator its `ready` names is the one run."""
    import sys

    (files / "fall_process.py").write_text(PROCESS)
    command = f"{sys.executable} {files / 'fall_process.py'} {files}"
    code = main(["study", str(files / "free_fall.toml"), "--vary", "body.mass=1,2", "--sim-process", command,
                 "--integrators", "semi_implicit_euler", "--no-twin", "--workers", "1", "--out", str(tmp_path)])
    assert code == 0, capsys.readouterr().err
    mine = [r for r in table.read_csv(tmp_path / "study.csv") if r["simulator"] == "yours"]
    assert [r["integrator"] for r in mine] == ["semi_implicit_euler"] * 2
    assert all(r["status"] == "ok" and float(r["position_error_max"]) < FREE_FALL_AGREEMENT for r in mine), mine
