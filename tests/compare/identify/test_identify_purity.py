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
import pytest

from compare.cli import main
from compare.identify import identify_step
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
    assert main(["identify", f"{sim}:step", str(scene)]) in (0, 1)
    text = capsys.readouterr().out
    assert "keeps state between calls" in text and "steps of its sequential run" in text


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
