"""A user's law is data: identify recovers every family from custom_sim's own step on every body,
and the two worked examples (a Hunt-Crossley contact, a stiction ramp) pass under their own law,
fail under the seed's with the effect named, and fail under their own law once a mistake is put in."""
from __future__ import annotations

import dataclasses
import json
import re

import pytest

from compare.cli import main
from compare.identification import identify_step
from compare.scenarios import load
from test_identify import PARAMETER_RTOL, Direct, custom_step

BODIES = ("point_drop", "box_drop", "t_shape_drop", "rolling_circle")
NORMAL = {"compression": {"c": 20.0}, "linear": {"c": 20.0}, "unclamped": {"c": 20.0},
          "hunt_crossley": {"c": 0.0, "dissipation": 1.5}}
FRICTION = {"tanh": {"alpha": 80.0}, "ramp": {"alpha": 80.0}, "smooth_coulomb": {"alpha": 80.0},
            "sign": {"alpha": None}}


def under(scene, **changes):
    return dataclasses.replace(scene, contact=dataclasses.replace(scene.contact, **changes))


def close(a, b) -> bool:
    return a is not None and abs(a - b) <= PARAMETER_RTOL * max(abs(b), 1.0)


@pytest.mark.parametrize("law", NORMAL)
@pytest.mark.parametrize("name", BODIES)
def test_identify_recovers_each_damping_family_from_custom_sim(name, law):
    scene = under(load(name), damping_law=law, **NORMAL[law])
    n = identify_step(Direct(custom_step(scene)), scene)["normal"]
    assert n["law"] == law, n
    assert close(n["k"], scene.contact.k)
    assert close(n["dissipation"] if law == "hunt_crossley" else n["c"], NORMAL[law].get("dissipation", 20.0))


@pytest.mark.parametrize("law", FRICTION)
@pytest.mark.parametrize("name", BODIES)
def test_identify_recovers_each_friction_family_from_custom_sim(name, law):
    scene = under(load(name), friction_law=law, mu=0.4, **FRICTION[law])
    f = identify_step(Direct(custom_step(scene)), scene)["friction"]
    assert f["law"] == law, f
    assert close(f["mu"], 0.4)
    if law != "sign":
        assert close(f["alpha"], 80.0)


@pytest.mark.parametrize("law, sharpness", [("tanh", 60.0), ("sign", None)])
def test_identify_recovers_each_rolling_family_from_custom_sim(law, sharpness):
    scene = under(load("rolling_circle"), roll_law=law, roll_sharpness=sharpness, mu_roll=0.003)
    r = identify_step(Direct(custom_step(scene)), scene)["rolling"]
    assert r["law"] == law and close(r["mu_roll"], 0.003), r
    if sharpness:
        assert close(r["roll_sharpness"], sharpness)


# -- the worked examples, end to end ----------------------------------------------------------

def short_scene(tmp_path, name: str, duration: float):
    """A built-in scene file cut to `duration` s (the checks' verdicts need the first landing)."""
    path = tmp_path / f"{name}.toml"
    path.write_text(re.sub(r"(?m)^duration = .*$", f"duration = {duration}", open(load(name).source).read()))
    return str(path)


def run(tmp_path, capsys, *argv):
    out = tmp_path / f"out{len(list(tmp_path.iterdir()))}"
    status = main(["run", *argv, "--out", str(out)])
    return status, capsys.readouterr(), out


EXAMPLES = [pytest.param("examples/hunt_crossley_sim.py", "box_drop", 0.6, "normal", "hunt_crossley",
                         "examples/laws/hunt_crossley.toml", marks=pytest.mark.slow),
            ("examples/stiction_ramp_sim.py", "box_slide", 0.6, "friction", "ramp",
             "examples/laws/stiction_ramp.toml")]


@pytest.mark.parametrize("module, name, duration, effect, family, law_file", EXAMPLES)
def test_an_example_passes_under_its_own_law_and_is_named_under_the_seeds(tmp_path, capsys, module, name,
                                                                           duration, effect, family, law_file):
    scene = short_scene(tmp_path, name, duration)
    for law in ("identified", law_file):
        status, said, out = run(tmp_path, capsys, scene, "--sim", f"{module}:step", "--law", law)
        assert status == 0, said.out
        data = json.loads((out / name / "metrics.json").read_text())
        assert data["law"]["judged"][{"normal": "damping_law", "friction": "friction_law"}[effect]] == family
        assert [d["effect"] for d in data["law"]["differences"]] == [effect]
        assert data["law"]["differences"][0]["largest"] > 1e-3
    status, said, out = run(tmp_path, capsys, scene, "--sim", f"{module}:step")
    assert status == 1, said.out
    verdict = json.loads((out / name / "metrics.json").read_text())["diagnosis"]["verdict"]
    assert verdict.startswith("your law differs from the scene's") and family in verdict, verdict
    assert "`run --law identified` judges your code under it" in verdict


@pytest.mark.parametrize("wrong, right", [("(1.0 - DISSIPATION * normal_velocity)", "(1.0 + DISSIPATION * normal_velocity)"),
                                          pytest.param("np.maximum(0.0, ct[\"k\"]", "np.maximum(0.0, 1.01 * ct[\"k\"]",
                                                       marks=pytest.mark.slow)])
def test_the_same_code_with_one_mistake_fails_under_its_own_law(tmp_path, capsys, wrong, right):
    text = open("examples/hunt_crossley_sim.py").read()
    assert wrong in text
    broken = tmp_path / "broken_hc.py"
    broken.write_text(text.replace(wrong, right, 1))
    scene = short_scene(tmp_path, "box_drop", 0.6)
    status, said, _ = run(tmp_path, capsys, scene, "--sim", f"{broken}:step", "--law", "examples/laws/hunt_crossley.toml")
    assert status == 1 and "FAIL" in said.out, said.out


OUTSIDER = "tests/outsiders/rk4_smooth_unclamped.py"


def test_an_outsiders_law_is_identified_and_its_code_judged_under_it(tmp_path, capsys):
    """Another style (RK4, a dict state, tuples back) and another law (unclamped, c = 15 N s/m;
    smooth Coulomb, eps = 0.02 m/s): identified, passing under it, and told which effects differ."""
    assert main(["identify", f"{OUTSIDER}:step", "point_drop", "--json"]) == 1
    found = json.loads(capsys.readouterr().out)
    assert (found["integrator"]["name"], found["normal"]["law"], found["friction"]["law"]) == \
        ("rk4", "unclamped", "smooth_coulomb")
    assert close(found["normal"]["c"], 15.0) and close(found["friction"]["alpha"], 50.0)
    scene = short_scene(tmp_path, "point_drop", 0.6)
    status, said, _ = run(tmp_path, capsys, scene, "--sim", f"{OUTSIDER}:step", "--law", "identified")
    assert status == 0, said.out
    status, said, _ = run(tmp_path, capsys, scene, "--sim", f"{OUTSIDER}:step")
    assert status == 1
    assert "law   your normal force is unclamped (k 10000 N/m, c 15 N s/m)" in said.out, said.out
    assert "law   your friction is smooth_coulomb (mu 0.5, alpha 50 s/m)" in said.out, said.out
