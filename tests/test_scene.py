"""The scene loader: built-ins load, defaults apply, typos are refused (issue 6 tests the rest)."""
import pytest

from custom_sim import SceneError, load_scene, parse_scene
from compare.scenarios import builtin_paths

REQUIRED = {"duration": 1.0, "dt": 1e-3, "body": {"shape": "circle", "mass": 1.0, "radius": 0.1},
            "initial": {"position": [0.0, 0.1]}}


@pytest.mark.parametrize("path", builtin_paths(), ids=lambda p: p.stem)
def test_builtins_load_with_a_description(path):
    scene = load_scene(path)
    assert scene.name == path.stem and len(scene.description) > 20


def test_defaults():
    s = parse_scene(REQUIRED)
    assert s.integrator == "semi_implicit_euler" and s.effects == ("gravity", "contact", "friction")
    assert s.g == 9.81 and s.mujoco.solref == "penalty" and s.mujoco.dt is None and s.steps == 1000


def test_a_typo_is_an_error_naming_the_field():
    with pytest.raises(SceneError, match=r"x.toml: contact.mus: unknown field"):
        parse_scene({**REQUIRED, "contact": {"mus": 0.5}}, file="x.toml")


def test_a_field_of_another_shape_is_an_error():
    with pytest.raises(SceneError, match=r"body.size: does not belong to shape 'circle'"):
        parse_scene({**REQUIRED, "body": {**REQUIRED["body"], "size": [1, 1]}})
