"""`python -m compare identify`: which contact law a step function (or a run) implements.

custom_sim's own step on every built-in body recovers the scene's law; small numpy steps of the
other families, under each integrator, recover theirs; a law of no family (a cubic spring, a
friction coefficient that changes at 1 m/s) is named by none, with the closest given; the buggy
example's wrong effects are the ones that do not match; bad input is one line, exit 2.
"""
from __future__ import annotations

import dataclasses
import json
import math
import textwrap

import numpy as np
import pytest

from compare.cli import main
from compare.identification import identified_contact, identify_run, identify_step
from compare.scenarios import builtin_names, load
from compare.usersim import load_simulator, scene_dict
from custom_sim import Stepper, mass_properties, simulate

# A part in 1e9: every parameter is recovered far closer (round-off is 1e-13 to 1e-15 of it);
# this only keeps the comparison clear of the last digits. A physical mistake (a wrong mass, a
# damper left out) moves a parameter by 1e-3 or more.
PARAMETER_RTOL = 1e-9
# The contact points are found where contact begins, to a few ulps of the body's size (0.1 m).
POINT_ATOL = 1e-14

INTEGRATORS = ("explicit_euler", "semi_implicit_euler", "implicit_euler", "rk4")


class Direct:
    """A plain function as the simulator under test (what StepFunction gives identify)."""

    def __init__(self, fn, spec="test_identify.py:step"):
        self.function, self.spec = fn, spec

    def fresh(self):
        pass


def custom_step(scene):
    """custom_sim's step from any state, with the dt it is called with."""
    steppers = {}

    def step(state, scene_d, dt):
        s = steppers.setdefault(dt, Stepper(dataclasses.replace(scene, dt=dt), watch_chatter=False))
        s.reset(state)
        return s.advance(1).copy()
    return step


PHI = {"tanh": math.tanh, "ramp": lambda x: min(1.0, max(-1.0, x)),
       "smooth_coulomb": lambda x: x / math.sqrt(x * x + 1.0)}


def numpy_step(integrator, normal="compression", friction="tanh", rolling="tanh", k=1e4, c=20.0,
               dissipation=0.0, mu=0.5, alpha=100.0, mu_roll=0.002, sharpness=100.0, spring=None, traction=None,
               torque=1.0, friction_arm=-1.0):
    """A seed-style step in plain numpy with the law given here (not the scene's); torque and
    friction_arm put in a mistake of the torque (the seed's: 1 and -1, tau = r x F)."""
    def normal_force(d, vn):
        if spring is not None:
            return spring(d, vn)
        return {"compression": lambda: k * d + c * max(0.0, -vn), "linear": lambda: max(0.0, k * d - c * vn),
                "unclamped": lambda: k * d - c * vn,
                "hunt_crossley": lambda: max(0.0, k * d * (1.0 - dissipation * vn))}[normal]()

    def friction_force(fn, v):
        if traction is not None:
            return traction(fn, v)
        if friction == "sign":
            return -mu * fn * float(np.sign(v))
        return 0.0 if friction == "none" else -mu * fn * PHI[friction](alpha * v)

    def accel(z, scene):
        x, y, th, vx, vy, om = (float(v) for v in z)
        mp, on = scene["mass_properties"], scene["effects"]
        m, inertia = mp["mass"], mp["inertia"]
        fx, fy, tau = 0.0, -m * scene["g"] if "gravity" in on else 0.0, 0.0
        cs, sn = (math.cos(th), math.sin(th)) if mp["points_rotate"] else (1.0, 0.0)
        for lx, ly in mp["contact_points"]:
            rx, ry = cs * lx - sn * ly, sn * lx + cs * ly
            d = -(y + ry)
            if d <= 0.0:
                continue
            fn = normal_force(d, vy + om * rx)
            ft = friction_force(fn, vx - om * ry) if "friction" in on else 0.0
            fx, fy, tau = fx + ft, fy + fn, tau + torque * (rx * fn + friction_arm * ry * ft)
            if "rolling_friction" in on and rolling != "none":
                tau -= mu_roll * fn * (math.tanh(sharpness * om) if rolling == "tanh" else float(np.sign(om)))
        return np.array([fx / m, fy / m, tau / inertia if mp["rotates"] else 0.0])

    def f(z, scene):
        return np.concatenate([z[3:], accel(z, scene)])

    def step(state, scene, dt):
        z = np.array(state, dtype=float)
        if integrator == "explicit_euler":
            return z + dt * f(z, scene)
        if integrator == "semi_implicit_euler":
            v = z[3:] + dt * accel(z, scene)
            return np.concatenate([z[:3] + dt * v, v])
        if integrator == "rk4":
            k1 = f(z, scene)
            k2 = f(z + 0.5 * dt * k1, scene)
            k3 = f(z + 0.5 * dt * k2, scene)
            k4 = f(z + dt * k3, scene)
            return z + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
        q0, v0 = z[:3], z[3:]   # implicit Euler: Newton on G(v) = v - v0 - h a(q0 + h v, v)

        def G(v):
            return v - v0 - dt * accel(np.concatenate([q0 + dt * v, v]), scene)
        v = v0 + dt * accel(z, scene)
        for _ in range(60):
            J = np.empty((3, 3))
            for j in range(3):
                e = np.zeros(3)
                e[j] = 1e-7 * (1.0 + abs(v[j]))
                J[:, j] = (G(v + e) - G(v - e)) / (2.0 * e[j])
            dv = -np.linalg.solve(J if abs(np.linalg.det(J)) > 1e-300 else np.eye(3), G(v))
            v = v + dv
            if np.max(np.abs(dv)) <= 1e-15 * (1.0 + np.max(np.abs(v))):
                break
        return np.concatenate([q0 + dt * v, v])
    return step


def close(a, b, rtol=PARAMETER_RTOL):
    return a is not None and abs(a - b) <= rtol * max(abs(b), 1.0 if b == 0.0 else abs(b))


# -- custom_sim's own step, every built-in body, the seed's law --------------------------------

@pytest.mark.parametrize("name", builtin_names())
def test_custom_sim_recovers_each_scene_law(name):
    scene = load(name)
    out = identify_step(Direct(custom_step(scene)), scene)
    assert out["integrator"]["name"] == scene.integrator
    assert all(v is not False for v in out["matches_scene"].values()), out["matches_scene"]
    assert close(out["gravity"]["g"], scene.g)
    ct = scene.contact
    n = out["normal"]
    assert n["law"] == ct.damping_law or ct.damping_law in n.get("also_fit", [])
    assert close(n["k"], ct.k)
    if ct.c > 0.0:
        assert n["law"] == ct.damping_law and close(n["c"], ct.c)
    else:   # no damper: every damping law is the same spring, and each is said to fit
        assert abs(n["c"]) < 1e-9 and set(n["also_fit"]) | {n["law"]} == {"compression", "linear", "unclamped",
                                                                          "hunt_crossley"}
    if scene.has("friction"):
        f = out["friction"]
        assert (f["law"], f.get("also_fit")) == (ct.friction_law, None)
        assert close(f["mu"], ct.mu) and close(f["alpha"], ct.alpha)
    else:
        assert out["friction"]["exercised"] is False
    if scene.has("rolling_friction"):
        r = out["rolling"]
        assert r["law"] == ct.roll_law and close(r["mu_roll"], ct.mu_roll) and close(r["roll_sharpness"], 100.0)
    else:
        assert out["rolling"]["exercised"] is False
    body, props = out["body"], mass_properties(scene.body)
    assert body["mass"] == props.mass
    assert close(body["inertia"], props.inertia) or (props.inertia == 0.0 and body["inertia"] == 0.0)
    found = [p for p in body["contact_points"] if p is not None]
    assert found, "no contact point found"
    for p, want in zip(body["contact_points"], props.points):
        if p is not None:
            assert np.allclose(p, want, rtol=0.0, atol=POINT_ATOL), (p, want)
    assert body["points_match"]


# -- other families, each under each integrator (plain numpy steps) ----------------------------

FAMILY_CASES = [
    ("box_drop", "normal", dict(normal="hunt_crossley", dissipation=0.5), {"k": 1e4, "dissipation": 0.5}),
    ("box_drop", "normal", dict(normal="unclamped", c=30.0), {"k": 1e4, "c": 30.0}),
    ("point_drop", "normal", dict(normal="linear", c=40.0), {"k": 1e4, "c": 40.0}),
    ("box_drop", "friction", dict(friction="ramp", alpha=80.0), {"mu": 0.5, "alpha": 80.0}),
    ("point_drop", "friction", dict(friction="smooth_coulomb", mu=0.4, alpha=150.0), {"mu": 0.4, "alpha": 150.0}),
    ("point_drop", "friction", dict(friction="sign", mu=0.4), {"mu": 0.4}),
    ("rolling_circle", "rolling", dict(rolling="sign", mu_roll=0.003), {"mu_roll": 0.003}),
]


@pytest.mark.parametrize("integrator", INTEGRATORS)
@pytest.mark.parametrize("name,effect,law,want", FAMILY_CASES, ids=[f"{c[0]}-{c[2][c[1]]}" for c in FAMILY_CASES])
def test_each_family_under_each_integrator(integrator, name, effect, law, want):
    out = identify_step(Direct(numpy_step(integrator, **law)), load(name))
    assert out["integrator"]["name"] == integrator
    entry = out[effect]
    assert entry["law"] == law[effect], entry
    for key, value in want.items():
        assert close(entry[key], value), (key, entry[key], value)
    assert out["matches_scene"][effect] is False   # not the scene's law
    # the other effects: the step's own (compression, tanh friction, tanh rolling), where exercised
    for other, default in (("normal", "compression"), ("friction", "tanh"), ("rolling", "tanh")):
        if other != effect and out[other]["exercised"]:
            assert out[other]["law"] == default or default in out[other].get("also_fit", []), (other, out[other])


def test_no_friction_and_no_rolling_are_named_none():
    out = identify_step(Direct(numpy_step("semi_implicit_euler", friction="none", rolling="none")),
                        load("rolling_circle"))
    assert out["friction"]["law"] == "none" and out["rolling"]["law"] == "none"
    assert out["matches_scene"]["friction"] is False and out["matches_scene"]["rolling"] is False


# -- laws of no family: null, with the closest --------------------------------------------------

def _cubic(d, vn):
    return 1e4 * d + 2e6 * d ** 3 + 20.0 * max(0.0, -vn)


def _two_coefficients(fn, v):
    return -(0.5 if abs(v) < 1.0 else 0.3) * fn * math.tanh(100.0 * v)


@pytest.mark.parametrize("integrator", ("semi_implicit_euler", "implicit_euler"))
@pytest.mark.parametrize("effect,law", [("normal", dict(spring=_cubic)),
                                        ("friction", dict(traction=_two_coefficients))])
def test_a_law_of_no_family_is_null_with_the_closest(integrator, effect, law):
    out = identify_step(Direct(numpy_step(integrator, **law)), load("box_drop"))
    entry = out[effect]
    assert entry["exercised"] and entry["law"] is None
    assert entry["closest"]["law"] in entry["families"] and entry["closest"]["relative"] > 1.0
    assert out["matches_scene"][effect] is False
    assert out["integrator"]["name"] == integrator   # told apart without the law


# -- the buggy example: its wrong effects are the ones that do not match ----------------------

def test_buggy_example_effects_it_gets_wrong():
    sim = load_simulator("examples/buggy_sim.py:step")
    out = identify_step(sim, load("box_drop"))
    # friction on the centre of mass velocity: no family of the slip reproduces it
    assert out["friction"]["law"] is None and out["matches_scene"]["friction"] is False
    # the box inertia about a corner: m (w^2 + h^2) / 3, four times the scene's
    assert close(out["body"]["inertia"], 2.0 * (0.2 ** 2 + 0.1 ** 2) / 3.0)
    assert out["matches_scene"]["body"] is False
    assert {k for k, v in out["matches_scene"].items() if v is True} == {"integrator", "gravity", "normal"}
    # a point mass has neither mistake: everything matches
    point = identify_step(sim, load("point_drop"))
    assert all(v is not False for v in point["matches_scene"].values())


@pytest.mark.parametrize("mistake, words", [
    ({"friction_arm": 1.0}, "none reproduces the torque (the forces found times their arms, r x F, for any inertia); closest"),
    ({"torque": -1.0}, "(negative: the torque turns the body the wrong way)"),
])
def test_a_torque_that_is_not_r_cross_f_is_not_given_an_inertia(mistake, words):
    """The friction's arm with the wrong sign: no inertia reproduces the torque, and the inertia
    fitted is only the closest. Every torque with the wrong sign: an inertia reproduces it, the
    scene's with its sign turned, which the line says is no body's."""
    from compare.identification.report import text
    out = identify_step(Direct(numpy_step("semi_implicit_euler", normal="linear", **mistake)), load("box_drop"))
    assert out["matches_scene"]["body"] is False
    line = next(line for line in text(out).splitlines() if line.lstrip().startswith("body"))
    assert words in line, line
    if "torque" in mistake:
        assert close(out["body"]["inertia"], -mass_properties(load("box_drop").body).inertia)


def test_a_point_mass_that_turns_is_not_the_scenes_body():
    """A point mass has no inertia to fit: the step must leave omega alone. One that spins it up
    (0.1 rad/s^2) is no body's, though the inertia compared (0) is the scene's."""
    from compare.identification.report import text
    scene = load("point_drop")
    seed = custom_step(scene)

    def spinning(state, scene_d, dt):
        z = np.array(seed(state, scene_d, dt))
        z[5] += 0.1 * dt
        return z
    out = identify_step(Direct(spinning), scene)
    assert out["matches_scene"]["body"] is False and out["body"]["rotates"] is False
    line = next(line for line in text(out).splitlines() if line.lstrip().startswith("body"))
    assert "the step turns the point mass" in line and "rad/s^2" in line and "N m" not in line, line
    assert identify_step(Direct(seed), scene)["matches_scene"]["body"] is True


# -- the command: table, JSON, exit status, bad input -------------------------------------------

def test_command_json_and_table(capsys):
    assert main(["identify", "examples/seed_sim.py:step", "box_drop", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["scene"] == "box_drop" and out["normal"]["law"] == "linear" and out["friction"]["law"] == "tanh"
    assert set(out["integrator"]) >= {"name", "residual"} and set(out["gravity"]) >= {"g", "residual"}
    assert set(out["body"]) >= {"mass", "inertia", "contact_points", "residual"}
    assert main(["identify", "examples/buggy_sim.py:step", "box_drop"]) == 1
    text = capsys.readouterr().out
    assert "friction    no family fits; closest" in text and "≠ scene" in text


@pytest.mark.parametrize("body,expect", [
    ("def step(state, scene, dt):\n    return 1 / 0\n", "raised ZeroDivisionError: division by zero"),
    ("def step(state, scene, dt):\n    return 0.3\n", "returned a float 0.3"),
    ("def step(state, scene, dt):\n    return [float('nan')] * 6\n", "returned a non-finite state"),
    ("def other(state, scene, dt):\n    return state\n", "has no function 'step'"),
])
def test_bad_input_is_one_line_exit_2(tmp_path, capsys, body, expect):
    path = tmp_path / "user_sim.py"
    path.write_text(body)
    assert main(["identify", f"{path}:step", "box_drop"]) == 2
    err = capsys.readouterr().err
    assert expect in err and "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert "step" in err


# -- the identified law as the scene's Contact ----------------------------------------------------

def test_identified_contact_replaces_the_scene_law():
    scene = load("box_drop")
    out = identify_step(Direct(numpy_step("semi_implicit_euler", normal="hunt_crossley", dissipation=0.5,
                                          friction="ramp", alpha=80.0)), scene)
    contact = identified_contact(scene, out)
    assert (contact.damping_law, contact.friction_law) == ("hunt_crossley", "ramp")
    assert close(contact.dissipation, 0.5) and contact.c == 0.0 and close(contact.alpha, 80.0)
    assert close(contact.k, 1e4) and close(contact.mu, 0.5)


# -- a whole run and a CSV: regression over the steps visited ------------------------------------

SIMULATE = """
import numpy as np
from seed_sim import step

def simulate(scene):
    z = np.array(scene["state0"], dtype=float)
    out = [z]
    for _ in range(scene["steps"]):
        z = step(z, scene, scene["dt"])
        out.append(z)
    return np.array(out)
"""


def test_whole_run_recovers_the_law_and_says_what_it_never_exercised(tmp_path, capsys):
    (tmp_path / "seed_sim.py").write_text((load.__globals__["SCENARIO_DIR"].parent / "examples" /
                                           "seed_sim.py").read_text())
    (tmp_path / "whole.py").write_text(textwrap.dedent(SIMULATE))
    assert main(["identify", f"{tmp_path / 'whole.py'}:simulate", "point_drop", "--whole", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["integrator"]["name"] == "semi_implicit_euler"
    assert close(out["normal"]["k"], 1e4) and close(out["normal"]["c"], 60.0, rtol=1e-6)
    assert out["friction"]["law"] == "tanh" and out["matches_scene"]["friction"]
    # elastic_bounce has no damper: no step tells the damping laws apart
    sim = load_simulator(f"{tmp_path / 'whole.py'}:simulate", whole=True)
    scene = load("elastic_bounce")
    res = identify_run(sim.run(scene).states, scene)
    assert res["normal"]["law"] == "linear" and set(res["normal"]["also_fit"]) == {"compression", "unclamped",
                                                                                   "hunt_crossley"}
    assert "never separates" in res["normal"]["why"]


def test_a_whole_rk4_run_of_another_law_is_named():
    """Hunt-Crossley and smooth Coulomb under RK4, box_slide: RK4's stages couple the channels,
    so a channel fitted beside the scene's law for the others lands a part in 1e5 off. Fitted
    again beside the laws found, every effect is named with its parameters."""
    scene = dataclasses.replace(load("box_slide"), duration=0.1, integrator="rk4")
    step = numpy_step("rk4", normal="hunt_crossley", friction="smooth_coulomb", dissipation=0.3, alpha=50.0)
    sd = scene_dict(scene)
    states = [np.array(sd["state0"], dtype=float)]
    for _ in range(scene.steps):
        states.append(step(states[-1], sd, scene.dt))
    out = identify_run(np.array(states), scene)
    assert out["integrator"]["name"] == "rk4"
    assert out["normal"]["law"] == "hunt_crossley" and close(out["normal"]["dissipation"], 0.3)
    assert out["friction"]["law"] == "smooth_coulomb" and close(out["friction"]["alpha"], 50.0)
    assert out["matches_scene"]["body"] is True


def test_csv_at_six_decimals_is_judged_to_its_rounding(tmp_path):
    scene = load("box_slide")
    states = load_simulator("examples/seed_sim.py:step").run(scene).states
    t = np.arange(len(states)) * scene.dt
    np.savetxt(tmp_path / "box_slide.csv", np.column_stack([t, states]), delimiter=",",
               header="t,x,y,theta,vx,vy,omega", comments="", fmt="%.6f")
    files = load_simulator(trajectories=str(tmp_path))
    run = files.run(scene)
    out = identify_run(run.states, scene, run.rounding, "trajectories")
    assert out["integrator"]["name"] == "semi_implicit_euler"
    assert out["gravity"]["exercised"] is False          # it never leaves the ground
    assert all(v is not False for v in out["matches_scene"].values()), out["matches_scene"]
    assert out["friction"]["law"] == "tanh" and abs(out["friction"]["mu"] - 0.5) < 1e-3


def test_a_wrong_simulator_fails_at_six_decimals_too(tmp_path):
    """buggy_sim's box_slide written with %.6f: its friction on vx and its inertia are still
    told from the scene's law, the rounding allowed for."""
    scene = load("box_slide")
    states = load_simulator("examples/buggy_sim.py:step").run(scene).states
    t = np.arange(len(states)) * scene.dt
    np.savetxt(tmp_path / "box_slide.csv", np.column_stack([t, states]), delimiter=",",
               header="t,x,y,theta,vx,vy,omega", comments="", fmt="%.6f")
    run = load_simulator(trajectories=str(tmp_path)).run(scene)
    out = identify_run(run.states, scene, run.rounding, "trajectories")
    assert out["friction"]["law"] is None and out["matches_scene"]["friction"] is False
    assert out["matches_scene"]["body"] is False


def test_buggy_whole_run_finds_the_friction_it_never_applies():
    """buggy_sim's friction acts on vx, which box_drop never gets: its run has no friction where
    the scene's law has some, so "none" is what it implements there."""
    scene = load("box_drop")
    states = load_simulator("examples/buggy_sim.py:step").run(scene).states
    out = identify_run(states, scene)
    assert out["friction"]["law"] == "none" and out["matches_scene"]["friction"] is False
    assert out["matches_scene"]["body"] is False and out["matches_scene"]["normal"]


def test_kinematics_computed_once_give_the_same_forces_and_never_serve_other_points():
    """A fit computes the points' kinematics once for all its trial laws: the forces from them
    are those computed afresh, bit for bit; a trial law that moves the points (a fitted arm)
    gets its own, not the stale ones."""
    from compare.identification.from_step import scene_law
    from compare.identification.model import accelerations, kinematics
    from compare.usersim.scene_dict import scene_dict

    scene = load("t_shape_drop")
    states = simulate(dataclasses.replace(scene, duration=0.6)).states()
    law = scene_law(scene, scene_dict(scene))
    kin = kinematics(law.geometry, states)
    assert kin.touching.any() and not kin.touching.all()
    stiffer = law.with_(normal=(law.normal[0], (2.0 * law.normal[1][0], *law.normal[1][1:])))
    for trial in (law, stiffer):
        assert np.array_equal(accelerations(trial, states, kin), accelerations(trial, states))
    moved = law.with_(geometry=law.geometry.with_points(law.geometry.points + [0.0, -0.01]))
    assert np.array_equal(accelerations(moved, states, kin), accelerations(moved, states))
    assert not np.array_equal(accelerations(moved, states), accelerations(law, states))
