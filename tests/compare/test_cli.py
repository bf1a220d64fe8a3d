"""The command line of docs/cli.md: help, list, run's output files and exit statuses."""
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from compare.cli import main
from compare.scenarios import builtin_names
from custom_sim import read_csv
from scene_types.trajectory import CSV_COLUMNS
from short_scene import short_scene

ROOT = Path(__file__).resolve().parents[2]


def test_list_shows_every_builtin(capsys):
    assert main(["list"]) == 0
    out = capsys.readouterr().out
    for name in builtin_names():
        assert name in out


def test_output_to_a_reader_that_went_away_ends_quietly():
    """`python -m compare list | head -1`: the pipe's reader is gone before the listing is
    written. The command stops with the shell's status for it (128 + SIGPIPE) and no traceback."""
    import os
    read, write = os.pipe()
    os.close(read)
    try:
        done = subprocess.run([sys.executable, "-m", "compare", "list"], cwd=ROOT, stdout=write,
                              stderr=subprocess.PIPE, text=True, timeout=60)
    finally:
        os.close(write)
    assert done.returncode == 141 and done.stderr == "", (done.returncode, done.stderr)


def test_run_writes_the_contract_files(tmp_path):
    pytest.importorskip("mujoco_models")
    scene = short_scene(tmp_path)
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "compare", "run", str(scene), "--out", str(out)],
                          capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode in (0, 1), proc.stderr
    folder = out / "point_drop_short"
    for name in ("metrics.json", "trajectory_custom.csv", "trajectory_mujoco.csv", "model.xml", "index.md"):
        assert (folder / name).is_file(), name
    assert list(folder.glob("*.png"))
    data = json.loads((folder / "metrics.json").read_text())
    for key in ("name", "integrator", "dt", "steps", "position_error_max", "position_error_rms",
                "angle_error_max", "energy_drift_custom", "energy_drift_mujoco", "tolerance", "pass",
                "wall_time_custom", "wall_time_mujoco"):
        assert key in data, key
    assert data["steps"] == round(0.4 / data["dt"]) and data["pass"] == (proc.returncode == 0)
    for sim in ("custom", "mujoco"):
        lines = (folder / f"trajectory_{sim}.csv").read_text().splitlines()
        assert lines[0] == ",".join(CSV_COLUMNS) and len(lines) == data["steps"] + 2  # header, t = 0, every step
        cols = read_csv(folder / f"trajectory_{sim}.csv")
        assert cols["t"][0] == 0.0 and cols["t"][1] == pytest.approx(data["dt"])
        assert cols["y"][0] == pytest.approx(0.6) and np.all(np.isfinite(cols["energy"]))
    index = (out / "index.md").read_text()
    assert "[point_drop_short](point_drop_short/index.md)" in index
    assert not [p for p in out.iterdir() if p.name.startswith(".")], "no temporary left behind"


def test_unknown_scenario_is_bad_input(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["run", "no_such_scene", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "no_such_scene" in err and "expected" in err
    assert not out.exists()


def sign_scene(tmp_path, builtin, integrator, duration):
    """A built-in scene under the bare sign friction (friction_law = "sign", no alpha), cut short."""
    lines = []
    for line in (ROOT / "scenarios" / f"{builtin}.toml").read_text().splitlines():
        if line.startswith("alpha"):
            line = 'friction_law = "sign"'
        elif line.startswith("integrator") and not any(seen.startswith("[") for seen in lines):   # top level
            line = f'integrator = "{integrator}"'
        elif line.startswith("duration"):
            line = f"duration = {duration}"
        lines.append(line)
    path = tmp_path / f"{builtin}_sign_{integrator}.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.slow
@pytest.mark.parametrize("builtin, integrator", [("box_drop", "implicit_euler"), ("box_drop", "rk4")])
def test_a_bare_sign_scene_ends_in_a_verdict_and_nothing_else(tmp_path, builtin, integrator):
    """Under the bare sign the box starts at rest in the air, every slip exactly 0 with no load:
    the run ends in its verdict line, with no Python warning or traceback on the way and no NaN
    in metrics.json (about 20 s)."""
    pytest.importorskip("mujoco_models")
    scene = sign_scene(tmp_path, builtin, integrator, 0.4)
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-W", "default", "-m", "compare", "run", str(scene), "--out", str(out)],
                          capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode in (0, 1), proc.stderr
    assert "Warning" not in proc.stderr and "Traceback" not in proc.stderr, proc.stderr
    name = scene.stem
    verdict = next(line for line in proc.stdout.splitlines() if line.startswith(name))
    assert verdict.split()[1] in ("pass", "FAIL", "unstable:"), verdict
    data = json.loads((out / name / "metrics.json").read_text())
    assert all(entry["value"] != "nan" for entry in data.get("non_finite", [])), data["non_finite"]
