"""Bad input gets one clear line naming the file, the field and what was expected, and writes nothing.

Every case is a valid scene with one thing broken (CASES: the edit, the field the message must
name, and words of what was expected). Each is checked twice: `custom_sim.load_scene` raises
a one-line SceneError, and `python -m compare run <file> --out <dir>` exits with status 2, one
line on stderr, and leaves the output folder untouched.
"""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from custom_sim import SceneError, load_scene

ROOT = Path(__file__).resolve().parents[2]

VALID = """\
name = "bad_input_base"
duration = 1.0
dt = 1e-3
integrator = "semi_implicit_euler"
effects = ["gravity", "contact", "friction"]

[body]
shape = "box"
mass = 1.0
size = [0.2, 0.1]

[contact]
k = 1e4
c = 20.0
mu = 0.5

[initial]
position = [0.0, 0.5]
velocity = [0.0, 0.0]

[mujoco]
solref = "penalty"
"""

COMPOUND = 'shape = "compound"\nparts = [{ size = [0.1, 0.1], offset = [0.0, 0.0], mass = 1.0 }]'
BOX = 'shape = "box"\nmass = 1.0\nsize = [0.2, 0.1]'


def edit(old: str, new: str) -> str:
    assert old in VALID, old
    return VALID.replace(old, new, 1)


# name: (scene text, field the message names, words of what was expected)
CASES = {
    "malformed TOML": ("duration = 1.0\ndt = \n", "", "line 2"),
    "unclosed table header": (edit("[contact]", "[contact"), "", "line 12"),
    "unknown field": (edit("dt = 1e-3", "dt = 1e-3\ndurations = 2.0"), "durations", "expected one of"),
    "unknown field in [contact]": (edit("mu = 0.5", "mus = 0.5"), "contact.mus", "expected one of"),
    "unknown field in [mujoco]": (edit('solref = "penalty"', "timestep = 1e-3"), "mujoco.timestep", "expected one of"),
    "unknown table": (VALID + "\n[visual]\ncolor = 'red'\n", "visual", "expected one of"),
    "unknown field in a part": (edit(BOX, COMPOUND.replace("mass = 1.0 }", "mass = 1.0, radius = 0.1 }")),
                                "body.parts[0].radius", "expected one of"),
    "string for a number": (edit("duration = 1.0", 'duration = "1.0"'), "duration", "expected a number"),
    "boolean for a number": (edit("mass = 1.0", "mass = true"), "body.mass", "expected a number"),
    "string for a pair": (edit("position = [0.0, 0.5]", 'position = "0.0, 0.5"'), "initial.position",
                          "expected a list of two numbers"),
    "three numbers for a pair": (edit("size = [0.2, 0.1]", "size = [0.2, 0.1, 0.3]"), "body.size",
                                 "expected a list of two numbers"),
    "string inside a pair": (edit("position = [0.0, 0.5]", 'position = [0.0, "0.5"]'), "initial.position",
                             "expected a number"),
    "number for a table": (edit("[contact]\nk = 1e4\nc = 20.0\nmu = 0.5\n", "").replace("dt = 1e-3", "dt = 1e-3\ncontact = 5"),
                           "contact", "expected a table"),
    "string for a list": (edit('effects = ["gravity", "contact", "friction"]', 'effects = "gravity"'),
                          "effects", "expected a list of strings"),
    "number for a choice": (edit('integrator = "semi_implicit_euler"', "integrator = 4"), "integrator",
                            "expected one of"),
    "missing dt": (edit("dt = 1e-3\n", ""), "dt", "missing (expected a number)"),
    "missing duration": (edit("duration = 1.0\n", ""), "duration", "missing (expected a number)"),
    "missing body": (edit("[body]\n" + BOX + "\n", ""), "body", "missing (expected a table)"),
    "missing shape": (edit('shape = "box"\n', ""), "body.shape", "missing (expected one of"),
    "missing mass": (edit("mass = 1.0\n", ""), "body.mass", "missing (expected a number)"),
    "missing size": (edit("size = [0.2, 0.1]\n", ""), "body.size", "missing (expected a list of two numbers)"),
    "missing radius": (edit(BOX, 'shape = "circle"\nmass = 1.0'), "body.radius", "missing (expected a number)"),
    "missing part mass": (edit(BOX, COMPOUND.replace(", mass = 1.0 }", " }")), "body.parts[0].mass",
                          "missing (expected a number)"),
    "missing initial position": (edit("position = [0.0, 0.5]\n", ""), "initial.position", "missing"),
    "empty file": ("", "duration", "missing (expected a number)"),
    "negative mass": (edit("mass = 1.0", "mass = -1.0"), "body.mass", "expected a number > 0"),
    "zero mass": (edit("mass = 1.0", "mass = 0.0"), "body.mass", "expected a number > 0"),
    "zero part mass": (edit(BOX, COMPOUND.replace("mass = 1.0 }", "mass = 0 }")), "body.parts[0].mass",
                       "expected a number > 0"),
    "negative k": (edit("k = 1e4", "k = -1e4"), "contact.k", "expected a number > 0"),
    "zero k": (edit("k = 1e4", "k = 0"), "contact.k", "expected a number > 0"),
    "negative c": (edit("c = 20.0", "c = -20.0"), "contact.c", "expected a number >= 0"),
    "negative mu": (edit("mu = 0.5", "mu = -0.5"), "contact.mu", "expected a number >= 0"),
    "zero alpha": (edit("mu = 0.5", "mu = 0.5\nalpha = 0"), "contact.alpha", "expected a number > 0"),
    "negative g": (edit("dt = 1e-3", "dt = 1e-3\ng = -9.81"), "g", "expected a number >= 0"),
    "negative size": (edit("size = [0.2, 0.1]", "size = [-0.2, 0.1]"), "body.size", "expected two numbers > 0"),
    "zero dt": (edit("dt = 1e-3", "dt = 0.0"), "dt", "expected a number > 0"),
    "negative dt": (edit("dt = 1e-3", "dt = -1e-3"), "dt", "expected a number > 0"),
    "zero duration": (edit("duration = 1.0", "duration = 0"), "duration", "expected a number > 0"),
    "negative duration": (edit("duration = 1.0", "duration = -1.0"), "duration", "expected a number > 0"),
    "dt larger than duration": (edit("dt = 1e-3", "dt = 2.0"), "dt", "expected dt <= duration"),
    "unknown shape": (edit('shape = "box"', 'shape = "triangle"'), "body.shape",
                      "expected one of: point, box, compound, circle"),
    "unknown effect": (edit('"friction"]', '"magnetism"]'), "effects", "expected a subset of"),
    "effect listed twice": (edit('"friction"]', '"friction", "friction"]'), "effects", "twice"),
    "friction without contact": (edit('["gravity", "contact", "friction"]', '["gravity", "friction"]'),
                                 "effects", "expected 'contact' in the list too"),
    "rolling friction on a box": (edit('"friction"]', '"friction", "rolling_friction"]'), "effects",
                                  "rolling circle"),
    "unknown integrator": (edit('"semi_implicit_euler"', '"verlet"'), "integrator",
                           "expected one of: explicit_euler, semi_implicit_euler, implicit_euler, rk4"),
    "unknown damping law": (edit("mu = 0.5", 'mu = 0.5\ndamping_law = "quadratic"'), "contact.damping_law",
                            "expected one of: compression, linear"),
    "unknown solref mapping": (edit('"penalty"', '"magic"'), "mujoco.solref", "expected one of"),
    "unknown MuJoCo integrator": (edit('solref = "penalty"', 'integrator = "verlet"'), "mujoco.integrator",
                                  "expected one of"),
    "a radius on a box": (edit("size = [0.2, 0.1]", "size = [0.2, 0.1]\nradius = 0.1"), "body.radius",
                          "does not belong to shape 'box'"),
    "a size on a circle": (edit(BOX, 'shape = "circle"\nmass = 1.0\nradius = 0.1\nsize = [0.2, 0.1]'),
                           "body.size", "does not belong to shape 'circle'"),
    "parts on a box": (edit("size = [0.2, 0.1]", "size = [0.2, 0.1]\nparts = []"), "body.parts",
                       "does not belong to shape 'box'"),
    "no parts in a compound": (edit(BOX, 'shape = "compound"\nparts = []'), "body.parts",
                               "expected a non-empty list"),
    "compound mass not the sum": (edit(BOX, COMPOUND + "\nmass = 2.0"), "body.mass", "differs from the sum"),
    "a turning point mass": (edit(BOX, 'shape = "point"\nmass = 1.0').replace("velocity = [0.0, 0.0]", "angle = 0.3"),
                             "initial.angle", "does not rotate"),
    "NaN mass": (edit("mass = 1.0", "mass = nan"), "body.mass", "expected a finite number"),
    "NaN dt": (edit("dt = 1e-3", "dt = nan"), "dt", "expected a finite number"),
    "NaN k": (edit("k = 1e4", "k = nan"), "contact.k", "expected a finite number"),
    "infinite duration": (edit("duration = 1.0", "duration = inf"), "duration", "expected a finite number"),
    "minus infinite damping": (edit("c = 20.0", "c = -inf"), "contact.c", "expected a finite number"),
    "infinite position": (edit("position = [0.0, 0.5]", "position = [0.0, inf]"), "initial.position",
                          "expected a finite number"),
    "NaN part size": (edit(BOX, COMPOUND.replace("size = [0.1, 0.1]", "size = [nan, 0.1]")),
                      "body.parts[0].size", "expected a finite number"),
    "a number beyond float": (edit("mass = 1.0", "mass = 1e400"), "body.mass", "expected a finite number"),
    # the box's lower corners 5 cm and 15 cm below the ground (it would be reported as chatter)
    "starting below the ground": (edit("position = [0.0, 0.5]", "position = [0.0, 0.0]"), "initial.position",
                                  "below the ground (expected a start above the ground or pressed in by at most"),
    "starting far below the ground": (edit("position = [0.0, 0.5]", "position = [0.0, -0.1]"), "initial.position",
                                      "raise initial.position's y by at least"),
    # at angle 0 this box would clear the ground by 1 cm: the angle puts a corner 5 cm into it
    "turned into the ground": (edit("velocity = [0.0, 0.0]", "angle = 1.0").replace("[0.0, 0.5]", "[0.0, 0.06]"),
                               "initial.angle", "below the ground"),
}

# Loader checks beyond the schema's types: a step count that cannot fit in memory, a MuJoCo
# step longer than the run.
LOADER_GAPS = {
    # 1e17 steps: simulate() then dies allocating 4 EiB (MemoryError, a traceback, not exit 2)
    "more steps than memory holds": (edit("dt = 1e-3", "dt = 1e-15").replace("duration = 1.0", "duration = 100.0"),
                                     "dt", "steps"),
    # a MuJoCo step longer than the whole run
    "mujoco dt larger than duration": (edit('solref = "penalty"', "dt = 2.0"), "mujoco.dt", "duration"),
}
ALL = [pytest.param(name, id=name) for name in {**CASES, **LOADER_GAPS}]


def write_case(tmp_path: Path, name: str) -> tuple[Path, str, str]:
    text, field, expected = {**CASES, **LOADER_GAPS}[name]
    path = tmp_path / "bad scene.toml"  # a space in the name: the message must still name it whole
    path.write_text(text, encoding="utf-8")
    return path, field, expected


def assert_clear(message: str, file: str, field: str, expected: str):
    """One line naming the file, the field (as `file: field: ...`) and what was expected."""
    assert "\n" not in message.strip(), f"more than one line: {message!r}"
    assert file in message, f"the file is not named: {message!r}"
    if field:
        assert f"{file}: {field}: " in message, f"the field {field!r} is not named: {message!r}"
    assert expected in message, f"{expected!r} missing from: {message!r}"


@pytest.mark.parametrize("name", ALL)
def test_the_loader_names_file_field_and_expectation(tmp_path, name):
    path, field, expected = write_case(tmp_path, name)
    with pytest.raises(SceneError) as info:
        load_scene(path)
    assert info.value.field == field
    assert_clear(str(info.value), str(path), field, expected)


def test_the_valid_base_scene_loads(tmp_path):
    path = tmp_path / "good.toml"
    path.write_text(VALID)
    assert load_scene(path).name == "bad_input_base"


def test_a_file_that_is_not_utf8(tmp_path):
    path = tmp_path / "latin1.toml"
    path.write_bytes(VALID.replace('"bad_input_base"', '"caf\xe9"').encode("latin-1"))
    with pytest.raises(SceneError) as info:
        load_scene(path)
    assert_clear(str(info.value), str(path), "", "expected a UTF-8 TOML file")


def test_a_path_that_does_not_exist(tmp_path):
    path = tmp_path / "missing.toml"
    with pytest.raises(SceneError) as info:
        load_scene(path)
    assert_clear(str(info.value), str(path), "", "no such file (expected a path to a .toml scene file)")


def test_a_path_that_is_a_folder(tmp_path):
    with pytest.raises(SceneError) as info:
        load_scene(tmp_path)
    assert_clear(str(info.value), str(tmp_path), "", "is a folder (expected a path to a .toml scene file)")


# ---------------------------------------------------------------------------------------
# Through the command line: exit status 2, one line on stderr, nothing written


def run_cli(capsys, *argv) -> tuple[int, str]:
    pytest.importorskip("compare.commands.run")
    from compare.cli import main

    status = main(["run", *map(str, argv)])
    return status, capsys.readouterr().err


def assert_untouched(out: Path, existed: bool):
    if existed:
        assert out.is_dir() and not any(out.iterdir()), f"bad input wrote {list(out.iterdir())}"
    else:
        assert not out.exists(), "bad input created the output folder"


@pytest.mark.parametrize("name", list(CASES))  # the gaps would run: the loader test covers them
@pytest.mark.parametrize("out_exists", [False, True], ids=["new-out", "empty-out"])
def test_run_refuses_bad_input(tmp_path, capsys, name, out_exists):
    path, field, expected = write_case(tmp_path, name)
    out = tmp_path / "out"
    if out_exists:
        out.mkdir()
    status, err = run_cli(capsys, path, "--out", out)
    assert status == 2
    assert_clear(err, str(path), field, expected)
    assert_untouched(out, out_exists)


@pytest.mark.parametrize("where", ["missing", "folder"])
def test_run_refuses_a_path_that_is_not_a_scene_file(tmp_path, capsys, where):
    path = tmp_path / "missing.toml" if where == "missing" else tmp_path / "a_folder"
    if where == "folder":
        path.mkdir()
    out = tmp_path / "out"
    status, err = run_cli(capsys, path, "--out", out)
    assert status == 2
    assert_clear(err, str(path), "", "expected a path to a .toml scene file")
    assert_untouched(out, False)


def test_one_bad_scene_among_good_ones_writes_nothing(tmp_path, capsys):
    good = tmp_path / "good.toml"
    good.write_text(VALID)
    bad, field, expected = write_case(tmp_path, "unknown field in [contact]")
    out = tmp_path / "out"
    status, err = run_cli(capsys, good, bad, "--out", out)
    assert status == 2
    assert_clear(err, str(bad), field, expected)
    assert_untouched(out, False)


@pytest.mark.parametrize("name", ["malformed TOML", "NaN mass"])
def test_run_in_a_fresh_process(tmp_path, name):
    """The real entry point: `python -m compare run`, its exit status and its stderr."""
    pytest.importorskip("compare.commands.run")
    path, field, expected = write_case(tmp_path, name)
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "compare", "run", str(path), "--out", str(out)],
                          capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode == 2, proc.stderr
    assert_clear(proc.stderr, str(path), field, expected)
    assert proc.stdout == ""
    assert_untouched(out, False)


def test_a_resting_start_loads_and_a_point_starting_inside_the_ground_does_not(tmp_path):
    """The allowed depth is 2 m g / k: a point released from rest there stays on the ground."""
    path = tmp_path / "rest.toml"
    # box 0.2 x 0.1 m, 1 kg, k 1e4: m g / k = 0.98 mm, up to 1.96 mm allowed
    path.write_text(edit("position = [0.0, 0.5]", "position = [0.0, 0.0485]"))   # 1.5 mm in
    assert load_scene(path).initial.position == (0.0, 0.0485)
    path.write_text(edit("position = [0.0, 0.5]", "position = [0.0, 0.048]"))    # 2 mm in
    with pytest.raises(SceneError, match=r"initial.position: .*0.002 m below the ground .* at most 0.00196 m"):
        load_scene(path)
    # a soft contact: the resting compression itself is deep (k 100 N/m: m g / k = 9.8 cm)
    path.write_text(edit("position = [0.0, 0.5]", "position = [0.0, -0.1]").replace("k = 1e4", "k = 100"))
    assert load_scene(path).initial.position == (0.0, -0.1)
    # no contact effect: no ground to start below
    path.write_text(edit("position = [0.0, 0.5]", "position = [0.0, -1.0]")
                    .replace('["gravity", "contact", "friction"]', '["gravity"]'))
    assert load_scene(path).initial.position == (0.0, -1.0)
    # no gravity: nothing rests on the spring, only placement round-off passes (a box on its
    # side at angle pi/2: cos(pi/2) = 6e-17)
    side = edit("position = [0.0, 0.5]", "position = [0.0, 0.1]\nangle = 1.5707963267948966")
    path.write_text(side.replace('["gravity", "contact", "friction"]', '["contact", "friction"]'))
    assert load_scene(path).initial.angle == pytest.approx(1.5707963267948966)
    path.write_text(side.replace('["gravity", "contact", "friction"]', '["contact", "friction"]')
                    .replace("[0.0, 0.1]", "[0.0, 0.0999]"))
    with pytest.raises(SceneError, match="initial.angle: .*0.0001 m below the ground"):   # flat, it would clear it
        load_scene(path)


@pytest.mark.parametrize("under", ["a_file.txt/sub", "a_file.txt/sub/deeper", "a_file.txt"])
def test_run_refuses_an_out_folder_under_a_file(tmp_path, capsys, under):
    """--out under a file was a NotADirectoryError traceback: now exit 2 naming the path, nothing written."""
    good = tmp_path / "good.toml"
    good.write_text(VALID)
    (tmp_path / "a_file.txt").write_text("not a folder\n")
    before = sorted(p.name for p in tmp_path.iterdir())
    out = tmp_path / under
    status, err = run_cli(capsys, good, "--out", out)
    assert status == 2, err
    assert err.startswith("error: ") and err.count("\n") == 1 and str(out) in err and "a_file.txt" in err, err
    assert "expected" in err and "Traceback" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == before
    assert (tmp_path / "a_file.txt").read_text() == "not a folder\n"
