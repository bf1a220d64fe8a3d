"""`python -m compare scene`: the resolved scene a user's simulator is given."""
import json
import subprocess
import sys
from pathlib import Path

import pytest

from compare.cli import main
from compare.scenarios import builtin_names, load
from compare.usersim import scene_dict

ROOT = Path(__file__).resolve().parents[3]


def test_json_is_the_dict_a_step_function_gets():
    proc = subprocess.run([sys.executable, "-m", "compare", "scene", "t_shape_drop", "--json"],
                          capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout) == scene_dict(load("t_shape_drop"))


@pytest.mark.parametrize("name", builtin_names())
def test_every_default_is_filled_in(name):
    d = scene_dict(load(name))
    assert json.loads(json.dumps(d)) == d  # plain JSON types only
    for key in ("duration", "dt", "steps", "integrator", "effects", "g", "state0"):
        assert d[key] is not None, key
    assert set(d["contact"]) == {"k", "c", "damping_law", "dissipation", "mu", "alpha", "friction_law", "mu_roll",
                                 "roll_law", "roll_sharpness"}
    assert set(d["initial"]) == {"position", "velocity", "angle", "angular_velocity"}
    assert d["mujoco"]["dt"] is not None
    assert d["steps"] * d["dt"] == pytest.approx(d["duration"])


def test_mass_properties_are_the_textbook_ones():
    """Box m (w^2 + h^2)/12 with corners at +-w/2, +-h/2; disk m R^2 / 2 with one point R below;
    T-shape by the parallel-axis theorem about its centre of mass (worked by hand here)."""
    box = scene_dict(load("box_drop"))["mass_properties"]
    assert box["inertia"] == pytest.approx(2.0 * (0.2 ** 2 + 0.1 ** 2) / 12, rel=1e-15)
    assert sorted(map(tuple, box["contact_points"])) == sorted([(-0.1, -0.05), (0.1, -0.05), (0.1, 0.05), (-0.1, 0.05)])
    disk = scene_dict(load("rolling_circle"))["mass_properties"]
    assert disk["inertia"] == pytest.approx(0.5 * 2.0 * 0.1 ** 2) and disk["contact_points"] == [[0.0, -0.1]]
    assert disk["points_rotate"] is False and disk["rotates"] is True
    t = scene_dict(load("t_shape_drop"))["mass_properties"]
    com_y = (0.9 * 0.12 + 0.6 * 0.0) / 1.5
    inertia = (0.9 * (0.30 ** 2 + 0.06 ** 2) / 12 + 0.9 * (0.12 - com_y) ** 2
               + 0.6 * (0.06 ** 2 + 0.24 ** 2) / 12 + 0.6 * com_y ** 2)
    assert t["com"] == pytest.approx([0.0, com_y]) and t["inertia"] == pytest.approx(inertia, rel=1e-12)
    point = scene_dict(load("point_drop"))["mass_properties"]
    assert point["contact_points"] == [[0.0, -0.05]] and point["rotates"] is False


def test_text_form_and_bad_scene(capsys, tmp_path):
    assert main(["scene", "box_slide"]) == 0
    out = capsys.readouterr().out
    assert "inertia:" in out and "contact_points:" in out
    assert main(["scene", str(tmp_path / "missing.toml")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "missing.toml" in err[0] and "no such file" in err[0]
