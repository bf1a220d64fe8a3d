"""Every contact-law family in the MuJoCo twins: the dynamics twin's force against the law by hand,
its motion against analytic results, and the native twin's line per law."""
import dataclasses
import math

import mujoco
import numpy as np
import pytest
from scipy.optimize import brentq

from mujoco_models import simulate_dynamics, simulate_mujoco
from mujoco_models import contact_law
from mujoco_models.approximations import approximations
from mujoco_models.frames import qpos_qvel
from mujoco_models.passive import LAW_CODES, installed, law_parameters
from mujoco_models.sites import contact_below_site
from mujoco_models.spec import build_twin
from scene_types.laws import DAMPING_LAWS, FRICTION_LAWS, LAW_NAMES, ROLL_LAWS
from scene_types.schema import parse_scene

G = 9.81
EPS = np.finfo(float).eps

# The callback's force and the one by hand are the same few products and sums (MuJoCo's
# Jacobian, rotation from its quaternion) in another order: a few hundred ulp of the largest
# term at most.
FORCE_ROUNDOFF = 1e-13
# Semi-implicit Euler is first order: the velocity a point leaves a contact of about pi / wn
# with is off by O(h wn) of the impact speed (the discrete spring's frequency and damping are
# off by O(h wn) relative, and the entry falls anywhere within a step). The restitution is
# allowed h wn, the error's order with constant 1 (measured: at most 0.1 h wn).
RESTITUTION_PER_HWN = 1.0
# On a law v' = -A s(v) that only slows (h A s' < 2: each step contracts an error), explicit
# Euler in v (MuJoCo's Euler's velocity update) makes a local error (h^2 / 2) |v''| a step; summed,
# at most (h / 2) times the total variation of v', which is A as s runs once from 1 to 0.
EULER_BOUND = 0.5
# Euler takes a constant deceleration exactly (its error term h^2 v'' / 2 vanishes): only the
# rounding of n updates of a speed v remains, n ulp(v); four times that for the forces' own.
ROUNDOFF_PER_STEP = 4 * EPS
# Euler's discrete decay rate of v' = -lam v is -ln(1 - h lam) / h = lam (1 + h lam / 2 + ...):
# the first-order relative error h lam / 2 with its remainder stays below h lam while h lam < 0.7.
RATE_PER_HLAM = 1.0


# --------------------------------------------------------------------------------------
# The laws by hand: Fn per point, the friction's s(v) and the rolling law's r(omega)

NORMAL = {
    "compression": lambda ct, d, vn: ct.k * d + ct.c * max(0.0, -vn),
    "linear": lambda ct, d, vn: max(0.0, ct.k * d - ct.c * vn),
    "unclamped": lambda ct, d, vn: ct.k * d - ct.c * vn,
    "hunt_crossley": lambda ct, d, vn: max(0.0, ct.k * d * (1.0 - ct.dissipation * vn)),
}
SLIP = {   # Ft = -mu Fn s(v)
    "tanh": lambda ct, v: math.tanh(ct.alpha * v),
    "ramp": lambda ct, v: min(1.0, max(-1.0, ct.alpha * v)),
    "smooth_coulomb": lambda ct, v: ct.alpha * v / math.sqrt(1.0 + (ct.alpha * v) ** 2),
    "sign": lambda ct, v: float(np.sign(v)),
}
ROLL = {   # tau = -mu_roll Fn r(omega)
    "tanh": lambda ct, w: math.tanh(ct.roll_sharpness * w),
    "sign": lambda ct, w: float(np.sign(w)),
}

BOX = {"shape": "box", "mass": 0.8, "size": [0.2, 0.1]}
DISK = {"shape": "circle", "mass": 2.0, "radius": 0.1}
POINT = {"shape": "point", "mass": 1.0, "contact_height": 0.05}
ALL_EFFECTS = ["gravity", "contact", "friction", "rolling_friction"]


def contact_table(damping="compression", friction="tanh", roll="tanh", **over):
    """A [contact] table naming the three families, with each family's own parameters."""
    table = {"k": 1e4, "mu": 0.4, "mu_roll": 0.003, "damping_law": damping, "friction_law": friction,
             "roll_law": roll}
    table.update({"dissipation": 0.6} if damping == "hunt_crossley" else {"c": 20.0})
    if friction != "sign":
        table["alpha"] = 100.0
    if roll != "sign":
        table["roll_sharpness"] = 0.5     # not the old constant 100 s/rad: read from the scene
    return {**table, **over}


def make_scene(body, contact, effects, position, velocity=(0.0, 0.0), omega=0.0, duration=0.01, dt=1e-4):
    initial = {"position": list(position), "velocity": list(velocity)}
    if body["shape"] != "point":
        initial["angular_velocity"] = omega
    return parse_scene({"duration": duration, "dt": dt, "effects": list(effects), "body": body,
                        "contact": contact, "initial": initial}, file="<test>")


def contact_points(body):
    """The contact points about the COM in the body frame, and whether they turn with it."""
    if body.shape == "box":
        w, h = body.size
        return [(sx * w / 2, sy * h / 2) for sx in (-1, 1) for sy in (-1, 1)], True
    if body.shape == "circle":
        return [(0.0, -body.radius)], False
    return [(0.0, -body.contact_height)], False


def law_by_hand(scene, state):
    """(Fx, Fy, tau) of the scene's laws at the state: per point below ground, Fn, Ft at the
    point's slip, the torque r x F and the rolling torque."""
    x, y, th, vx, vy, om = state
    ct = scene.contact
    points, turns = contact_points(scene.body)
    c, s = (math.cos(th), math.sin(th)) if turns else (1.0, 0.0)
    force = np.zeros(3)
    for lx, ly in points:
        rx, ry = c * lx - s * ly, s * lx + c * ly
        d = -(y + ry)
        if d <= 0.0:
            continue
        fn = NORMAL[ct.damping_law](ct, d, vy + om * rx)
        ft = -ct.mu * fn * SLIP[ct.friction_law](ct, vx - om * ry) if scene.has("friction") else 0.0
        roll = (-ct.mu_roll * fn * ROLL[ct.roll_law](ct, om)
                if scene.has("rolling_friction") and scene.body.shape != "point" else 0.0)
        force += (ft, fn, rx * fn - ry * ft + roll)
    return force


def passive_force(scene, state):
    """qfrc_passive of the dynamics twin after mj_forward at the state [x, y, theta, vx, vy, omega]."""
    twin = build_twin(scene, pairs="none")
    model = twin.spec.compile()
    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:] = qpos_qvel(twin.props, state)
    params = law_parameters(scene, twin.props, contact_below_site(scene.body), native_normal=False,
                            friction_at="corner")
    with installed(model, data, params):
        mujoco.mj_forward(model, data)
    return data.qfrc_passive.copy()


# Box states: both lower corners down at BOX_STATES[0]: the right one 0.94 mm deep and leaving
# at 2.25 m/s (k d < c v_n: the linear law clamps, the unclamped one pulls, Hunt-Crossley's
# 1 - D v_n < 0 clamps), the left one 10.9 mm deep and approaching; slips 0.004 m/s (inside the
# ramp's 1/alpha) and 0.204 m/s. BOX_STATES[1]: one corner down, turning the other way.
BOX_STATES = [[0.1, 0.044, 0.05, -0.8948, 0.2, 20.0], [-0.3, 0.07, -0.3, 0.5, -0.4, -2.0]]
# Disk states: S omega = 2 and -0.15 with roll_sharpness S = 0.5 s/rad (tanh's both regimes)
DISK_STATES = [[0.0, 0.098, 1.1, 0.7, -0.3, 4.0], [0.0, 0.0995, 0.0, -0.2, 0.1, -0.3]]
FORCE_CASES = ([("damping_law", law, BOX, s) for law in DAMPING_LAWS for s in BOX_STATES]
               + [("damping_law", law, POINT, [0.2, 0.047, 0.0, 0.5, 0.4, 0.0]) for law in DAMPING_LAWS]
               + [("friction_law", law, BOX, s) for law in FRICTION_LAWS for s in BOX_STATES]
               + [("roll_law", law, DISK, s) for law in ROLL_LAWS for s in DISK_STATES])


def scene_with(field, law, body):
    families = {"damping": "compression", "friction": "tanh", "roll": "tanh"}
    families[field.split("_")[0]] = law
    effects = ALL_EFFECTS if body is DISK else ALL_EFFECTS[:3]
    return make_scene(body, contact_table(**families), effects, (0.0, 1.0))


def test_the_chosen_states_reach_every_branch():
    scene = scene_with("damping_law", "unclamped", BOX)
    ct = scene.contact
    x, y, th, vx, vy, om = BOX_STATES[0]
    rx, ry = [0.1 * math.cos(th) + 0.05 * math.sin(th), -0.1 * math.cos(th) + 0.05 * math.sin(th)], \
        [0.1 * math.sin(th) - 0.05 * math.cos(th), -0.1 * math.sin(th) - 0.05 * math.cos(th)]
    depth = [-(y + r) for r in ry]
    vn = [vy + om * r for r in rx]
    slip = [vx - om * r for r in ry]
    assert min(depth) > 0.0
    assert ct.k * depth[0] - ct.c * vn[0] < 0.0 < ct.k * depth[1] - ct.c * vn[1], "a pull and a push"
    assert 1.0 - 0.6 * vn[0] < 0.0, "Hunt-Crossley clamps the leaving corner"
    assert abs(ct.alpha * slip[0]) < 1.0 < abs(ct.alpha * slip[1]), "inside and beyond the ramp"


@pytest.mark.parametrize("field,law,body,state", FORCE_CASES,
                         ids=[f"{f}={law}-{b['shape']}{i % 2}" for i, (f, law, b, _) in enumerate(FORCE_CASES)])
def test_callback_force_is_the_family_by_hand(field, law, body, state):
    scene = scene_with(field, law, body)
    got = passive_force(scene, state)
    want = law_by_hand(scene, state)
    assert np.any(want != 0.0), "the state touches the ground"
    scale = np.max(np.abs(want))
    assert got == pytest.approx(want[:len(got)], rel=FORCE_ROUNDOFF, abs=FORCE_ROUNDOFF * scale), \
        f"{field} = {law}: callback {got} against {want} (N, N, N m)"


def test_the_unclamped_law_pulls():
    """At BOX_STATES[0] the leaving corner's Fn < 0 and the callback pulls (the force test above
    also checks that the friction takes that Fn as it is: Ft = -mu Fn s(v))."""
    scene = scene_with("damping_law", "unclamped", BOX)
    linear = scene_with("damping_law", "linear", BOX)
    pull = passive_force(scene, BOX_STATES[0])[1] - passive_force(linear, BOX_STATES[0])[1]
    assert pull < -1.0, f"the unclamped law pulls {pull:.3g} N harder than the linear law"


@pytest.mark.parametrize("values", [(1e4, 20.0, 0.6, 3e-3, -1.7), (1e4, 20.0, 0.6, 1e-3, 2.5), (5e3, 0.0, 0.2, 0.02, 0.0)])
def test_plain_python_and_compiled_law_functions_agree_with_the_families(values):
    """contact_law's functions (numba-compiled, and their plain-Python py_func) against the
    formulas above, with integer family codes."""
    k, c, dissipation, depth, vn = values
    ct = dataclasses.make_dataclass("C", ["k", "c", "dissipation", "alpha", "roll_sharpness"])(k, c, dissipation, 80.0, 3.0)
    for name, code in contact_law.DAMPING_CODES.items():
        want = NORMAL[name](ct, depth, vn)
        for f in (contact_law.normal_force, contact_law.normal_force.py_func):
            assert f(code, k, c, dissipation, depth, vn) == pytest.approx(want, rel=FORCE_ROUNDOFF), name
    for slip in (-0.3, -0.004, 0.0, 0.01, 2.0):
        for name, code in contact_law.FRICTION_CODES.items():
            want = -0.4 * 7.0 * SLIP[name](ct, slip)
            for f in (contact_law.friction_force, contact_law.friction_force.py_func):
                assert f(code, 0.4, 80.0, 7.0, slip) == pytest.approx(want, rel=FORCE_ROUNDOFF, abs=1e-300), (name, slip)
        for name, code in contact_law.ROLL_CODES.items():
            want = -0.003 * 7.0 * ROLL[name](ct, slip)
            for f in (contact_law.rolling_torque, contact_law.rolling_torque.py_func):
                assert f(code, 0.003, 3.0, 7.0, slip) == pytest.approx(want, rel=FORCE_ROUNDOFF, abs=1e-300), (name, slip)
    assert math.isnan(contact_law.normal_force(99, k, c, dissipation, depth, vn)), "an unknown code shows"


# --------------------------------------------------------------------------------------
# Nothing refused silently


def test_every_named_family_is_implemented():
    for field, names in LAW_NAMES.items():
        assert set(names) <= set(LAW_CODES[field]), f"{field}: {set(names) - set(LAW_CODES[field])}"


@pytest.mark.parametrize("field", list(LAW_NAMES))
def test_a_law_the_callback_does_not_implement_is_refused_by_name(field):
    scene = make_scene(BOX, contact_table(), ALL_EFFECTS[:3], (0.0, 1.0))
    odd = dataclasses.replace(scene, contact=dataclasses.replace(scene.contact, **{field: "stribeck"}))
    twin = build_twin(scene, pairs="none")
    with pytest.raises(ValueError, match=f"{field} = 'stribeck'"):
        law_parameters(odd, twin.props, 0.0, native_normal=False, friction_at="corner")
    with pytest.raises(ValueError, match="stribeck"):
        simulate_dynamics(odd)


# --------------------------------------------------------------------------------------
# Motions against analytic results (MuJoCo's Euler at the scene's dt)

# A point mass of 1 kg on k = 1e4 N/m (wn = 100 rad/s) sent at the ground without gravity or
# friction, from 0.2 of a step's travel above it; dt = 1e-5 s (h wn = 1e-3).
DROP_K, DROP_M, DROP_DT = 1e4, 1.0, 1e-5


def restitution(law, v0, **params):
    """The dynamics twin's restitution: leaving speed / impact speed of the point mass."""
    table = {"k": DROP_K, "mu": 0.0, "damping_law": law, **params}
    scene = make_scene(dict(POINT, mass=DROP_M), table, ["contact"], (0.0, 0.05 + 0.2 * DROP_DT * v0),
                       (0.0, -v0), duration=0.06, dt=DROP_DT)
    tr = simulate_dynamics(scene)
    assert tr.y[-1] > 0.05 and tr.vy[-1] > 0.0, "the point has left the ground"
    return tr.vy[-1] / v0


def restitution_tolerance():
    return RESTITUTION_PER_HWN * DROP_DT * math.sqrt(DROP_K / DROP_M)


# The spring-damper x'' = -wn^2 x - 2 zeta wn x' from x = 0, x' = v0 (x the depth): the
# unclamped law leaves at x = 0 after half a damped period; the linear law where its force
# k x + c x' reaches 0 (wd t = 2 acos zeta), with speed exactly v0 exp(-zeta wn t); the
# compression law at its deepest point (wd t = acos zeta) and undamped after: docs/mujoco-twins.md.
ZETA = 0.2
RESTITUTION = {
    "unclamped": math.exp(-math.pi * ZETA / math.sqrt(1 - ZETA ** 2)),
    "linear": math.exp(-2 * ZETA * math.acos(ZETA) / math.sqrt(1 - ZETA ** 2)),
    "compression": math.exp(-ZETA * math.acos(ZETA) / math.sqrt(1 - ZETA ** 2)),
}


@pytest.mark.parametrize("law", list(RESTITUTION))
def test_restitution_of_a_spring_damper_law(law):
    c = 2 * ZETA * math.sqrt(DROP_K * DROP_M)
    e = restitution(law, 1.0, c=c)
    assert e == pytest.approx(RESTITUTION[law], abs=restitution_tolerance()), \
        f"{law}: restitution {e:.6f}, analytic {RESTITUTION[law]:.6f}"


def hunt_crossley_restitution(u):
    """The exact restitution of k x (1 + D x') without gravity, u = D v0: x'' = -wn^2 x (1 + D x')
    separates in the phase plane, and one contact returns x to 0, so u - ln(1 + u) =
    -e u - ln(1 - e u) (docs/mujoco-twins.md): no k or m in it."""
    return brentq(lambda e: -e * u - math.log1p(-e * u) - (u - math.log1p(u)), 0.0, 1.0, xtol=1e-15)


def test_hunt_crossley_restitution_falls_with_impact_speed():
    dissipation = 0.05
    speeds = (0.5, 1.0, 2.0, 4.0)
    measured = [restitution("hunt_crossley", v0, dissipation=dissipation) for v0 in speeds]
    assert all(a > b for a, b in zip(measured, measured[1:])), f"falls with impact speed: {measured}"
    for v0, e in zip(speeds, measured):
        u = dissipation * v0
        assert e == pytest.approx(hunt_crossley_restitution(u), abs=restitution_tolerance()), f"v0 = {v0}"
        # near 1 - (2/3) u: the series is 1 - 2u/3 + 4u^2/9 - ..., its third term negative
        assert 0.0 < e - (1 - 2 * u / 3) <= 4 * u * u / 9 + restitution_tolerance(), f"v0 = {v0}"


# A point mass of 0.5 kg resting at its depth m g / k (vertical forces balance exactly: Fn = m g
# at every step), launched sideways at V0: v' = -mu g s(v) at the contact point.
SLIDE_MU, SLIDE_ALPHA, SLIDE_V0, SLIDE_DT = 0.5, 100.0, 2.0, 1e-4


def slide(law, native=False):
    table = contact_table(friction=law, damping="linear", mu=SLIDE_MU)
    if law != "sign":
        table["alpha"] = SLIDE_ALPHA
    scene = make_scene(dict(POINT, mass=0.5), table, ALL_EFFECTS[:3], (0.0, 0.05 - 0.5 * G / 1e4),
                       (SLIDE_V0, 0.0), duration=0.6, dt=SLIDE_DT)
    return simulate_mujoco(scene) if native else simulate_dynamics(scene)


def sliding_speed(law, t):
    """v(t) of v' = -mu g s(v), v(0) = V0, solved in closed form (smooth_coulomb: implicitly)."""
    a, alpha, v0 = SLIDE_MU * G, SLIDE_ALPHA, SLIDE_V0
    if law == "tanh":      # d/dt sinh(alpha v) = -a alpha sinh(alpha v)
        return np.arcsinh(np.sinh(alpha * v0) * np.exp(-a * alpha * t)) / alpha
    if law == "ramp":      # mu g until alpha v = 1, then exponential at mu g alpha
        t1 = (v0 - 1 / alpha) / a
        return np.where(t < t1, v0 - a * t, np.exp(-a * alpha * (t - t1)) / alpha)
    if law == "sign":
        return np.maximum(v0 - a * t, 0.0)
    eps = 1 / alpha        # smooth_coulomb: H(v) = sqrt(v^2 + eps^2) - eps ln((eps + sqrt(v^2 + eps^2)) / v)
    H = lambda v: math.hypot(v, eps) - eps * math.log((eps + math.hypot(v, eps)) / v)   # noqa: E731
    return np.array([math.exp(brentq(lambda w: H(math.exp(w)) - (H(v0) - a * ti), -600.0, math.log(v0),
                                     xtol=1e-14)) if ti > 0 else v0 for ti in t])


@pytest.mark.parametrize("law", FRICTION_LAWS)
def test_sliding_point_mass_follows_each_friction_law(law):
    tr = slide(law)
    a = SLIDE_MU * G
    every = 20
    t, v = tr.t[::every], tr.vx[::every]
    if law == "sign":
        stop = SLIDE_V0 / a
        before = t < stop - SLIDE_DT
        n = np.arange(len(tr.t))[::every][before]
        assert np.all(np.abs(v[before] - (SLIDE_V0 - a * t[before])) <= ROUNDOFF_PER_STEP * n * SLIDE_V0 + 1e-15)
        assert np.max(np.abs(tr.vx[tr.t > stop])) <= a * SLIDE_DT, "stopped: it chatters within mu g h"
        return
    error = np.max(np.abs(v - sliding_speed(law, t)))
    assert error <= EULER_BOUND * SLIDE_DT * a, f"{law}: {error:.3g} m/s from the closed form"


def test_ramp_decelerates_at_mu_g_then_decays_at_mu_g_alpha():
    """The point mass under the ramp: a straight line at -mu g down to 1/alpha, then an
    exponential at mu g alpha (fitted)."""
    tr = slide("ramp")
    a, lam = SLIDE_MU * G, SLIDE_MU * G * SLIDE_ALPHA
    t1 = (SLIDE_V0 - 1 / SLIDE_ALPHA) / a
    line = tr.t < t1 - SLIDE_DT
    decel = -np.polyfit(tr.t[line], tr.vx[line], 1)[0]
    assert decel == pytest.approx(a, rel=ROUNDOFF_PER_STEP * line.sum())
    tail = (tr.t > t1 + SLIDE_DT) & (tr.vx > 1e-12)
    rate = -np.polyfit(tr.t[tail], np.log(tr.vx[tail]), 1)[0]
    assert rate == pytest.approx(lam, rel=RATE_PER_HLAM * SLIDE_DT * lam), f"decay {rate:.4g} 1/s"


def test_box_slide_under_the_ramp_decelerates_at_mu_g():
    """box_slide under the ramp: while both lower corners slip faster than 1/alpha, the
    friction is mu times the normal load, so vx falls by mu (g dt + the rise of vy): Euler's
    sums telescope, to round-off. (Below 1/alpha the box's tilt, which the friction's torque
    sets, moves the corners' slip, and the decay is not the point mass's.)"""
    scene = make_scene({"shape": "box", "mass": 0.5, "size": [0.2, 0.1]},
                       contact_table(damping="compression", friction="ramp", mu=0.5, c=20.0, alpha=100.0),
                       ALL_EFFECTS[:3], (0.0, 0.0497548), (2.0, 0.0), duration=0.5, dt=1e-4)
    tr = simulate_dynamics(scene)
    th, om = tr.theta, tr.omega
    slips = [tr.vx - om * (np.sin(th) * lx + np.cos(th) * -0.05) for lx in (-0.1, 0.1)]
    fast = np.minimum(*slips) * 100.0 > 1.0
    last = np.flatnonzero(~fast)[0] - 1
    assert last > 3000, "slides beyond 1/alpha for 0.3 s"
    n = np.arange(last + 1)
    residual = (tr.vx[:last + 1] - 2.0) + 0.5 * (G * tr.t[:last + 1] + tr.vy[:last + 1] - tr.vy[0])
    assert np.all(np.abs(residual) <= ROUNDOFF_PER_STEP * n * 2.0 + 1e-15)


# Disk: 2 kg, R = 0.1 m, resting at its depth m g / k; mu_roll = 0.01 m
ROLL_R, ROLL_MU = 0.1, 0.01


def disk_run(law, velocity, omega, effects, sharpness=None, duration=1.0, dt=1e-4):
    table = contact_table(roll=law, damping="linear", mu=0.3, mu_roll=ROLL_MU)
    if law != "sign":
        table["roll_sharpness"] = sharpness
    return simulate_dynamics(make_scene(DISK, table, effects, (0.0, ROLL_R - 2.0 * G / 1e4), velocity, omega,
                                        duration=duration, dt=dt))


@pytest.mark.parametrize("law", ROLL_LAWS)
def test_rolling_disk_decelerates_at_two_thirds_mu_roll_g_over_r(law):
    """Rolling without slipping: m a = f, (m R^2 / 2) omega' = mu_roll m g + R f, a = -R omega':
    a = 2 mu_roll g / (3 R) (0.654 m/s^2), constant until the disk stops (tanh: S omega >> 1,
    S = 100 s/rad). The tanh friction's slip settles within e^-40 by 0.05 s."""
    v0 = 0.5
    tr = disk_run(law, (v0, 0.0), -v0 / ROLL_R, ALL_EFFECTS, sharpness=100.0)
    a = 2 * ROLL_MU * G / (3 * ROLL_R)
    window = (tr.t > 0.05) & (tr.t < v0 / a - 0.1)
    decel = -np.polyfit(tr.t[window], tr.vx[window], 1)[0]
    spin = np.polyfit(tr.t[window], tr.omega[window], 1)[0] * ROLL_R
    n = np.flatnonzero(window)[-1]
    assert decel == pytest.approx(a, rel=ROUNDOFF_PER_STEP * n), f"{law}: {decel:.15g} m/s^2"
    assert spin == pytest.approx(a, rel=ROUNDOFF_PER_STEP * n), "it rolls: a = R omega'"


@pytest.mark.parametrize("law", ROLL_LAWS)
def test_spinning_disk_follows_each_rolling_law(law):
    """No sliding friction: a disk spinning in place, (m R^2 / 2) omega' = -mu_roll m g r(omega):
    omega' = -b r(omega), b = 2 mu_roll g / R^2; tanh with the scene's roll_sharpness S = 10 s/rad:
    sinh(S omega) = sinh(S omega0) exp(-b S t); sign: omega0 - b t to the stop, then a chatter
    within b h."""
    omega0, S, dt = 5.0, 10.0, 1e-4
    tr = disk_run(law, (0.0, 0.0), omega0, ["gravity", "contact", "rolling_friction"], sharpness=S,
                  duration=0.5, dt=dt)
    b = 2 * ROLL_MU * G / ROLL_R ** 2
    if law == "tanh":
        exact = np.arcsinh(np.sinh(S * omega0) * np.exp(-b * S * tr.t)) / S
        assert np.max(np.abs(tr.omega - exact)) <= EULER_BOUND * dt * b
        return
    stop = omega0 / b
    before = tr.t < stop - dt
    n = np.arange(len(tr.t))[before]
    assert np.all(np.abs(tr.omega[before] - (omega0 - b * tr.t[before])) <= ROUNDOFF_PER_STEP * n * omega0 + 1e-15)
    assert np.max(np.abs(tr.omega[tr.t > stop])) <= b * dt


# --------------------------------------------------------------------------------------
# The native twins: one line per law, and what it says


LINE = {"damping_law": "damping law:", "friction_law": "friction law:", "roll_law": "rolling law:"}
FAMILIES = [(field, law) for field, names in LAW_NAMES.items() for law in names]


def native_scene(field, law):
    return scene_with(field, law, DISK if field == "roll_law" else BOX)


@pytest.mark.parametrize("field,law", FAMILIES, ids=[f"{f}={law}" for f, law in FAMILIES])
def test_every_law_family_has_its_line(field, law):
    lines = {}
    for mapping in ("penalty", "physical", "seed"):
        notes = approximations(build_twin(native_scene(field, law), mapping))
        ours = [n for n in notes if n.startswith(LINE[field])]
        assert len(ours) == 1 and law in ours[0], f"{mapping}: {ours}"
        lines[mapping] = ours[0]
    others = [approximations(build_twin(native_scene(field, other)))
              for other in LAW_NAMES[field] if other != law]
    assert all(lines["penalty"] not in notes for notes in others), "each family says its own"


@pytest.mark.parametrize("field,law", FAMILIES, ids=[f"{f}={law}" for f, law in FAMILIES])
def test_native_twin_runs_every_family(field, law):
    scene = dataclasses.replace(native_scene(field, law), duration=0.05)
    above = 0.06 if field != "roll_law" else 0.11     # 1 cm above the ground
    scene = dataclasses.replace(scene, initial=dataclasses.replace(scene.initial, position=(0.0, above)))
    for mapping in ("penalty", "physical", "seed"):
        assert np.all(np.isfinite(simulate_mujoco(scene, solref=mapping).states())), mapping


def test_native_twin_holds_what_the_sign_law_makes_chatter():
    """The sign law's line: MuJoCo's cone holds the stopped point still (static friction) where
    the dynamics twin's bare sign flips mu Fn every step."""
    native, ours = slide("sign", native=True), slide("sign")
    stop = SLIDE_V0 / (SLIDE_MU * G)
    chatter = np.max(np.abs(ours.vx[ours.t > stop + 0.05]))
    held = np.max(np.abs(native.vx[native.t > stop + 0.05]))
    assert chatter > 0.1 * SLIDE_MU * G * SLIDE_DT and held < 1e-6 * SLIDE_MU * G * SLIDE_DT


def test_native_twin_under_hunt_crossley_is_an_undamped_spring():
    """The hunt_crossley line: the twin gets c = 0, so the penalty mapping's contact bounces
    elastically, where the dynamics twin's loses about (2/3) D v."""
    v0, dissipation = 2.0, 0.05
    table = {"k": DROP_K, "mu": 0.0, "damping_law": "hunt_crossley", "dissipation": dissipation}
    scene = make_scene(dict(POINT, mass=DROP_M), table, ["contact"], (0.0, 0.05 + 0.2 * DROP_DT * v0),
                       (0.0, -v0), duration=0.06, dt=DROP_DT)
    tr = simulate_mujoco(scene, solref="penalty", integrator="Euler")
    assert tr.vy[-1] / v0 == pytest.approx(1.0, abs=restitution_tolerance())
    assert "undamped spring" in " ".join(tr.meta["approximations"])
