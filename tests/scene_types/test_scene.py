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


@pytest.mark.parametrize("path", builtin_paths() + builtin_paths("stress"), ids=lambda p: p.stem)
def test_every_builtin_and_stress_scene_starts_above_the_allowed_depth(path):
    """Each starts at most at the resting compression (resting_60s: 1.01 m g / k), well inside
    the allowed 2 m g / k, or in the air."""
    import numpy as np

    from custom_sim import mass_properties
    from custom_sim.bodies import contact_points_world
    from scene_types.schema import allowed_initial_depth

    s = load_scene(path)
    i = s.initial
    _, py = contact_points_world(mass_properties(s.body), i.position[0], i.position[1], i.angle)
    g = s.g if "gravity" in s.effects else 0.0
    assert -float(np.min(py)) <= allowed_initial_depth(s.body, g, s.contact.k)


def test_the_depth_is_checked_for_scene_files_and_on_request():
    """A scene built in code may start a spring pressed in on purpose (the tests of one implicit
    Euler step; custom_sim's compile warm-up presses its box 1 cm in): parse_scene checks the
    initial depth only when asked, load_scene always."""
    data = {**REQUIRED, "initial": {"position": [0.0, 0.05]}}    # the disk 5 cm into the ground
    assert parse_scene(data).initial.position == (0.0, 0.05)
    with pytest.raises(SceneError, match="initial.position"):
        parse_scene(data, check_initial_depth=True)


@pytest.mark.parametrize("body, position, angle, field", [
    ({"shape": "circle", "mass": 1.0, "radius": 0.1}, [0.0, 0.05], 0.0, "initial.position"),
    ({"shape": "point", "mass": 1.0, "contact_height": 0.05}, [0.0, 0.0], 0.0, "initial.position"),
    ({"shape": "compound", "parts": [{"size": [0.3, 0.05], "offset": [0.0, 0.1], "mass": 1.0},
                                     {"size": [0.05, 0.2], "offset": [0.0, 0.0], "mass": 1.0}]},
     [0.0, 0.15], -2.03, "initial.angle"),   # upright on the ground (allowed); turned, a crossbar corner 1.8 cm in
])
def test_a_start_below_the_ground_names_the_field_and_the_allowed_depth(body, position, angle, field):
    data = {**REQUIRED, "body": body, "initial": {"position": position, "angle": angle}}
    with pytest.raises(SceneError) as info:
        parse_scene(data, file="x.toml", check_initial_depth=True)
    err = info.value
    assert err.field == field and str(err).startswith(f"x.toml: {field}: puts contact point")
    assert "below the ground (expected a start above the ground or pressed in by at most" in str(err)
    assert "m g / k" in str(err) and "\n" not in str(err)
