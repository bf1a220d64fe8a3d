"""The attribution ladder: every difference between custom_sim and MuJoCo's native contact
measured, cause by cause, against what the physics says each cause does."""
import dataclasses

import pytest
from markdown_table import rows as table_rows

from compare.scenarios import load
from compare.checks.attribution import attribute, cause


def ladder(name: str, duration: float | None = None) -> dict:
    scene = load(name)
    if duration is not None:
        scene = dataclasses.replace(scene, duration=duration)
    rows = attribute(scene)
    return {r["name"]: r for r in rows}, rows


def test_rungs_in_order():
    """Each rung removes one cause, from MuJoCo's native contact to custom_sim itself."""
    by_name, rows = ladder("box_drop", 0.5)
    assert [r["name"] for r in rows] == ["native", "friction law", "contact point", "mapping"]
    assert all(r["measured"] for r in rows), [r["note"] for r in rows]
    assert all(r["cause"] == cause(r["name"], load("box_drop")) for r in rows)
    assert "mu Fn tanh(alpha v)" in by_name["friction law"]["cause"]
    _, rows = ladder("rolling_circle", 0.5)
    assert [r["name"] for r in rows] == ["native", "friction law and shared cone", "contact point", "mapping",
                                         "damping law"]


def test_box_difference_is_the_mid_penetration_contact_point():
    """A tumbling box: with our friction law at MuJoCo's midpoint most of the difference stays;
    moving friction to our corner removes it (measured: 0.034 m -> 9e-4 m on box_drop)."""
    by_name, _ = ladder("box_drop")
    native, point = by_name["native"], by_name["contact point"]
    assert point["share_position"] > 0.5 * native["position_error_max"], point
    assert by_name["mapping"]["share_position"] < 0.1 * native["position_error_max"]


def test_point_drop_difference_is_the_damping_law():
    """A point mass cannot turn: no contact-point cause, and its friction stops it either way;
    what is left is the compression law's higher rebounds."""
    by_name, _ = ladder("point_drop")
    native = by_name["native"]["position_error_max"]
    assert by_name["damping law"]["share_position"] > 0.99 * native
    assert by_name["contact point"]["step_position"] == 0.0


@pytest.mark.slow
def test_stiff_contact_difference_is_the_friction_law_at_impact():
    """stiff_contact's 0.166 m: at the first impact the load peaks at ~4000 m g; our tanh law
    brakes at mu Fn and nearly stops the slide (0.5 -> 0.026 m/s in 0.1 ms), MuJoCo's viscous
    row (slope set at the resting load) barely slows it (0.5 -> 0.48 m/s). The rest is the
    damping law; the mapping takes 1e-9 m."""
    by_name, _ = ladder("stiff_contact")
    native = by_name["native"]["position_error_max"]
    assert native > 0.1
    friction = by_name["friction law"]
    assert friction["step_position"] > 0.9 * native and friction["share_position"] > 0.4 * native
    assert by_name["damping law"]["share_position"] > 0.3 * native
    assert abs(by_name["mapping"]["share_position"]) < 1e-6


def test_a_scene_without_friction_has_no_friction_rungs():
    by_name, rows = ladder("elastic_bounce", 1.0)
    assert [r["name"] for r in rows] == ["native", "mapping"]


def test_attribute_command(capsys, tmp_path):
    from compare.cli import main

    out = tmp_path / "rows.json"
    assert main(["attribute", "elastic_bounce", "--json", str(out)]) == 0
    text = capsys.readouterr().out
    assert "## Check contact" in text
    contact = table_rows(text)[0]
    assert contact[0] == "elastic_bounce" and contact[-1] == "pass", contact
    import json
    rows = json.loads(out.read_text())
    assert rows[0]["contact"]["pass"] is True and rows[0]["attribution"][0]["name"] == "native"
    assert main(["attribute", "no_such_scene"]) == 2
    assert "unknown scenario" in capsys.readouterr().err


@pytest.mark.parametrize("law, words", [("hunt_crossley", "no damping at touchdown"),
                                        ("unclamped", "pulls the body down"),
                                        ("compression", "damps only while a point approaches")])
def test_the_damping_rung_names_the_scenes_family(law, words):
    scene = load("point_drop")
    params = {"dissipation": 2.0, "c": 0.0} if law == "hunt_crossley" else {}
    scene = dataclasses.replace(scene, contact=dataclasses.replace(scene.contact, damping_law=law, **params))
    assert words in cause("damping law", scene)
