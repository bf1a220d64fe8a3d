"""The independent oracle under every contact-law family: the force law against hand-written
formulas, its round-off scale against extended precision, one step of each integrator converging
at its order, a mistake put into each family caught at round-off, and the reference against
closed forms (Hunt-Crossley's restitution, the ramp's exponential creep, the sign friction's
stop) and against its own energy balance E(t) - E(0) + W(t) = 0.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from compare.oracle.force_law import EPS, Law, accelerations
from compare.oracle.reference import (Equations, ReferenceFailed, cached_reference, energy, initial_mode,
                                      right_hand_side, solve_reference)
from compare.scenarios import load, load_builtins
from compare.diagnosis.mistakes import BY_NAME, applicable
from compare.oracle.one_step import FORCE_ULPS, METHODS, NO_UNIQUE_STEP, one_step, undecided
from scene_types import parse_scene

# The energy balance of the reference: DOP853 at rtol = atol = 1e-11 integrates the motion and
# the works together; their sum E - E(0) + W is conserved by the exact motion, so it measures the
# solver's own error: a few 1e-11 of the energies in play (up to 450 J on fast_impact) per
# second, measured at most 2.5e-9 J on every built-in and stress scene.
BALANCE = 1e-8               # J
# One code's round-off from the exact value: half the allowance between two codes (FORCE_ULPS).
ONE_CODE_ULPS = FORCE_ULPS / 2
# Observed orders over a short smooth stretch, from the last halving of the step: the next term
# of the error is smaller than the leading one by h times the stretch's fastest rate (the
# friction's mu g alpha (1 + m R^2 / I) = 880 1/s, h <= 1.5e-4 s for the Euler methods) and, for
# RK4, by (h rate) at h = 1.25e-4 s, 0.11: measured within 0.03 and 0.13 of 1 and 4.
ORDER_SLACK = {1: 0.05, 4: 0.3}
ORDERS = {"explicit_euler": 1, "semi_implicit_euler": 1, "implicit_euler": 1, "rk4": 4}
FIRST_STEPS = {"explicit_euler": 3e-4, "semi_implicit_euler": 3e-4, "implicit_euler": 3e-4, "rk4": 5e-4}
# A reference tight enough that the integrators' errors (at least 2e-12 in these stretches) are
# measured against it, not against its own.
TIGHT = 1e-13
# One formula evaluated by two codes in different orders: a few ulps of forces of 1 to 100 N
# (relative), or of N m torques.
SAME_FORMULA = 1e-12
# The oracle's implicit Euler solves v1 to 1e-13 m/s (OWN_SOLVE_TOL), 1.5e-10 of the 0.67 mm/s
# compared with.
SOLVED = 1e-9                # relative
# The reference against a closed form: DOP853 at 1e-11 on states of order 1 over a fraction
# of a second (Hunt-Crossley's exit speed measured within 1e-10 relative).
CLOSED_FORM = 1e-8           # m/s, or relative for a restitution
# A rolling disk's rolling work grows at mu_roll Fn tanh(100 omega) omega: Fn is m g to the
# vertical bounce left at 1 s, tanh 1 to e^-1800, omega linear in t (the trapezoid exact):
# measured within 3.4e-10 of mu_roll m g |omega|.
ROLLING_POWER = 1e-8         # relative

K, C, D, MU, ALPHA, MU_ROLL = 1e4, 30.0, 0.4, 0.5, 100.0, 0.002
DAMPING = {"compression": {}, "linear": {"damping_law": "linear"}, "unclamped": {"damping_law": "unclamped"},
           "hunt_crossley": {"damping_law": "hunt_crossley", "dissipation": D}}
FRICTION = {"tanh": {}, "ramp": {"friction_law": "ramp"}, "smooth_coulomb": {"friction_law": "smooth_coulomb"},
            "sign": {"friction_law": "sign"}}
ROLLING = {"tanh": {}, "sign": {"roll_law": "sign"}}


def contact_table(**law):
    """A [contact] table of the given families (only the parameters each takes)."""
    table = {"k": K, "mu": MU, "mu_roll": MU_ROLL, **law}
    if law.get("damping_law") != "hunt_crossley":
        table["c"] = C
    if law.get("friction_law") != "sign":
        table["alpha"] = ALPHA
    return table


def point_scene(law: dict, y=0.5, vx=0.0, vy=0.0, effects=("contact", "friction"), duration=1.0, height=0.05):
    """A 0.5 kg point mass touching at `height` below its centre."""
    return parse_scene({"duration": duration, "dt": 1e-4, "effects": list(effects),
                        "body": {"shape": "point", "mass": 0.5, "contact_height": height},
                        "contact": contact_table(**law),
                        "initial": {"position": [0.0, y], "velocity": [vx, vy]}})


def with_law(scene, **changes):
    """The scene under other families: parameters a family does not take set neutral."""
    ct = dict(changes)
    if ct.get("damping_law") == "hunt_crossley":
        ct.setdefault("c", 0.0)
        ct.setdefault("dissipation", D)
    if ct.get("friction_law") == "sign":
        ct["alpha"] = None
    if ct.get("roll_law") == "sign":
        ct["roll_sharpness"] = None
    return dataclasses.replace(scene, contact=dataclasses.replace(scene.contact, **ct))


# ---------------------------------------------------------------------------------------
# 1. Each family's force against a hand-written formula


def normal_by_hand(law, d, vn):
    """Fn (N) of each damping law, written out (scene_types.laws)."""
    if d <= 0.0:
        return 0.0
    return {"compression": K * d + C * max(0.0, -vn),
            "linear": max(0.0, K * d - C * vn),
            "unclamped": K * d - C * vn,
            "hunt_crossley": max(0.0, K * d * (1.0 - D * vn))}[law]


def shape_by_hand(law, v):
    """The friction's unit shape phi(v), written out."""
    return {"tanh": math.tanh(ALPHA * v),
            "ramp": min(1.0, max(-1.0, ALPHA * v)),
            "smooth_coulomb": v / math.sqrt(v * v + 1.0 / ALPHA ** 2),
            "sign": float(np.sign(v))}[law]


# (y, vx, vy) of the point mass (contact 0.05 m below its centre): pressing in and sliding; leaving
# slowly with a slip inside every regularisation; leaving fast (the linear law and Hunt-Crossley
# clamp at zero, the unclamped law pulls); in the air
POINT_STATES = [(0.049, 0.3, -0.2), (0.049, 0.003, 0.2), (0.0499, -0.02, 3.0), (0.051, 0.3, -0.2)]


@pytest.mark.parametrize("friction", list(FRICTION))
@pytest.mark.parametrize("damping", list(DAMPING))
def test_each_family_is_its_formula(damping, friction):
    """force_law.accelerations and the reference's right-hand side both give m a = (Ft, Fn) of
    the hand formulas, at states on every branch (no gravity: the contact alone)."""
    scene = point_scene({**DAMPING[damping], **FRICTION[friction]})
    eq = Equations.from_scene(scene)
    for y, vx, vy in POINT_STATES:
        z = np.array([0.0, y, 0.0, vx, vy, 0.0])
        fn = normal_by_hand(damping, 0.05 - y, vy)
        ft = -MU * fn * shape_by_hand(friction, vx)
        a, _ = accelerations(eq, z[None, :])
        rhs = right_hand_side(eq, initial_mode(eq, z))(0.0, z)
        for got in (a[0], rhs[3:]):
            assert got[1] * 0.5 == pytest.approx(fn, rel=SAME_FORMULA, abs=SAME_FORMULA), (damping, y, vx, vy)
            assert got[0] * 0.5 == pytest.approx(ft, rel=SAME_FORMULA, abs=SAME_FORMULA), (friction, y, vx, vy)


@pytest.mark.parametrize("roll", list(ROLLING))
@pytest.mark.parametrize("omega", [7.0, -0.004, 0.0])
def test_rolling_families_are_their_formula(roll, omega):
    """A disk (R 0.1 m, 2 kg) pressed 1 mm in, rolling at omega: I omega' = R Ft - mu_roll Fn s(omega),
    s = tanh(100 omega) or sign(omega)."""
    R, m = 0.1, 2.0
    scene = parse_scene({"duration": 1.0, "dt": 1e-4, "effects": ["contact", "friction", "rolling_friction"],
                         "body": {"shape": "circle", "mass": m, "radius": R},
                         "contact": contact_table(**ROLLING[roll]),
                         "initial": {"position": [0.0, R - 1e-3], "velocity": [0.2, -0.1], "angular_velocity": omega}})
    eq = Equations.from_scene(scene)
    z = np.array([0.0, R - 1e-3, 0.0, 0.2, -0.1, omega])
    fn = K * 1e-3 + C * 0.1
    ft = -MU * fn * math.tanh(ALPHA * (0.2 + omega * R))
    s = math.tanh(100.0 * omega) if roll == "tanh" else float(np.sign(omega))
    torque = R * ft - MU_ROLL * fn * s
    a, _ = accelerations(eq, z[None, :])
    assert a[0, 2] * m * R * R / 2 == pytest.approx(torque, rel=SAME_FORMULA, abs=SAME_FORMULA)
    if omega != 0.0:    # at omega = 0 the reference's sign law picks its mode from the torques
        rhs = right_hand_side(eq, initial_mode(eq, z))(0.0, z)
        assert rhs[5] * m * R * R / 2 == pytest.approx(torque, rel=SAME_FORMULA, abs=SAME_FORMULA)


# ---------------------------------------------------------------------------------------
# 2. The round-off scale covers each family's terms


def family_scenes():
    """box_drop under each damping and friction family, rolling_circle under each rolling law."""
    out = [(f"damping {n}", with_law(load("box_drop"), damping_law=n)) for n in DAMPING]
    out += [(f"friction {n}", with_law(load("box_drop"), friction_law=n)) for n in FRICTION if n != "tanh"]
    out += [(f"rolling {n}", with_law(load("rolling_circle"), roll_law=n)) for n in ROLLING]
    return out


def near_ground(scene, n, rng):
    """States around the contact: heights about the depth, angles of many turns, velocities of
    every size (slips at and far from the regularisations)."""
    z = np.empty((n, 6))
    z[:, 0] = rng.uniform(-1, 1, n)
    z[:, 1] = rng.uniform(-0.06, 0.12, n)
    z[:, 2] = rng.uniform(-40, 40, n) if scene.body.shape == "box" else rng.uniform(-3, 3, n)
    z[:, 3:5] = rng.normal(0, 2, (n, 2)) * rng.choice([1.0, 1e-2, 1e-4], (n, 2))
    z[:, 5] = rng.normal(0, 10, n) * rng.choice([1.0, 1e-3], n)
    return z


@pytest.mark.parametrize("label, scene", family_scenes(), ids=[n for n, _ in family_scenes()])
def test_scale_covers_each_familys_round_off(label, scene):
    """Evaluated in double precision, every acceleration is within ONE_CODE_ULPS eps of its scale
    of the same formulas evaluated in extended precision (80-bit): the bound FORCE_ULPS eps h
    scale then holds between two codes of one family."""
    eq = Equations.from_scene(scene)
    z = near_ground(scene, 4000, np.random.default_rng(11))
    a, scale = accelerations(eq, z)
    exact, _ = accelerations(eq, z.astype(np.longdouble))
    err = np.abs(a - exact.astype(float))
    assert np.all(err <= ONE_CODE_ULPS * EPS * scale), (label, float(np.max(err / (EPS * scale + 1e-300))))


# ---------------------------------------------------------------------------------------
# 3. One step of each integrator converges to the reference at its order under every family


DISK_R, DISK_M = 0.1, 2.0
STRETCH = 0.015          # s: a quarter of the disk's vertical period on its spring is 22 ms
# (slip m/s, omega rad/s) at the start: a slip inside the regularisations (the ramp's linear
# piece, tanh and smooth_coulomb near zero), sliding far beyond them, and rolling slowly (the
# rolling tanh's steep part); the disk rebounds (vy +0.05 m/s) from its resting depth.
STARTS = {"regularised": (0.005, -5.0), "sliding": (0.5, -5.0), "rolling": (0.0, -0.03)}
ORDER_CASES = [("compression", {}, "regularised"), ("linear", {"damping_law": "linear"}, "regularised"),
               ("unclamped", {"damping_law": "unclamped"}, "regularised"),
               ("hunt_crossley", DAMPING["hunt_crossley"], "regularised"),
               ("ramp", {"friction_law": "ramp"}, "regularised"), ("ramp", {"friction_law": "ramp"}, "sliding"),
               ("smooth_coulomb", FRICTION["smooth_coulomb"], "regularised"),
               ("sign", FRICTION["sign"], "sliding"), ("roll tanh", {}, "rolling"),
               ("roll sign", ROLLING["sign"], "rolling")]


def disk_stretch(law: dict, start: str):
    """A smooth stretch: the disk rebounding on its spring while it slides or rolls (no switch:
    the normal velocity stays positive below the linear law's clamp, the slip and omega keep
    their signs, the ramp its piece)."""
    slip, omega = STARTS[start]
    return parse_scene({"duration": STRETCH, "dt": 1e-4,
                        "effects": ["gravity", "contact", "friction", "rolling_friction"],
                        "body": {"shape": "circle", "mass": DISK_M, "radius": DISK_R},
                        "contact": {**contact_table(**law), "mu": 0.3},
                        "initial": {"position": [0.0, DISK_R - DISK_M * 9.81 / K],
                                    "velocity": [slip - omega * DISK_R, 0.05], "angular_velocity": omega}})


def run_steps(eq, z0, h, method, duration):
    z = np.asarray(z0, dtype=float)[None, :]
    for _ in range(round(duration / h)):
        z = one_step(eq, z, h, method)[0]
    return z[0]


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("name, law, start", ORDER_CASES, ids=[f"{n}-{s}" for n, _, s in ORDER_CASES])
def test_one_step_converges_at_its_order(name, law, start, method):
    scene = disk_stretch(law, start)
    eq = Equations.from_scene(scene)
    i = scene.initial
    z0 = [0.0, i.position[1], 0.0, *i.velocity, i.angular_velocity]
    ref = solve_reference(scene, [0.0, STRETCH], rtol=TIGHT, atol=TIGHT).states[-1]
    h = FIRST_STEPS[method]
    errors = [np.max(np.abs(run_steps(eq, z0, h / 2 ** j, method, STRETCH) - ref)) for j in (1, 2)]
    order = math.log2(errors[0] / errors[1])
    assert abs(order - ORDERS[method]) <= ORDER_SLACK[ORDERS[method]], (errors, order)
    assert errors[1] > 10 * TIGHT, errors   # measured against the reference, not its own error


# ---------------------------------------------------------------------------------------
# 4. A mistake put into each family is caught at round-off


def hunt_crossley_wrong_sign(eq, d, vcy):
    return np.maximum(0.0, eq.k * d * (1.0 + eq.dissipation * vcy))


def ramp_clamped_short(slip, alpha):
    return np.clip(alpha * slip, -0.9, 0.9)


def smooth_coulomb_unsquared(slip, alpha):
    return slip / np.sqrt(slip * slip + 1.0 / alpha)


MISTAKES = [  # (family, scene, the mistaken law)
    ("compression", with_law(load("box_drop"), damping_law="compression"), Law(damping_law="linear")),
    ("linear", load("box_drop"), Law(damping_law="compression")),
    ("unclamped", with_law(load("box_drop"), damping_law="unclamped"), Law(damping_law="linear")),
    ("hunt_crossley", with_law(load("box_drop"), damping_law="hunt_crossley"),
     Law(damping_law=hunt_crossley_wrong_sign)),
    ("tanh", load("box_drop"), Law(friction_shape="sign")),
    ("ramp", with_law(load("box_drop"), friction_law="ramp"), Law(friction_shape=ramp_clamped_short)),
    ("smooth_coulomb", with_law(load("box_drop"), friction_law="smooth_coulomb"),
     Law(friction_shape=smooth_coulomb_unsquared)),
    ("sign", with_law(load("box_drop"), friction_law="sign"), Law(friction_shape="tanh")),
    ("roll tanh", load("rolling_circle"), Law(rolling="sign")),
    ("roll sign", with_law(load("rolling_circle"), roll_law="sign"), Law(rolling="tanh")),
]


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("family, scene, mistaken", MISTAKES, ids=[m[0] for m in MISTAKES])
def test_a_mistake_in_each_family_leaves_round_off(family, scene, mistaken, method):
    """The mistaken law's step differs from the correct law's by more than the round-off bound
    at some state near the ground, and not at all in flight."""
    eq = Equations.from_scene(scene)
    z = near_ground(scene, 300, np.random.default_rng(5))
    right, bound, solved = one_step(eq, z, scene.dt, method)
    wrong, _, solved_wrong = one_step(eq, z, scene.dt, method, mistaken)
    judged = np.ones(len(z), dtype=bool) if solved is None else solved & solved_wrong
    over = np.any(np.abs(wrong - right) > bound, axis=1) & judged
    assert over.any(), f"{family}: the mistake stays within round-off at every state"
    flight = z.copy()
    flight[:, 1] += 1.0                      # every point (and every RK4 stage) a metre clear of the ground
    assert np.array_equal(one_step(eq, flight, scene.dt, method)[0],
                          one_step(eq, flight, scene.dt, method, mistaken)[0])


def test_catalogued_mistakes_that_became_laws_do_not_apply():
    """'friction sign instead of tanh' is no mistake where the scene asks the sign (nor where it
    asks another shape than tanh); the regularised rolling and the damping swaps likewise."""
    for friction in ("sign", "ramp", "smooth_coulomb"):
        scene = with_law(load("box_drop"), friction_law=friction)
        assert BY_NAME["friction_sign_not_tanh"] not in applicable(scene, scene.integrator)
    assert BY_NAME["friction_sign_not_tanh"] in applicable(load("box_drop"), "semi_implicit_euler")
    disk = with_law(load("rolling_circle"), roll_law="sign")
    assert BY_NAME["rolling_resistance_bare_sign"] not in applicable(disk, disk.integrator)
    hunt = with_law(load("point_drop"), damping_law="hunt_crossley")
    names = {m.name for m in applicable(hunt, hunt.integrator)}
    assert not names & {"linear_damping_for_compression", "compression_damping_for_linear", "damping_in_the_air"}


def test_implicit_euler_under_a_bare_sign_is_not_judged_where_it_has_no_root():
    """A point resting on the ground, sliding at 1 mm/s: one implicit step of 1 ms under the sign
    friction would need v1 = v0 - h mu g sign(v1), which no v1 solves (mu g h = 4.9 mm/s > v0):
    the row is reported as not judged. Under the ramp the same step has its root, and is judged."""
    sign = point_scene(FRICTION["sign"], y=0.05 - 0.5 * 9.81 / K, vx=1e-3, effects=("gravity", "contact", "friction"))
    ramp = with_law(sign, friction_law="ramp", alpha=ALPHA)
    z = np.array([[0.0, sign.initial.position[1], 0.0, 1e-3, 0.0, 0.0]])
    _, _, solved = one_step(Equations.from_scene(sign), z, 1e-3, "implicit_euler")
    assert not solved[0] and undecided(Equations.from_scene(sign), solved)[0]
    assert "not judged" in NO_UNIQUE_STEP
    v1, _, solved = one_step(Equations.from_scene(ramp), z, 1e-3, "implicit_euler")
    assert solved[0] and not undecided(Equations.from_scene(ramp), solved)[0]
    # v1 (1 + h mu g alpha) = v0 on the ramp's linear piece
    assert v1[0, 3] == pytest.approx(1e-3 / (1 + 1e-3 * MU * 9.81 * ALPHA), rel=SOLVED)


# ---------------------------------------------------------------------------------------
# 5. The reference against closed forms


def hunt_crossley_exit(v_in):
    """The exit speed (m/s) of a point mass hitting a Hunt-Crossley spring at v_in without
    gravity. With x the depth, m x'' = -k x (1 + D x'); dividing by x' and integrating,
    m (x'/D - ln(1 + D x')/D^2) + k x^2/2 is constant, so at x = 0 on the way in and out
    u - ln(1 + u) = -w - ln(1 - w), u = D v_in, w = D v_out (no clamp while w < 1)."""
    u = D * v_in
    lhs = u - math.log1p(u)
    return brentq(lambda w: -w - math.log1p(-w) - lhs, 1e-12, 1.0 - 1e-15, xtol=1e-16, rtol=1e-15) / D


def test_hunt_crossley_restitution_falls_with_impact_speed():
    speeds = [0.25, 0.5, 1.0, 2.0]
    restitution = []
    for v in speeds:
        scene = point_scene(DAMPING["hunt_crossley"], y=1e-3, vy=-v, effects=("contact",),
                            duration=1e-3 / v + 0.05, height=0.0)
        ref = solve_reference(scene, [0.0, scene.duration])
        v_out = ref.states[-1, 4]
        assert v_out == pytest.approx(hunt_crossley_exit(v), rel=CLOSED_FORM)
        restitution.append(v_out / v)
    assert all(1.0 > a > b for a, b in zip(restitution, restitution[1:])), restitution


def test_ramp_slides_at_mu_g_then_creeps_exponentially():
    """A point mass at its resting depth sliding at 0.5 m/s: Ft = -mu m g while alpha v > 1, so
    v = v0 - mu g t until v = 1/alpha at t1 = (v0 - 1/alpha) / (mu g); then Ft = -mu m g alpha v,
    v = exp(-mu g alpha (t - t1)) / alpha."""
    g, v0 = 9.81, 0.5
    scene = point_scene(FRICTION["ramp"], y=0.05 - 0.5 * g / K, vx=v0, effects=("gravity", "contact", "friction"),
                        duration=0.12)
    t = np.linspace(0.0, 0.12, 241)
    ref = solve_reference(scene, t)
    t1 = (v0 - 1 / ALPHA) / (MU * g)
    exact = np.where(t < t1, v0 - MU * g * t, np.exp(-MU * g * ALPHA * (t - t1)) / ALPHA)
    assert np.max(np.abs(ref.states[:, 3] - exact)) < CLOSED_FORM
    assert ref.switches["friction"] == 1


def test_box_sliding_flat_under_the_ramp_decelerates_at_mu_g():
    """box_slide under the ramp: while both corners slide beyond 1/alpha each carries
    Ft = -mu Fn, so the horizontal impulse is mu times the vertical one:
    vx(t) - vx(0) = -mu (g t + vy(t) - vy(0)), the deceleration mu g up to the vertical bounce.
    (Below 1/alpha the box does not creep at mu g alpha: the pitch its friction held is released
    and rocks the corners, and the slip is no longer vx.)"""
    scene = with_law(load("box_slide"), friction_law="ramp")
    t = np.linspace(0.0, 0.35, 351)
    ref = solve_reference(scene, t)
    vx, vy = ref.states[:, 3], ref.states[:, 4]
    expected = scene.initial.velocity[0] - MU * (scene.g * t + vy - vy[0])
    assert np.max(np.abs(vx - expected)) < CLOSED_FORM


def test_sign_friction_stops_a_point_and_holds_it_stuck():
    """A point mass at its resting depth sliding at 0.5 m/s under the bare sign stops at
    v0 / (mu g) after v0^2 / (2 mu g) and stays stuck (the Filippov stick mode), all its kinetic
    energy taken by friction."""
    g, v0 = 9.81, 0.5
    scene = point_scene(FRICTION["sign"], y=0.05 - 0.5 * g / K, vx=v0, effects=("gravity", "contact", "friction"),
                        duration=0.3)
    t = np.linspace(0.0, 0.3, 301)
    ref = solve_reference(scene, t)
    stop = v0 / (MU * g)
    assert np.max(np.abs(ref.states[t < stop, 3] - (v0 - MU * g * t[t < stop]))) < CLOSED_FORM
    assert np.max(np.abs(ref.states[t > stop, 3])) < CLOSED_FORM
    assert ref.states[-1, 0] == pytest.approx(v0 ** 2 / (2 * MU * g), abs=CLOSED_FORM)
    assert ref.work[-1, 1] == pytest.approx(0.5 * 0.5 * v0 ** 2, abs=BALANCE)


def test_sign_friction_two_corners_stuck_is_not_judged():
    """box_slide under the sign slides until v0 / (mu g), then rocks on its corners, one stuck
    while the other slides, in turn, until both would stick at once: the split of the friction
    that would hold both is ill-posed, and the reference stops there, saying so, with the time."""
    scene = with_law(load("box_slide"), friction_law="sign")
    stop = scene.initial.velocity[0] / (MU * scene.g)
    with pytest.raises(ReferenceFailed, match="stuck at once") as caught:
        solve_reference(scene, np.linspace(0.0, scene.duration, 11))
    assert stop < caught.value.t < scene.duration
    ref = solve_reference(scene, np.linspace(0.0, 0.99 * caught.value.t, 101))
    assert ref.switches["friction"] > 2      # stick and slip, one corner at a time


# ---------------------------------------------------------------------------------------
# 6. The reference carries the dissipated work: E(t) - E(0) + W(t) = 0


def balance(scene, points=20001):
    """(max |E - E(0) + W| J, smallest W J) over the reference at `points` times; where the
    reference stops (ReferenceFailed), over the stretch before it."""
    duration = scene.duration
    try:
        ref = solve_reference(scene, np.linspace(0.0, duration, points))
    except ReferenceFailed as exc:
        assert exc.t and exc.t > 0.1 * duration, str(exc)
        ref = solve_reference(scene, np.linspace(0.0, 0.99 * exc.t, points))
    eq = Equations.from_scene(scene)
    e = energy(eq, ref.states)
    return float(np.max(np.abs(e - e[0] + ref.work.sum(axis=1)))), float(ref.work.min())


SEED_SCENES = load_builtins() + [pytest.param(s, marks=pytest.mark.slow, id=s.name) for s in load_builtins("stress")]


@pytest.mark.parametrize("scene", SEED_SCENES, ids=lambda s: s.name)
def test_energy_balance_closes_on_every_scene(scene):
    residual, least = balance(scene)
    assert residual <= BALANCE, f"{scene.name}: max |E - E(0) + W| = {residual:.3g} J"
    assert least >= -BALANCE


FAMILY_CASES = [(name, law) for name in ("box_slide", "box_drop")
                for law in ({"damping_law": "compression"}, {"damping_law": "linear"},
                            {"damping_law": "unclamped"}, {"damping_law": "hunt_crossley"},
                            {"friction_law": "ramp"}, {"friction_law": "smooth_coulomb"}, {"friction_law": "sign"})]


@pytest.mark.parametrize("name, law", FAMILY_CASES, ids=[f"{n}-{list(l.values())[0]}" for n, l in FAMILY_CASES])
def test_energy_balance_closes_under_each_family(name, law):
    residual, least = balance(with_law(load(name), **law))
    assert residual <= BALANCE, f"{name} {law}: max |E - E(0) + W| = {residual:.3g} J"
    assert least >= -BALANCE


def test_work_of_each_effect_is_its_own():
    """elastic_bounce dissipates nothing; rolling_circle's rolling work is the torque mu_roll m g
    against the spin it has once it rolls: W_roll grows at mu_roll m g |omega|."""
    ref = solve_reference(load("elastic_bounce"), np.linspace(0, 3.0, 31))
    assert np.max(np.abs(ref.work)) < BALANCE
    scene = load("rolling_circle")
    t = np.linspace(1.0, 2.0, 11)
    ref = solve_reference(scene, np.concatenate([[0.0], t]))
    rate = np.diff(ref.work[1:, 2]) / np.diff(t)
    spin = np.abs(ref.states[1:, 5])
    expected = scene.contact.mu_roll * scene.body.mass * scene.g * (spin[1:] + spin[:-1]) / 2
    assert np.max(np.abs(rate / expected - 1)) < ROLLING_POWER


def test_cache_keeps_the_work(tmp_path):
    scene = dataclasses.replace(load("point_drop"), duration=0.5)
    t = np.linspace(0.0, 0.5, 101)
    first = cached_reference(scene, t, tmp_path)
    again = cached_reference(scene, t, tmp_path)
    assert first.work.shape == (101, 3) and np.array_equal(first.work, again.work)
