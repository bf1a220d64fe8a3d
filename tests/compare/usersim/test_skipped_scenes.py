"""Code that does only some scenes (issue 34, item 3): a module's SHAPES and a step's
NotImplementedError skip a scene with the reason; skipped scenes are never judged and fail
nothing (run, validate, identify, run --law identified), and a run where every scene was
skipped is not a pass. The simulators are outsiders' box-only code (tests/outsiders/)."""
import dataclasses
import json
import re
import textwrap
from pathlib import Path

import pytest

from compare.cli import main
from compare.scenarios import load
from compare.usersim import SceneSkipped, UserCodeError, load_simulator, run_user

ROOT = Path(__file__).resolve().parents[3]
CLASS_SIM = str(ROOT / "tests" / "outsiders" / "box_only_class.py") + ":step"     # NotImplementedError
SHAPES_SIM = str(ROOT / "tests" / "outsiders" / "box_only_shapes.py") + ":step"   # SHAPES = ("box",)
CLASS_REASON = "BoxWorld does boxes only, not a point"


def short_file(tmp_path, builtin: str, duration: float = 0.05) -> str:
    """A built-in scene with a shorter duration (s), written as <builtin>.toml."""
    text = (ROOT / "scenarios" / f"{builtin}.toml").read_text()
    text = "\n".join(f"duration = {duration}" if line.startswith("duration") else line for line in text.splitlines())
    path = tmp_path / f"{builtin}.toml"
    path.write_text(text)
    return str(path)


def module(tmp_path, text: str, name: str = "user_sim") -> str:
    path = tmp_path / f"{name}.py"
    path.write_text(textwrap.dedent(text))
    return str(path) + ":step"


def run_cli(argv, capsys):
    code = main(argv)
    captured = capsys.readouterr()
    return code, captured.out, captured.err


# --- what the loader answers -----------------------------------------------------------------

@pytest.mark.parametrize("shapes, said", [
    ('"box"', "a string, not a tuple"),
    ('("box", "sphere")', "'sphere' is not a shape the harness knows"),
    ("3", "expected a tuple of shape names"),
    ("()", "expected a tuple of shape names"),
])
def test_a_bad_shapes_is_bad_input_naming_the_module_the_field_and_what_was_expected(tmp_path, capsys, shapes, said):
    spec = module(tmp_path, f"SHAPES = {shapes}\ndef step(z, scene, dt):\n    return z\n")
    with pytest.raises(UserCodeError) as caught:
        load_simulator(spec)
    message = str(caught.value)
    assert message.startswith(f"{spec}: SHAPES = {shapes.replace(chr(34), chr(39))}: ") and said in message, message
    assert "point, box, compound, circle" in message, message
    out = tmp_path / "out"
    code, _, err = run_cli(["run", "point_drop", "--sim", spec, "--out", str(out)], capsys)
    assert code == 2 and said in err and err.count("\n") == 1 and not out.exists(), err


def test_a_shape_left_out_of_shapes_is_skipped_without_calling_the_code(tmp_path):
    called = tmp_path / "called"
    spec = module(tmp_path, f"""
        SHAPES = ["box", "compound"]
        def step(z, scene, dt):
            open({str(called)!r}, "w").close()
            return z
        """)
    sim = load_simulator(spec)
    circle = dataclasses.replace(load("rolling_circle"), duration=0.01)
    with pytest.raises(SceneSkipped) as caught:
        run_user(sim, circle)
    assert caught.value.reason == "a circle body, not in the module's SHAPES = ('box', 'compound')"
    assert not called.exists()
    run_user(sim, dataclasses.replace(load("box_slide"), duration=0.001))   # a box: called
    assert called.exists()


def test_not_implemented_error_skips_with_its_message_and_the_step_when_not_the_first(tmp_path):
    scene = dataclasses.replace(load("point_drop"), duration=0.01)
    with pytest.raises(SceneSkipped) as caught:
        run_user(load_simulator(CLASS_SIM), scene)
    assert caught.value.reason == CLASS_REASON
    later = module(tmp_path, """
        def step(z, scene, dt):
            if z[1] < 0.5999:
                raise NotImplementedError("no contact yet")
            return [z[0] + dt * z[3], z[1] + dt * z[4], z[2], z[3], z[4] - dt * 9.81, z[5]]
        """)
    with pytest.raises(SceneSkipped) as caught:
        run_user(load_simulator(later), scene)
    assert re.fullmatch(r"no contact yet \(raised at step \d+\)", caught.value.reason), caught.value.reason
    whole = module(tmp_path, """
        def simulate(scene):
            raise NotImplementedError
        """, name="whole")
    with pytest.raises(SceneSkipped) as caught:
        run_user(load_simulator(whole.replace(":step", ":simulate"), whole=True), scene)
    assert caught.value.reason == "the code raised NotImplementedError"


def test_a_skipped_scene_runs_nothing_else(tmp_path):
    """NotImplementedError at the first step: the scene is skipped after that one call (no
    contact variant, no second call to see whether the step keeps state, no diagnosis probe)."""
    from compare.run.scenario import run_scenario
    calls = tmp_path / "calls"
    spec = module(tmp_path, f"""
        def step(z, scene, dt):
            with open({str(calls)!r}, "a") as f:
                f.write(scene["name"] + "\\n")
            raise NotImplementedError("not this one")
        """)
    result = run_scenario(load(short_file(tmp_path, "box_slide")), load_simulator(spec))
    assert result.status == "skipped" and result.skipped == "not this one" and not result.checks
    assert calls.read_text() == "box_slide\n"


def test_the_contact_variant_a_step_does_not_do_is_not_judged_and_the_scene_still_is(tmp_path):
    """The contact check's variant (friction off, the linear law) raising NotImplementedError
    leaves that check not judged; the scene itself is judged, not skipped."""
    from compare.run.scenario import run_scenario
    spec = module(tmp_path, f"""
        import importlib.util
        spec = importlib.util.spec_from_file_location("box_only_class", {CLASS_SIM[:-5]!r})
        box = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(box)
        INTEGRATOR = box.INTEGRATOR
        def step(z, scene, dt):
            if "friction" not in scene["effects"]:
                raise NotImplementedError("this code needs friction")
            return box.step(z, scene, dt)
        """)
    result = run_scenario(load(short_file(tmp_path, "box_slide")), load_simulator(spec))
    assert result.skipped is None and result.status == "pass", (result.status, result.error)
    (contact,) = [c for c in result.checks if c.name == "contact"]
    assert contact.passed is None and "this code needs friction" in contact.reason, contact.reason


# --- run -------------------------------------------------------------------------------------

def test_run_lists_skipped_scenes_and_judges_the_others_under_the_identified_law(tmp_path, capsys):
    """A box-only class under `run --law identified`: the point scene skipped (its own law kept,
    its page and metrics.json saying so), the box scene identified and judged; exit 0."""
    out = tmp_path / "out"
    code, printed, err = run_cli(["run", short_file(tmp_path, "point_drop"), short_file(tmp_path, "box_slide"),
                                  "--sim", CLASS_SIM, "--law", "identified", "--out", str(out)], capsys)
    assert code == 0, (printed, err)
    assert f"point_drop           skipped  {CLASS_REASON}\n" in printed, printed
    assert re.search(r"^box_slide +pass ", printed, re.M), printed
    assert "Traceback" not in err and "error" not in err, err
    data = json.loads((out / "point_drop" / "metrics.json").read_text())
    assert data["status"] == "skipped" and data["skipped"] == CLASS_REASON and data["checks"] == [], data
    assert data["pass"] is None and data["law"]["from"] == "scene"
    assert f"**SKIPPED**: {CLASS_REASON}." in (out / "point_drop" / "index.md").read_text()
    assert json.loads((out / "box_slide" / "metrics.json").read_text())["law"]["from"] == "identified"
    assert f"| **skipped**: {CLASS_REASON} |" in (out / "index.md").read_text()
    assert "[point_drop](point_drop/index.md)" in (out / "index.md").read_text()
    # before any scene ran, identify met the point scene and stopped the whole run (exit 2)


def test_the_identified_law_over_every_built_in_scene_keeps_the_skipped_ones_as_they_are():
    """`--law identified` over every built-in with box-only code: the box scenes under the law
    identify found (the scene's own, as the code follows it), the others as they are, with why."""
    from compare.run.law import under_law
    from compare.scenarios import load_all
    scenes = load_all([])
    skipped = {}
    judged = under_law(scenes, "identified", load_simulator(CLASS_SIM), skipped)
    assert [s.name for s in judged] == [s.name for s in scenes]
    boxes = {s.name for s in scenes if s.body.shape == "box"}
    assert boxes and set(skipped) == {s.name for s in scenes} - boxes, skipped
    assert skipped["t_shape_drop"] == "BoxWorld does boxes only, not a compound"
    for before, after in zip(scenes, judged):
        if before.name in boxes:
            assert after.law_from == "identified" and after.contact.damping_law == before.contact.damping_law
            assert after.contact.k == pytest.approx(before.contact.k, rel=1e-9)
        else:
            assert after is before


def test_a_run_where_every_scene_was_skipped_exits_1(tmp_path, capsys):
    out = tmp_path / "out"
    code, printed, err = run_cli(["run", short_file(tmp_path, "rolling_circle"), "--sim", SHAPES_SIM,
                                  "--out", str(out)], capsys)
    assert code == 1, (printed, err)
    assert "rolling_circle       skipped  a circle body, not in the module's SHAPES = ('box',)\n" in printed, printed
    assert json.loads((out / "rolling_circle" / "metrics.json").read_text())["status"] == "skipped"


def test_an_error_row_is_printed_once_with_its_scene(tmp_path, capsys):
    """Code that reads a box's size meets a point (KeyError, not NotImplementedError): its error
    row is printed once, with its scene, and its traceback after the scene's name."""
    out = tmp_path / "out"
    sizes = module(tmp_path, """
        def step(z, scene, dt):
            w, h = scene["body"]["size"]
            return z
        """)
    code, printed, err = run_cli(["run", short_file(tmp_path, "point_drop"), "--sim", sizes, "--out", str(out)], capsys)
    assert code == 1
    both = printed + err
    assert both.count("KeyError: 'size'") == 2, both   # the row, and the traceback's last line
    assert re.search(r"^point_drop +error: .* at step 1 .* raised KeyError: 'size'", printed, re.M), printed
    assert err.count("Traceback") == 1 and "point_drop: Traceback (your code" in err, err
    assert not re.search(r"^error: ", err, re.M), err


# --- validate, identify, scene, mjcf ---------------------------------------------------------

def test_validate_skips_the_scenes_the_code_does_not_do(tmp_path, capsys):
    point, box = short_file(tmp_path, "point_drop"), short_file(tmp_path, "box_slide")
    code, printed, _ = run_cli(["validate", CLASS_SIM, point, box], capsys)
    assert code == 0 and f"point_drop       skipped  {CLASS_REASON}\n" in printed, printed
    assert re.search(r"^box_slide +pass ", printed, re.M), printed
    code, printed, _ = run_cli(["validate", SHAPES_SIM, point], capsys)
    assert code == 1 and "every scene" in printed, printed


def test_validate_under_a_law_file_and_the_identified_law(tmp_path, capsys):
    """The outsider's own law (unclamped, smooth Coulomb): the scene's law fails it; under the law
    identify finds, or a file holding that law, it passes."""
    outsider = str(ROOT / "tests" / "outsiders" / "rk4_smooth_unclamped.py") + ":step"
    box = short_file(tmp_path, "box_slide", 0.02)
    law = tmp_path / "law.toml"
    law.write_text('[contact]\ndamping_law = "unclamped"\nc = 15.0\nfriction_law = "smooth_coulomb"\nalpha = 50.0\n')
    code, printed, _ = run_cli(["validate", outsider, box], capsys)
    assert code == 1 and re.search(r"^box_slide +FAIL ", printed, re.M), printed
    for given in ("identified", str(law)):
        code, printed, _ = run_cli(["validate", outsider, box, "--law", given], capsys)
        assert code == 0 and re.search(r"^box_slide +pass .* pass ", printed, re.M), (given, printed)


def test_identify_over_every_scene_skips_those_the_code_does_not_do(capsys):
    scenes = ["box_drop", "box_slide", "point_drop", "rolling_circle", "t_shape_drop"]
    code, printed, err = run_cli(["identify", CLASS_SIM, *scenes, "--json"], capsys)
    assert code == 0, err
    results = {r["scene"]: r for r in map(json.loads, printed.splitlines())}
    assert list(results) == scenes
    assert results["t_shape_drop"] == {"scene": "t_shape_drop", "skipped": "BoxWorld does boxes only, not a compound"}
    assert results["box_slide"]["normal"]["law"] == "compression" and results["box_drop"]["normal"]["law"] == "linear"
    # explicit Euler where the scenes ask semi-implicit: 1 for that, the skipped scenes fail nothing
    code, printed, err = run_cli(["identify", SHAPES_SIM, *scenes, "--json"], capsys)
    results = {r["scene"]: r for r in map(json.loads, printed.splitlines())}
    assert code == 1 and results["point_drop"]["skipped"] == "a point body, not in the module's SHAPES = ('box',)"
    for name in ("box_drop", "box_slide"):
        assert results[name]["integrator"]["name"] == "explicit_euler"
        assert {k for k, v in results[name]["matches_scene"].items() if v is False} == {"integrator"}, results[name]
    code, printed, _ = run_cli(["identify", CLASS_SIM, "point_drop", "box_slide"], capsys)
    assert code == 0 and f"point_drop  skipped  {CLASS_REASON}" in printed, printed
    code, printed, _ = run_cli(["identify", CLASS_SIM, "point_drop"], capsys)
    assert code == 1, printed   # nothing identified is not a pass


def test_identify_names_the_scene_where_a_step_fails(tmp_path, capsys):
    sizes = module(tmp_path, "def step(z, scene, dt):\n    w, h = scene['body']['size']\n    return z\n")
    code, printed, err = run_cli(["identify", sizes, "box_slide", "point_drop"], capsys)
    assert code == 2 and err.startswith("error: point_drop: ") and "KeyError: 'size'" in err, err


def test_scene_json_under_a_law_file_and_the_identified_law(tmp_path, capsys):
    law = tmp_path / "law.toml"
    law.write_text('[contact]\ndamping_law = "hunt_crossley"\ndissipation = 0.5\n')
    code, printed, _ = run_cli(["scene", "box_slide", "--json", "--law", str(law)], capsys)
    contact = json.loads(printed)["contact"]
    assert code == 0 and contact["damping_law"] == "hunt_crossley" and contact["dissipation"] == 0.5, contact
    assert contact["k"] == load("box_slide").contact.k
    # the outsider's own law, which identify finds: unclamped with its c, smooth Coulomb with its eps
    outsider = str(ROOT / "tests" / "outsiders" / "rk4_smooth_unclamped.py") + ":step"
    code, printed, _ = run_cli(["scene", "box_slide", "--json", "--law", "identified", "--sim", outsider], capsys)
    contact = json.loads(printed)["contact"]
    assert code == 0 and contact["damping_law"] == "unclamped" and contact["friction_law"] == "smooth_coulomb"
    assert contact["c"] == pytest.approx(15.0, rel=1e-9) and contact["alpha"] == pytest.approx(1 / 0.02, rel=1e-9)
    for scene, argv, said in [("box_slide", ["--law", "identified"], "expected --sim"),
                              ("box_slide", ["--sim", outsider], "expected it with --law identified"),
                              ("point_drop", ["--law", "identified", "--sim", SHAPES_SIM], "skips point_drop (a point body")]:
        code, printed, err = run_cli(["scene", scene, "--json", *argv], capsys)
        assert code == 2 and said in err and not printed, err


def test_mjcf_under_a_law_file_names_what_mujoco_cannot_express(tmp_path, capsys):
    import mujoco
    law = tmp_path / "law.toml"
    law.write_text('[contact]\ndamping_law = "hunt_crossley"\ndissipation = 0.5\nfriction_law = "sign"\n')
    code, own, _ = run_cli(["mjcf", "box_slide"], capsys)
    code, xml, _ = run_cli(["mjcf", "box_slide", "--law", str(law)], capsys)
    assert code == 0
    comments = re.findall(r"<!-- (.*?) -->", xml)
    assert any(c.startswith(f"contact law: the law of {law}, laid over the scene's [contact]: normal hunt_crossley")
               for c in comments), comments
    assert any(c.startswith("damping law: the law's 'hunt_crossley'") for c in comments), comments
    assert any(c.startswith("friction law: the law's 'sign'") for c in comments), comments
    # the nearest mapping: hunt_crossley's damping is no constant, so the twin's solref damping is 0
    assert re.search(r'solref="-\S+ -\S+"', own) and re.search(r'solref="-\S+ 0"', xml), xml
    model = mujoco.MjModel.from_xml_string(xml)   # the comments keep it a model MuJoCo loads
    assert model.npair == 4 and model.pair_solref[0][1] == 0.0
