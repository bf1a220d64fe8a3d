"""identify on code written without the harness in mind: the integrator as measurements (the
position-update share beta and whether the force depends on dt), contact where the forces show
it (an onset above the contact points), probes pressed to where the law is of the order of m g,
and a fit that saw only round-off is no finding."""
from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import numpy as np

from compare.identification import identify_step
from compare.identification.report import text
from compare.scenarios import load

OUTSIDERS = Path(__file__).resolve().parents[2] / "outsiders"


class Direct:
    """A plain function as the simulator under test (what StepFunction gives identify)."""

    def __init__(self, fn, spec="test_identify_onset.py:step"):
        self.function, self.spec = fn, spec

    def fresh(self):
        pass


def outsider(name: str):
    spec = importlib.util.spec_from_file_location(f"outsider_{name}", OUTSIDERS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def line(out: dict, head: str) -> str:
    return next(x for x in text(out).splitlines() if x.lstrip().startswith(head))


# -- the integrator in measurements -----------------------------------------------------------

def test_substeps_are_measured_as_their_position_share_not_named_a_method():
    """8 substeps moving positions first, the force held over the frame: beta = (8 - 1) / 16
    exactly (docs/identify.md: (N - 1)/(2N)), the force read at the start of the step (no dependence on dt). No
    method has that beta: none is named, and the line says what beta is."""
    module = outsider("substep_margin")
    out = identify_step(Direct(module.step), load("point_drop"))
    it = out["integrator"]
    want = (module.SUBSTEPS - 1) / (2 * module.SUBSTEPS)
    assert it["name"] is None
    assert abs(it["beta"] - want) <= 1e-6, it["beta"]
    assert it["depends_on_dt"] is False
    assert "none: beta = 0.4375 (between explicit and semi-implicit Euler" in line(out, "integrator")
    assert it["closest"]["name"] == "rk4"   # the nearest beta (1/2), no method matching it
    assert it["closest"]["residual"] == min(it["position_tests"].values())


def _baumgarte_step(state, scene, dt):
    """Explicit Euler with a game engine's position correction: the normal force carries a bias
    that removes a fifth of the depth per step, m 0.2 d / dt^2 (a force that depends on dt)."""
    x, y, th, vx, vy, om = (float(v) for v in state)
    mp, ct = scene["mass_properties"], scene["contact"]
    m = mp["mass"]
    d = -(y + mp["contact_points"][0][1])
    fn = 0.0
    if d > 0.0:
        fn = max(0.0, ct["k"] * d - ct["c"] * vy) + m * 0.2 * d / (dt * dt)
    fx = -ct["mu"] * fn * math.tanh(ct["alpha"] * vx)
    ay = fn / m - scene["g"]
    return [x + dt * vx, y + dt * vy, th, vx + dt * fx / m, vy + dt * ay, om]


def test_a_force_that_depends_on_dt_is_said_so_beside_its_beta():
    out = identify_step(Direct(_baumgarte_step), load("point_drop"))
    it = out["integrator"]
    assert it["name"] is None and abs(it["beta"]) <= 1e-6
    assert it["depends_on_dt"] is True
    # its beta: the one test every method has; rk4's largest test (flight only) is smaller than
    # explicit Euler's (which has the dt test too), but its position update is further off
    assert it["closest"]["name"] == "explicit_euler"
    assert it["closest"]["residual"] == min(it["position_tests"].values()) <= 1.0
    words = line(out, "integrator")
    assert "none: beta = 0 (explicit_euler's), and the force depends on the step size" in words, words
    assert "closest in beta explicit_euler" in words


def test_the_four_methods_are_still_named_with_their_measurements():
    from compare.usersim import load_simulator
    sim = load_simulator("examples/seed_sim.py:step")
    for name, beta in (("box_drop", 1.0), ("spinning_box", 0.5)):
        it = identify_step(sim, load(name))["integrator"]
        assert it["name"] == load(name).integrator and it["depends_on_dt"] is False
        assert abs(it["beta"] - beta) <= 1e-6


# -- contact where the forces show it ----------------------------------------------------------

def test_a_world_frame_margin_is_an_onset_not_points_scaled():
    """Contacts begin SKIN above each point in the world frame: the box's corners are found where
    the scene has them, the margin once as the onset (m above the ground), and the law read from
    there is the scene's (k, c), its onset excepted."""
    module = outsider("substep_margin")
    scene = load("box_drop")
    out = identify_step(Direct(module.step), scene)
    n = out["normal"]
    assert abs(n["onset"] - module.SKIN) <= 1e-12, n.get("onset")
    assert n["law"] == "linear" and abs(n["k"] - scene.contact.k) <= 1e-6 * scene.contact.k
    for p, want in zip(out["body"]["contact_points"], [(-0.1, -0.05), (0.1, -0.05), (0.1, 0.05), (-0.1, 0.05)]):
        assert np.allclose(p, want, rtol=0.0, atol=1e-14), p
    assert out["matches_scene"]["normal"] is False
    assert "the force begins 0.003 m above the ground" in line(out, "normal")


# -- probes where the law carries the body -----------------------------------------------------

def test_a_far_reaching_field_is_probed_where_it_carries_the_weight():
    """The field A exp(-z / L) is first seen ~0.17 m up; pressed only to the scene's resting
    depth below that, the probes would see ~1e-12 N and every family would 'fit'. The probes go
    down to where it carries m g: no family is that exponential, and the friction on that load is
    read as the code's (smooth Coulomb, mu from the scene, alpha = 1 / V_SMOOTH)."""
    module = outsider("exp_field")
    scene = load("point_drop")
    out = identify_step(Direct(module.step), scene)
    n, f = out["normal"], out["friction"]
    z_first = n["onset"] + scene.body.contact_height   # the field's height where the force is first seen
    assert 0.1 < n["onset"] and z_first > 0.1
    assert n["law"] is None and n["closest"]["relative"] > 1e6
    assert f["law"] == "smooth_coulomb" and abs(f["mu"] - scene.contact.mu) <= 1e-9
    assert abs(f["alpha"] - 1.0 / module.V_SMOOTH) <= 1e-6 / module.V_SMOOTH


def test_a_fit_to_round_off_is_no_finding():
    """A box on the same field: the probes may press a corner only an eighth of the gap to the next
    one, where the field is still ~1e-11 N. Nothing is named from that: the law could not be read,
    with the largest force seen."""
    out = identify_step(Direct(outsider("exp_field").step), load("box_drop"))
    for effect in ("normal", "friction"):
        e = out[effect]
        assert e["law"] is None and e["read"] is False and e["largest_force"] < 1e-6, e
        assert "the law could not be read" in line(out, effect)
    assert "none (mu 0)" not in text(out) and "hunt_crossley" not in line(out, "normal")


# -- a run: flight and touching from the forces seen -------------------------------------------

def _run(module, scene):
    from compare.usersim import scene_dict
    sd = scene_dict(scene)
    z = np.array(sd["state0"], dtype=float)
    out = [z]
    for _ in range(scene.steps):
        z = np.array(module.step(z, sd, scene.dt), dtype=float)
        out.append(z)
    return np.array(out)


def test_a_run_that_lands_on_a_field_reads_g_from_its_fall_and_no_scene_law():
    """The point falls 0.3 s through air (g exactly), then lands on the field: flight is where
    the velocity changes by g h alone, not where the scene's point is above y = 0, and the
    steps on the field are contact steps whatever the geometry says (no scene law echoed)."""
    import dataclasses

    from compare.identification import identify_run
    scene = dataclasses.replace(load("point_drop"), duration=0.6)
    out = identify_run(_run(outsider("exp_field"), scene), scene)
    assert abs(out["gravity"]["g"] - scene.g) <= 1e-9 * scene.g
    n = out["normal"]
    assert n["exercised"] and n["law"] is None and n["closest"]["relative"] > 1e6
    assert n["onset_seen"] > 0.01   # the field acts centimetres above the point
    assert out["friction"]["law"] != "none"


def test_a_run_floating_on_a_field_throughout_has_no_gravity_and_no_echo():
    """Started inside the field, the point never flies: gravity is not read (never 'not a
    constant g'), and the normal force is no family's (never the scene's k and c with 'residual 0')."""
    import dataclasses

    from compare.identification import identify_run
    base = load("point_drop")
    scene = dataclasses.replace(base, duration=0.3, initial=dataclasses.replace(base.initial, position=(0.0, 0.08)))
    out = identify_run(_run(outsider("exp_field"), scene), scene)
    assert out["gravity"]["exercised"] is False
    assert out["normal"]["law"] is None and out["normal"]["exercised"]
    assert "a force acts up to" in line(out, "normal")


def test_a_run_resting_on_a_margin_has_a_constant_g_or_none():
    """A box set down at the scene's resting height on a contact margin 3 mm above the ground:
    pressed 3 mm too deep, it hops and lands on the margin. Its hops give g exactly (where the
    scene's points are above y = 0 it rests on the margin: no flight there), and the margin is
    fitted beside the spring: the scene's k and c, 3 mm up."""
    import dataclasses

    from compare.identification import identify_run
    module = outsider("substep_margin")
    scene = dataclasses.replace(load("box_slide"), duration=0.3)
    out = identify_run(_run(module, scene), scene)
    assert abs(out["gravity"]["g"] - scene.g) <= 1e-9 * scene.g
    n = out["normal"]
    assert n["law"] == "linear" and abs(n["onset"] - module.SKIN) <= 1e-9   # max(0, k d - c v_n) from the margin
    assert abs(n["k"] - scene.contact.k) <= 1e-6 * scene.contact.k


def test_an_onset_is_no_law_to_run_under():
    """No [contact] table holds an onset: `--law identified` says so instead of running a law
    that puts the force 3 mm lower than the code does."""
    import pytest

    from compare.identification import NotIdentified, identified_contact
    scene = load("point_drop")
    out = identify_step(Direct(outsider("substep_margin").step), scene)
    with pytest.raises(NotIdentified, match="the force begins 0.003 m above the ground"):
        identified_contact(scene, out)
