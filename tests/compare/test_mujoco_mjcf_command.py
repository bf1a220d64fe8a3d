"""`python -m compare mjcf SCENE [-o FILE]`: prints or writes a model MuJoCo loads; bad input
exits 2, names the file and writes nothing."""
import mujoco
import pytest

from compare.cli import main
from compare.scenarios import builtin_names, load


def test_prints_mjcf_that_loads(capsys, tmp_path):
    assert main(["mjcf", "rolling_circle"]) == 0
    xml = capsys.readouterr().out
    path = tmp_path / "printed.xml"
    path.write_text(xml)
    model = mujoco.MjModel.from_xml_path(str(path))
    assert model.body("body").mass[0] == pytest.approx(load("rolling_circle").body.mass)


@pytest.mark.parametrize("name", builtin_names())
def test_writes_a_file_for_every_builtin(name, tmp_path, capsys):
    out = tmp_path / "sub" / f"{name}.xml"
    assert main(["mjcf", name, "-o", str(out)]) == 0
    assert str(out) in capsys.readouterr().out
    model = mujoco.MjModel.from_xml_path(str(out))
    assert model.nkey == 1 and model.key("initial").id == 0


def test_a_scene_path_and_a_mapping(tmp_path, capsys):
    scene = tmp_path / "drop.toml"
    scene.write_text('duration = 0.1\ndt = 1e-4\n[body]\nshape = "point"\nmass = 2.0\n'
                     '[initial]\nposition = [0.0, 1.0]\n')
    assert main(["mjcf", str(scene), "--solref", "physical"]) == 0
    assert 'model="drop"' in capsys.readouterr().out


@pytest.mark.parametrize("spec", ["no_such_scene", "missing/file.toml"])
def test_bad_scene_exits_2_and_writes_nothing(spec, tmp_path, capsys):
    out = tmp_path / "model.xml"
    assert main(["mjcf", spec, "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert spec in err
    assert not out.exists()


def test_invalid_scene_names_the_field(tmp_path, capsys):
    scene = tmp_path / "bad.toml"
    scene.write_text('duration = 0.1\ndt = 1e-4\n[body]\nshape = "box"\nmass = 1.0\nsize = [0.2, -0.1]\n'
                     '[initial]\nposition = [0.0, 1.0]\n')
    assert main(["mjcf", str(scene)]) == 2
    captured = capsys.readouterr()
    assert "body.size" in captured.err and captured.out == ""


def test_a_file_name_with_double_dashes_still_gives_valid_xml(tmp_path, capsys):
    scene = tmp_path / "a--b.toml"
    scene.write_text('duration = 0.1\ndt = 1e-4\n[body]\nshape = "point"\nmass = 1.0\n'
                     '[initial]\nposition = [0.0, 1.0]\n')
    out = tmp_path / "m.xml"
    assert main(["mjcf", str(scene), "-o", str(out)]) == 0
    mujoco.MjModel.from_xml_path(str(out))
