"""identify on code that keeps state, and what its answer says (issue 32: items 1, 4, 8, 11).

A step that keeps state between calls answers designed probes from what the call before left:
no law is read from them (keeps_state), the step's own sequential run is read instead. An
effect not exercised, or a body no inertia reproduces, is null; a step computing in float32 is
named so and held to single precision; the words carry no number below round-off.
"""
from __future__ import annotations

import json
import textwrap

import numpy as np

from compare.cli import main
from compare.identification import identify_step
from compare.scenarios import load
from compare.usersim import load_simulator

from short_scene import short_scene

OUTSIDERS = "tests/outsiders"

# A seed-style linear spring-damper, semi-implicit Euler, whose damper reads the velocity the
# step returned last (a module-level memo) instead of the state's: the same law along its own
# run (where the state in is the state it returned), another one from any probe out of order.
MEMO_STEP = """
import math
INTEGRATOR = "semi_implicit_euler"
last = {}

def step(state, scene, dt):
    x, y, th, vx, vy, om = (float(v) for v in state)
    vy_seen = last.get("vy", vy)
    mp, ct = scene["mass_properties"], scene["contact"]
    m = mp["mass"]
    fy = -m * scene["g"]
    for px, py in mp["contact_points"]:
        d = -(y + py)
        if d > 0:
            fy += max(0.0, ct["k"] * d - ct["c"] * vy_seen)
    vy = vy + dt * fy / m
    last["vy"] = vy
    return [x + dt * vx, y + dt * vy, th, vx, vy, om]
"""


def _write(tmp_path, text, name="memo_sim.py"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


def test_a_step_that_keeps_state_gets_no_law_from_probes_and_is_read_from_its_run(tmp_path, capsys):
    """Before: the probes answered with the memo of the probe before and identify named a law
    from them. Now: keeps_state, and the run (where the memo is the state's own velocity) gives
    the scene's linear law, k and c (the law written above, not read from the harness)."""
    sim = _write(tmp_path, MEMO_STEP)
    scene = short_scene(tmp_path, "point_drop", 0.4)
    assert main(["identify", f"{sim}:step", str(scene), "--json"]) in (0, 1)
    out = json.loads(capsys.readouterr().out)
    assert out["keeps_state"] is True and out["from"] == "run"
    assert "keeps state between calls" in out["keeps_state_why"]
    assert out["normal"]["law"] == "linear"
    assert abs(out["normal"]["k"] - 1e4) <= 1e-6 * 1e4 and abs(out["normal"]["c"] - 60.0) <= 1e-5 * 60.0
    from compare.identification.report import text
    shown = text(out)   # the table of the same object
    assert "keeps state between calls" in shown and "steps of its sequential run" in shown


def test_a_pure_step_says_keeps_state_false(capsys):
    assert main(["identify", "examples/seed_sim.py:step", "point_drop", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["keeps_state"] is False and out["from"] == "step"


def test_the_outsider_with_a_stick_slip_anchor_keeps_state(tmp_path):
    """tests/outsiders/c_port_anchor.py: a backward-differenced damper and a stick/slip anchor.
    Before: designed probes gave contact points 4.5 um off the scene's as a finding. Now no
    designed law; from its run, friction (an anchor spring, no family) is null."""
    sim = load_simulator(f"{OUTSIDERS}/c_port_anchor.py:step")
    scene = load(str(short_scene(tmp_path, "box_slide", 0.2)))
    out = identify_step(sim, scene)
    assert out["keeps_state"] is True and out["from"] == "run"
    assert out["friction"]["law"] is None and "closest" in out["friction"]


# -- item 4: null means null ---------------------------------------------------------------------

def _sequential(step, scene, steps=None):
    """The states of step's run from the scene's start (what --whole hands identify)."""
    from compare.usersim import scene_dict
    from custom_sim.model import initial_state
    sd = scene_dict(scene)
    z = initial_state(scene)
    out = [z]
    for _ in range(steps or scene.steps):
        z = np.asarray(step(z.copy(), sd, scene.dt), dtype=float)
        out.append(z)
    return np.array(out)


def _body_line(result):
    from compare.identification.report import text
    return next(line for line in text(result).splitlines() if line.lstrip().startswith("body"))


def test_an_effect_the_run_never_exercises_has_law_null(tmp_path):
    """point_drop dropped straight down: friction is listed, no step slides. Before: the law
    fitted to zero force stayed ("tanh" with the scene's mu, "(not exercised ...)" after it)."""
    from compare.identification import identify_run
    from compare.identification.report import text
    from test_identify import custom_step
    path = short_scene(tmp_path, "point_drop", 0.3)
    path.write_text(path.read_text().replace("velocity = [1.0, 0.0]", "velocity = [0.0, 0.0]"))
    scene = load(str(path))
    out = identify_run(_sequential(custom_step(scene), scene), scene)
    f = out["friction"]
    assert f["exercised"] is False and f["law"] is None and f.get("mu") is None and "closest" not in f
    line = next(line for line in text(out).splitlines() if line.lstrip().startswith("friction"))
    assert line.split() == ["friction", "not", "exercised:", "no", "step", "of", "the", "run", "has", "a",
                            "friction", "force", "above", "its", "round-off"], line
    assert out["matches_scene"]["friction"] is None


def test_no_inertia_reproduces_the_torque_so_the_json_has_none(tmp_path):
    """Designed probes, the friction's arm with the wrong sign: the text said "none reproduces"
    while body.inertia held a number. Now null, the number under body.closest."""
    from test_identify import Direct, numpy_step
    out = identify_step(Direct(numpy_step("semi_implicit_euler", normal="linear", friction_arm=1.0)), load("box_drop"))
    b = out["body"]
    assert b["inertia"] is None and b["closest"]["inertia"] is not None and b["closest"]["relative"] > 1
    line = _body_line(out)
    assert "none reproduces the torque" in line and "negative" not in line, line


def _two_speeds(fn, v):
    """mu 0.3 + 0.2 s/m |v|: a coefficient that grows with the slip, of no family."""
    return -(0.3 + 0.2 * abs(v)) * fn * float(np.tanh(100.0 * v))


def test_an_inertia_resting_on_a_friction_of_no_family_is_no_finding(tmp_path):
    """A whole run of box_slide whose friction fits no family: the torque carries r_y Ft, so the
    inertia fitted beside the closest friction is none. Before: printed as a finding."""
    from compare.identification import identify_run
    from test_identify import numpy_step
    scene = load(str(short_scene(tmp_path, "box_slide", 0.25)))
    out = identify_run(_sequential(numpy_step("semi_implicit_euler", normal="linear", traction=_two_speeds), scene),
                       scene)
    assert out["friction"]["law"] is None
    b = out["body"]
    assert b["inertia"] is None and "inertia" in b["closest"]
    line = _body_line(out)
    assert "inertia not identified (the friction fits no family" in line and "negative" not in line, line


# -- item 11: words -------------------------------------------------------------------------------

def test_identified_parameters_are_rounded_to_what_the_probes_resolve(capsys):
    """Hunt-Crossley k 1e4, dissipation 2 s/m, tanh mu 0.5, alpha 100 s/m (examples/, written
    apart from the harness). Before: mu 0.49999999999999906, k 9999.999999999985 in the JSON."""
    assert main(["identify", "examples/hunt_crossley_sim.py:step", "box_drop", "--json"]) == 1   # not the scene's law
    out = json.loads(capsys.readouterr().out)
    assert (out["normal"]["k"], out["normal"]["dissipation"]) == (1e4, 2.0)
    assert (out["friction"]["mu"], out["friction"]["alpha"]) == (0.5, 100.0)
    assert out["gravity"]["g"] == 9.81
    assert main(["identify", "examples/hunt_crossley_sim.py:step", "box_drop"]) == 1
    normal = next(line for line in capsys.readouterr().out.splitlines() if line.lstrip().startswith("normal"))
    assert "hunt_crossley (k 10000 N/m, dissipation 2 s/m)" in normal and " c " not in normal, normal


def test_no_number_below_round_off_no_inf_no_minus_zero():
    """The table from a result holding what the words must not show: a residual of 6e-123 N
    within round-off, an infinite one, a contact point at -0 and one at 1e-17 m (below the
    points' own resolution)."""
    from compare.identification.report import text
    from test_identify import Direct, custom_step
    scene = load("box_drop")
    out = identify_step(Direct(custom_step(scene)), scene)
    out["normal"].update(residual=6.12e-123, relative=1.4e-111)
    out["friction"] = {**out["friction"], "law": None, "closest": {"law": "tanh", "mu": 0.5, "alpha": 100.0,
                                                                   "residual": float("inf"), "relative": float("inf")}}
    out["body"].update(contact_points=[[-0.0, -0.05], [1e-17, 0.05]], points_residual=5.6e-17)
    shown = text(out)
    assert "e-123" not in shown and "inf" not in shown and "-0," not in shown and "e-17," not in shown, shown
    assert "residual 1.4e-111 of round-off" in shown and "residual not finite" in shown
    assert "(0, -0.05); (0, 0.05)" in shown


RAISES_ON_BOXES = """
import sys
sys.path.insert(0, "examples")
from seed_sim import step as seed

def step(state, scene, dt):
    if scene["body"]["shape"] == "box":
        raise ValueError("boxes are not supported yet")
    return seed(state, scene, dt)
"""


def test_a_scene_whose_step_raises_is_one_line_with_its_scene_and_the_others_go_on(tmp_path, capsys):
    """Before: the first fault ended identify (the scenes after it never identified), the line
    named no scene and ended "(expected a state [x, y, theta, vx, vy, omega])"."""
    sim = _write(tmp_path, RAISES_ON_BOXES, "boxes.py")
    assert main(["identify", f"{sim}:step", "box_drop", "point_drop"]) == 2
    cap = capsys.readouterr()
    err = cap.err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error: box_drop: ") and "ValueError: boxes are not supported" in err[0]
    assert "expected" not in err[0]
    assert cap.out.startswith("point_drop  (")
    assert main(["identify", f"{sim}:step", "box_drop", "point_drop", "--json"]) == 2
    rows = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert rows[0]["scene"] == "box_drop" and "boxes are not supported" in rows[0]["error"]
    assert rows[1]["scene"] == "point_drop" and rows[1]["normal"]["law"] == "compression"


# -- item 8: float32 arithmetic -------------------------------------------------------------------

def test_a_float32_step_is_named_and_held_to_single_precision(capsys):
    """tests/outsiders/f32_kernel.py computes the scene's law in float32 and returns float64.
    Before: "gravity not a constant g (closest 9.810000191 m/s^2 ...)", every effect null. Now:
    float32 named, the scene's law found (its parameters to the digits float32 resolves)."""
    assert main(["identify", f"{OUTSIDERS}/f32_kernel.py:step", "box_drop", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["precision"] == "float32" and out["gravity"]["g"] == 9.81
    assert (out["normal"]["law"], out["normal"]["k"], out["normal"]["c"]) == ("linear", 1e4, 20.0)
    assert (out["friction"]["law"], out["friction"]["mu"], out["friction"]["alpha"]) == ("tanh", 0.5, 100.0)
    # m (w^2 + h^2) / 12 of the 0.2 x 0.1 m, 2 kg box, to what the torque probes resolve in
    # float32: a change of 4e-5 of it moves a probe's torque by its round-off, and the JSON is
    # rounded there (0.008333)
    assert abs(out["body"]["inertia"] - 2.0 * (0.2 ** 2 + 0.1 ** 2) / 12.0) <= 1e-4 * out["body"]["inertia"]
    assert all(v is not False for v in out["matches_scene"].values())
    assert main(["identify", f"{OUTSIDERS}/f32_kernel.py:step", "box_drop"]) == 0
    assert "float32 arithmetic" in capsys.readouterr().out.splitlines()[0]


def test_a_float64_step_is_not_float32(capsys):
    assert main(["identify", "examples/seed_sim.py:step", "point_drop", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["precision"] == "float64"


def test_a_float32_whole_run_is_held_to_single_precision(tmp_path, capsys):
    scene = short_scene(tmp_path, "point_drop", 0.4)
    assert main(["identify", f"{OUTSIDERS}/f32_kernel.py:simulate", str(scene), "--whole", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["precision"] == "float32" and out["normal"]["law"] == "compression"
    assert out["friction"]["law"] == "tanh"
