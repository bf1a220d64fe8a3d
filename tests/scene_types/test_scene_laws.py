"""The [contact] table's laws: every family named, each parameter only where its family takes
it, and a law file laid over a scene's own contact (`run --law FILE.toml`)."""
from __future__ import annotations

import pytest

from compare.cli import main
from compare.scenarios import load
from scene_types import DAMPING_LAWS, FRICTION_LAWS, ROLL_LAWS, SceneError, parse_scene
from scene_types.law_file import load_law, with_law

BASE = {"duration": 0.1, "dt": 1e-3, "body": {"shape": "box", "mass": 1.0, "size": [0.2, 0.1]},
        "initial": {"position": [0.0, 0.5]}}


def scene_with(contact: dict, effects=("gravity", "contact", "friction")):
    return parse_scene({**BASE, "effects": list(effects), "contact": contact}, file="s.toml")


@pytest.mark.parametrize("law", DAMPING_LAWS)
def test_every_damping_family_parses(law):
    params = {"dissipation": 2.0} if law == "hunt_crossley" else {"c": 5.0}
    ct = scene_with({"damping_law": law, **params}).contact
    assert ct.damping_law == law
    assert (ct.dissipation, ct.c) == ((2.0, 0.0) if law == "hunt_crossley" else (0.0, 5.0))


@pytest.mark.parametrize("law", FRICTION_LAWS)
def test_every_friction_family_parses(law):
    ct = scene_with({"friction_law": law}).contact
    assert ct.friction_law == law and (ct.alpha is None) == (law == "sign")


@pytest.mark.parametrize("law", ROLL_LAWS)
def test_every_rolling_family_parses(law):
    ct = scene_with({"roll_law": law}).contact
    assert ct.roll_law == law and (ct.roll_sharpness is None) == (law == "sign")


@pytest.mark.parametrize("contact, field, says", [
    ({"damping_law": "hunt_crossley"}, "contact.dissipation", "is required by damping_law = 'hunt_crossley'"),
    ({"damping_law": "hunt_crossley", "dissipation": 1.0, "c": 3.0}, "contact.c",
     "is not a parameter of damping_law = 'hunt_crossley'"),
    ({"dissipation": 1.0}, "contact.dissipation", "is not a parameter of damping_law = 'compression'"),
    ({"friction_law": "sign", "alpha": 50.0}, "contact.alpha", "is not a parameter of friction_law = 'sign'"),
    ({"roll_law": "sign", "roll_sharpness": 50.0}, "contact.roll_sharpness", "is not a parameter of roll_law = 'sign'"),
    ({"friction_law": "stribeck"}, "contact.friction_law", "expected one of: tanh, ramp, smooth_coulomb, sign"),
    ({"damping_law": "hunt_crossley", "dissipation": -1.0}, "contact.dissipation", ">= 0"),
])
def test_a_law_is_never_half_read(contact, field, says):
    with pytest.raises(SceneError) as err:
        scene_with(contact)
    assert err.value.file == "s.toml" and err.value.field == field and says in str(err.value), str(err.value)


def write(tmp_path, text: str):
    path = tmp_path / "law.toml"
    path.write_text(text)
    return path


def test_a_law_file_replaces_a_family_and_keeps_the_scenes_parameters(tmp_path):
    scene = load("box_drop")
    law = load_law(write(tmp_path, '[contact]\ndamping_law = "hunt_crossley"\ndissipation = 2.0\n'))
    judged = with_law(scene, law, "law.toml")
    ct = judged.contact
    assert (ct.damping_law, ct.dissipation, ct.c) == ("hunt_crossley", 2.0, 0.0)
    assert (ct.k, ct.mu, ct.alpha, ct.friction_law) == (scene.contact.k, scene.contact.mu, scene.contact.alpha, "tanh")
    assert judged.scene_contact == scene.contact and judged.law_from == "law.toml"


def test_a_law_file_may_not_leave_out_what_its_family_needs(tmp_path):
    with pytest.raises(SceneError) as err:
        load_law(write(tmp_path, '[contact]\ndamping_law = "hunt_crossley"\n'))
    assert err.value.field == "contact.dissipation"


@pytest.mark.parametrize("text, field", [("[contact]\nmuu = 1\n", "contact.muu"), ("x = 1\n", "x"),
                                         ("[contact]\nfriction_law = 'sign'\nalpha = 3.0\n", "contact.alpha")])
def test_run_refuses_a_bad_law_file_and_writes_nothing(tmp_path, capsys, text, field):
    path = write(tmp_path, text)
    out = tmp_path / "out"
    assert main(["run", "box_slide", "--law", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"error: {path}: {field}:"), err
    assert not out.exists()


def test_law_identified_needs_a_simulator_under_test(tmp_path, capsys):
    assert main(["run", "box_slide", "--law", "identified", "--out", str(tmp_path / "o")]) == 2
    assert "--law identified: expected --sim" in capsys.readouterr().err


def test_a_study_may_vary_a_family_and_the_old_familys_parameters_fall_away():
    from compare.tools.study.fields import SceneSource, parse_vary
    from compare.scenarios import builtin_paths

    source = SceneSource.read(next(p for p in builtin_paths() if p.stem == "box_slide"))
    sign = source.varied([parse_vary("contact.friction_law=sign")], ("sign",))
    assert (sign.contact.friction_law, sign.contact.alpha) == ("sign", None)
    ramp = source.varied([parse_vary("contact.friction_law=ramp")], ("ramp",))
    assert (ramp.contact.friction_law, ramp.contact.alpha) == ("ramp", source.scene.contact.alpha)
    hc = source.varied([parse_vary("contact.damping_law=hunt_crossley"), parse_vary("contact.dissipation=1,2")],
                       ("hunt_crossley", 2.0))
    assert (hc.contact.damping_law, hc.contact.dissipation, hc.contact.c) == ("hunt_crossley", 2.0, 0.0)


FORCE_ROUNDOFF = 1e-12   # relative: two codes evaluating the same friction, a dozen roundings apart


def test_a_law_that_differs_by_round_off_is_not_said_to_differ():
    """The page names an effect only where the two laws' forces differ beyond round-off over the
    run: a fitted mu off by 1e-13 is the scene's, one off by 1 % is named with its newtons."""
    import dataclasses

    from compare.checks.law_difference import law_differences
    from custom_sim import simulate

    scene = dataclasses.replace(load("box_slide"), duration=0.3)
    run = simulate(scene)
    ct = scene.contact
    same = with_law(scene, dataclasses.replace(ct, mu=ct.mu * (1 + 1e-13)), "identified")
    assert law_differences(same, run.t, run.states()) == []
    other = with_law(scene, dataclasses.replace(ct, mu=ct.mu * 1.01), "identified")
    [row] = law_differences(other, run.t, run.states())
    # friction is linear in mu: 1 % of the scene law's friction at that step, read through the
    # energy package's own law (another implementation than the oracle's the page uses)
    from compare.energy.law import body_of, loads
    ft = loads(scene, body_of(scene), run.states()[row["step"]][None, :]).ft.sum()
    assert row["effect"] == "friction"
    assert abs(row["force"][0] - 0.01 * ft) < FORCE_ROUNDOFF * abs(ft), (row["force"][0], 0.01 * ft)
