"""Every contact-law family of the scene in custom_sim, each against a result it did not produce.

The derivations are in docs/contact-laws.md. Gravity is off wherever a bounce is measured: a
contact lasts about pi / w = 31 ms at w = 100 rad/s, and gravity would change the speed by
0.3 m/s meanwhile, as much as the laws' differences.
"""
from __future__ import annotations

import dataclasses
import hashlib
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from compare.scenarios import load
from custom_sim import INTEGRATORS, SimulationChattered, Stepper, simulate, stable_step
from custom_sim.stability import friction_rate, limit_modes, limits, warning
from scene_types import parse_scene

G = 9.81
EPS = float(np.finfo(float).eps)

# A step's velocity change differs from the hand formula's by round-off only: the two sum the
# same terms in another order (m g against g / (1/m), a library tanh against a series), each
# within a few ulps of the state and of h times the force terms. 64 ulps of both.
ROUNDOFF_ULPS = 64
# custom_sim's Newton stops with max |G| <= 1e-10 m/s (integrators.RESIDUAL_TOL); the hand
# formula's own rounding of h a (eps h |a| ~ 1e-16 m/s here) is far below the other 1e-10.
IMPLICIT_RESIDUAL = 2e-10


# ---------------------------------------------------------------------------------------
# Scenes


def point_scene(contact: dict, speed: float, dt: float, duration: float, integrator: str = "rk4",
                effects=("contact",), depth: float = 0.0, mass: float = 1.0):
    """A point mass at depth `depth` (m) moving down at `speed` (m/s)."""
    return parse_scene({"duration": duration, "dt": dt, "integrator": integrator, "effects": list(effects),
                        "body": {"shape": "point", "mass": mass}, "contact": contact,
                        "initial": {"position": [0.0, -depth], "velocity": [0.0, -speed]}}, file="<test>")


def sliding_box(friction: dict, speed: float, dt: float, duration: float, k: float = 1e6,
                integrator: str = "semi_implicit_euler"):
    """A 1 kg box 0.2 x 0.1 m lying flat at its resting depth m g / (2 k) per corner, sliding at
    `speed` (m/s); damping a quarter of critical on the two corners (c = sqrt(k m) / 2)."""
    contact = {"k": k, "c": 0.5 * math.sqrt(k), "mu": 0.5, **friction}
    return parse_scene({"duration": duration, "dt": dt, "integrator": integrator,
                        "body": {"shape": "box", "mass": 1.0, "size": [0.2, 0.1]}, "contact": contact,
                        "initial": {"position": [0.0, 0.05 - G / (2 * k)], "velocity": [speed, 0.0]}},
                       file="<test>")


def with_contact(scene, **changes):
    return dataclasses.replace(scene, contact=dataclasses.replace(scene.contact, **changes))


def restitution(scene) -> float:
    """Speed after the bounce over speed before, from a run that ends in flight."""
    traj = simulate(scene)
    assert traj.y[-1] > 0.0, "the run must end after the point has left the ground"
    return traj.vy[-1] / -scene.initial.velocity[1]


def force_of_one_step(scene, state):
    """(Fx, Fy) in N that one explicit Euler step of custom_sim applies at `state`, read back from
    v1 = v0 + h F / m, and the round-off of that reading (N)."""
    m, h = scene.body.mass, scene.dt
    st = Stepper(dataclasses.replace(scene, integrator="explicit_euler"), watch_chatter=False)
    st.reset(state)
    after = st.advance(1)
    noise = 4 * EPS * max(abs(state[3]), abs(state[4]), abs(after[3]), abs(after[4])) * m / h
    return (after[3] - state[3]) * m / h, (after[4] - state[4]) * m / h, noise


# ---------------------------------------------------------------------------------------
# Hunt-Crossley: Fn = max(0, k d (1 - dissipation v_n))

HC_K, HC_DISSIPATION = 1e4, 0.2      # N/m on 1 kg: w = 100 rad/s; s/m
HC_SPEEDS = (0.1, 0.5, 2.0)          # m/s: dissipation v = 0.02, 0.1, 0.4
HC_DT = 1e-6                         # s: h w = 1e-4
# RK4 steps over touchdown and lift-off: Hunt-Crossley's force k d (1 - D v_n) is zero at d = 0,
# so a stage on the wrong side misses at most k v h of force for a step: (w h)^2 = 1e-8 of the
# speed per crossing, two crossings.
HC_CROSSING = 2 * (100.0 * HC_DT) ** 2
# The expansion e = 1 - (2/3) D v + O((D v)^2): its next term is (4/9) (D v)^2 (measured), so the
# first-order formula holds to (D v)^2 at small D v.
HC_FIRST_ORDER = 1.0


def hunt_crossley_restitution_scipy(speed: float) -> float:
    """The 1-D contact ODE x'' = -max(0, k x (1 + D x')) / m (x the depth, x' = -v_n), from
    touchdown at `speed` to lift-off (x = 0), by DOP853 at rtol 1e-12: the rebound speed over
    the impact speed."""
    def rhs(_, s):
        return [s[1], -max(0.0, HC_K * s[0] * (1.0 + HC_DISSIPATION * s[1]))]

    def leaves(t, s):
        return s[0] if t > 1e-6 else 1.0
    leaves.terminal, leaves.direction = True, -1
    sol = solve_ivp(rhs, (0.0, 1.0), [0.0, speed], method="DOP853", rtol=1e-12, atol=1e-15, events=leaves)
    return -sol.y_events[0][0][1] / speed


def test_hunt_crossley_restitution_falls_with_speed_as_the_contact_ode_says():
    contact = {"k": HC_K, "damping_law": "hunt_crossley", "dissipation": HC_DISSIPATION}
    measured = [restitution(point_scene(contact, v, HC_DT, 0.04)) for v in HC_SPEEDS]
    for v, e in zip(HC_SPEEDS, measured):
        assert e == pytest.approx(hunt_crossley_restitution_scipy(v), abs=HC_CROSSING), v
    assert measured[0] > measured[1] > measured[2], "the restitution must fall with the impact speed"
    beta = HC_DISSIPATION * HC_SPEEDS[0]
    assert abs(measured[0] - (1.0 - 2.0 / 3.0 * beta)) <= HC_FIRST_ORDER * beta ** 2


def test_hunt_crossley_has_no_damping_force_at_touchdown():
    """Fn / d = k (1 + D |v_n|) as d -> 0 at a fast approach: the force vanishes with the depth,
    where the seed's damper would push with c |v_n| at once."""
    speed = 2.0
    contact = {"k": HC_K, "damping_law": "hunt_crossley", "dissipation": HC_DISSIPATION}
    for depth in (1e-4, 1e-6, 1e-8):
        scene = point_scene(contact, speed, 1e-4, 1e-4, depth=depth)
        _, fy, noise = force_of_one_step(scene, [0.0, -depth, 0.0, 0.0, -speed, 0.0])
        assert fy == pytest.approx(HC_K * depth * (1.0 + HC_DISSIPATION * speed), abs=noise), depth
    assert fy < 1e-3, "a hair of depth carries a hair of force"


# ---------------------------------------------------------------------------------------
# Unclamped: Fn = k d - c v_n

UC_K, UC_C = 1e4, 20.0               # zeta = c / (2 sqrt(k m)) = 0.1 on 1 kg
UC_DT = 1e-6
# The damper's force c v jumps on at touchdown and off at lift-off: RK4 places each within a
# step, an impulse error of c v h, so c h / m of the speed per crossing.
UC_CROSSING = 2 * UC_C * UC_DT / 1.0


def test_unclamped_damper_pulls_while_separating_fast():
    contact = {"k": UC_K, "c": UC_C, "damping_law": "unclamped"}
    depth, rising = 1e-3, 1.0        # c v = 20 N > k d = 10 N
    scene = point_scene(contact, -rising, 1e-4, 1e-4, depth=depth)
    _, fy, noise = force_of_one_step(scene, [0.0, -depth, 0.0, 0.0, rising, 0.0])
    assert fy == pytest.approx(UC_K * depth - UC_C * rising, abs=noise)
    assert fy < 0.0, "the unclamped law pulls the point down"
    _, clamped, noise = force_of_one_step(with_contact(scene, damping_law="linear"),
                                          [0.0, -depth, 0.0, 0.0, rising, 0.0])
    assert abs(clamped) <= noise, "the linear law at the same state does not pull"


def test_unclamped_restitution_is_the_textbook_spring_damper():
    zeta = UC_C / (2.0 * math.sqrt(UC_K))
    e = restitution(point_scene({"k": UC_K, "c": UC_C, "damping_law": "unclamped"}, 1.0, UC_DT, 0.04))
    assert e == pytest.approx(math.exp(-math.pi * zeta / math.sqrt(1.0 - zeta ** 2)), abs=UC_CROSSING)


# ---------------------------------------------------------------------------------------
# Ramp: Ft = -mu Fn clamp(alpha v, -1, 1)

RAMP_ALPHA = 10.0                    # s/m: the ramp is linear below 0.1 m/s
# Semi-implicit Euler integrates a constant deceleration exactly; what remains is the normal
# load's ripple after the start (the box's vertical speed stays within 3e-6 m/s at k = 1e6,
# and mu times it is the friction impulse it moves).
RAMP_DECEL = 1e-6
# As friction fades the box rocks back on its corner springs (a tilt ~ mu m g (h/2) / (k w^2 / 2)
# ~ 2e-5 rad at k = 1e6): its corners slip at vx - omega r_y, up to 4e-4 of vx over the fit.
RAMP_ROCKING = 1e-3


def test_ramp_box_decelerates_at_mu_g_then_decays_at_mu_g_alpha():
    h, mu, v0 = 1e-4, 0.5, 1.0
    scene = sliding_box({"friction_law": "ramp", "alpha": RAMP_ALPHA}, v0, h, 0.4)
    traj = simulate(scene)
    t_switch = (v0 - 1.0 / RAMP_ALPHA) / (mu * G)           # v0 - mu g t = 1 / alpha
    sliding = (traj.t > 0.02) & (traj.vx > 1.0 / RAMP_ALPHA + 0.05)
    decel = -np.polyfit(traj.t[sliding], traj.vx[sliding], 1)[0]
    assert decel == pytest.approx(mu * G, rel=RAMP_DECEL)
    switch = int(np.argmax(traj.vx <= 1.0 / RAMP_ALPHA))
    assert abs(switch - t_switch / h) <= 1.0, "the ramp's linear part starts where v = 1 / alpha"
    # below 1/alpha: v' = -mu g alpha v, which semi-implicit Euler maps by (1 - h mu g alpha) a step
    rate = mu * G * RAMP_ALPHA
    creeping = (np.arange(traj.t.size) > switch) & (traj.vx > 1e-3) & (traj.vx < 0.09)
    rocking = np.max(np.abs(traj.omega[creeping]) * 0.05 / traj.vx[creeping])
    assert rocking < RAMP_ROCKING, "the tolerance's premise: the corners slip with the body"
    fitted = -np.polyfit(traj.t[creeping], np.log(traj.vx[creeping]), 1)[0]
    assert fitted == pytest.approx(-math.log(1.0 - h * rate) / h, rel=RAMP_ROCKING)
    assert fitted == pytest.approx(rate, rel=RAMP_ROCKING + h * rate)   # the ODE's rate, to O(h rate)


# ---------------------------------------------------------------------------------------
# Smooth Coulomb: Ft = -mu Fn v / sqrt(v^2 + 1/alpha^2)

SC_K, SC_MU, SC_ALPHA = 1e4, 0.5, 100.0
SC_DEPTH = 1e-3                      # m: Fn = k d = 10 N at rest (compression law, v_n = 0)
# The slope at zero by central differences at alpha v = 1e-4: both laws' cubic terms (x^3 / 3,
# x^3 / 2) are x^2 = 1e-8 of the linear one.
SLOPE_FD = 1e-6


def slip_force(friction_law: str, slip: float) -> tuple[float, float]:
    """(Ft N, its round-off N) custom_sim applies to a point pressed in by SC_DEPTH, slipping at `slip`."""
    contact = {"k": SC_K, "mu": SC_MU, "friction_law": friction_law, "alpha": SC_ALPHA}
    scene = point_scene(contact, 0.0, 1e-4, 1e-4, effects=("contact", "friction"), depth=SC_DEPTH)
    fx, _, noise = force_of_one_step(scene, [0.0, -SC_DEPTH, 0.0, slip, 0.0, 0.0])
    return fx, noise


def test_smooth_coulomb_force_follows_its_formula():
    fn = SC_K * SC_DEPTH
    for slip in (-0.3, 1e-3, 1e-2, 0.05, 1.0):
        ft, noise = slip_force("smooth_coulomb", slip)
        assert ft == pytest.approx(-SC_MU * fn * slip / math.sqrt(slip ** 2 + 1.0 / SC_ALPHA ** 2), abs=noise), slip


def test_smooth_coulomb_and_ramp_have_the_tanh_slope_at_zero_slip():
    fn, dv = SC_K * SC_DEPTH, 1e-6
    expected = -SC_MU * fn * SC_ALPHA
    for law in ("tanh", "smooth_coulomb", "ramp"):
        slope = (slip_force(law, dv)[0] - slip_force(law, -dv)[0]) / (2 * dv)
        assert slope == pytest.approx(expected, rel=SLOPE_FD), law


# ---------------------------------------------------------------------------------------
# Bare sign friction and rolling: no stable step for an explicit method

SIGN_DTS = (1e-4, 3e-4, 1e-3)
SIGN_K = 1e5          # N/m: stiff enough that the box barely rocks, soft enough for h = 1e-3 s
# Where it should stick, every step kicks the slip by the whole mu (sum Fn) h / m; the loads sum
# to m (g + a_y), and the box's vertical acceleration a_y, the ripple of the rocking its stop
# started, stays within 1.2e-3 g (measured): the kick is mu g h to that.
SIGN_KICK = 2e-3


def corner_slips(states: np.ndarray) -> np.ndarray:
    """Slip vx - omega r_y of the box's two lower corners (rows: steps), the box 0.2 x 0.1 m."""
    out = []
    for lx in (-0.1, 0.1):
        ry = np.sin(states[:, 2]) * lx + np.cos(states[:, 2]) * -0.05
        out.append(states[:, 3] - states[:, 5] * ry)
    return np.array(out).T


@pytest.mark.parametrize("dt", SIGN_DTS)
def test_sign_friction_chatters_at_any_step(dt):
    mu, v0 = 0.5, 0.05
    scene = sliding_box({"friction_law": "sign"}, v0, dt, 0.3, k=SIGN_K)
    with pytest.raises(SimulationChattered) as caught:
        simulate(scene)
    assert caught.value.quantity == "slip velocity"
    assert caught.value.stable_dt == 0.0 and "No step size is stable for this law" in str(caught.value)
    assert "friction_law 'sign'" in str(caught.value)
    stepper = Stepper(scene, watch_chatter=False)
    states = np.array([stepper.advance(1).copy() for _ in range(scene.steps)])
    stopped = np.arange(scene.steps) * dt > v0 / (mu * G) + 0.05      # mu g decelerates it in 10 ms
    slips = corner_slips(states[stopped])
    assert np.all(slips[1:] * slips[:-1] < 0.0), "the slip flips sign at every step"
    kick, lift = np.abs(np.diff(states[stopped, 3])), np.diff(states[stopped, 4])
    # semi-implicit Euler: h sum(Fn) / m = dvy + g h, and the slip loses mu of that, whole
    balance = mu * (lift + G * dt)
    assert np.all(np.abs(kick - balance) <= ROUNDOFF_ULPS * EPS * (np.abs(states[stopped, 3][1:]) + balance))
    assert np.allclose(kick, mu * G * dt, rtol=SIGN_KICK), "each flip is one whole Coulomb kick"
    assert kick[-10:].min() >= (1.0 - SIGN_KICK) * mu * G * dt, "it never settles"


def test_sign_friction_under_rk4_creeps_instead():
    """RK4's stages straddle the jump: for a slip v below mu g h / 2 they cancel (-1 + 2 - 2 + 1),
    and the box creeps on at a constant speed: no stable step either, but no chatter."""
    h, mu = 1e-3, 0.5
    scene = sliding_box({"friction_law": "sign"}, 0.05, h, 0.3, k=1e4, integrator="rk4")
    late = simulate(scene).vx[-100:]
    assert np.all(late > 0.0) and late.max() < mu * G * h / 2
    assert np.all(np.abs(np.diff(late)) < 1e-2 * late[-1]), "a creep, not a decay to rest"
    assert stable_step(scene) == 0.0 and "creeps" in stable_step(scene).reason


# Semi-implicit Euler integrates the constant deceleration of rolling exactly, and the tanh
# friction's slip (constant while the deceleration is) moves nothing: round-off of the fit.
ROLL_DECEL = 1e-9


def test_sign_rolling_law_decelerates_a_disk_at_2_mu_roll_g_over_3_r_then_chatters():
    base = load("rolling_circle")
    scene = with_contact(base, roll_law="sign", roll_sharpness=None)
    traj = simulate(scene)
    rolling = traj.t > 0.5                                  # the slide ends at v0 / (3 mu g) = 0.23 s
    decel = -np.polyfit(traj.t[rolling], traj.vx[rolling], 1)[0]
    expected = 2.0 * scene.contact.mu_roll * G / (3.0 * scene.body.radius)
    assert decel == pytest.approx(expected, rel=ROLL_DECEL)
    stop = traj.vx[-1] / expected                           # it rolls on for (4/3 - a t) / a
    with pytest.raises(SimulationChattered) as caught:
        simulate(dataclasses.replace(scene, duration=scene.duration + stop + 1.0))
    assert "roll_law 'sign'" in str(caught.value) and "No step size is stable" in str(caught.value)


def test_implicit_euler_under_the_sign_stopped_by_chatter_says_why_not_a_step():
    """Implicit Euler has no step limit under a bare sign law (theory's stable step is inf), so a
    chatter there cannot be answered with a smaller step: the message says what does happen (its
    Newton ends on the jump, not on the set-valued stick) and never offers "a stable step below
    inf s"."""
    from custom_sim.runner import SimulationChattered as Chattered

    for scene, law in ((with_contact(load("t_shape_drop"), friction_law="sign", alpha=None), "friction_law 'sign'"),
                       (with_contact(load("rolling_circle"), roll_law="sign", roll_sharpness=None), "roll_law 'sign'")):
        scene = dataclasses.replace(scene, integrator="implicit_euler")
        assert stable_step(scene) == math.inf
        text = str(Chattered(scene, "implicit_euler", scene.dt, 10, np.zeros(6), 0, "slip velocity"))
        assert law in text and "no root where a point should stick" in text and "regularised law" in text
        assert "inf s" not in text
    tanh = dataclasses.replace(load("t_shape_drop"), integrator="implicit_euler")
    text = str(Chattered(tanh, "implicit_euler", tanh.dt, 10, np.zeros(6), 0, "slip velocity"))
    assert "puts no limit on the step" in text and "inf s" not in text


@pytest.mark.slow
def test_t_shape_resting_on_two_points_under_the_sign_chatters_under_implicit_euler():
    """The T of t_shape_drop under the sign comes to rest on a bar end and the stem's foot; the
    set-valued law would hold both stuck, but implicit Euler's Newton lands on alternate sides
    of the jump, and the run stops as chatter, explained (about 5 s)."""
    scene = dataclasses.replace(with_contact(load("t_shape_drop"), friction_law="sign", alpha=None),
                                integrator="implicit_euler")
    with pytest.raises(SimulationChattered) as caught:
        simulate(scene)
    assert "no root where a point should stick" in str(caught.value) and "inf s" not in str(caught.value)


# ---------------------------------------------------------------------------------------
# Stability theory per law


def test_ramp_and_smooth_coulomb_have_the_tanh_friction_limit():
    base = load("box_drop")
    for integrator in ("explicit_euler", "semi_implicit_euler", "rk4"):
        tanh = limits(base, integrator)["friction"]
        for law in ("ramp", "smooth_coulomb"):
            scene = with_contact(base, friction_law=law)
            assert limits(scene, integrator)["friction"] == tanh, (law, integrator)
            assert friction_rate(scene) == friction_rate(base)


def test_unclamped_has_the_linear_laws_limits():
    base = load("box_drop")           # a linear law
    for integrator in ("explicit_euler", "semi_implicit_euler", "rk4"):
        assert limit_modes(with_contact(base, damping_law="unclamped"), integrator) == limit_modes(base, integrator)


@pytest.mark.parametrize("integrator", ["explicit_euler", "semi_implicit_euler", "rk4"])
def test_bare_sign_laws_have_no_stable_explicit_step(integrator):
    box = with_contact(load("box_slide"), friction_law="sign", alpha=None)
    disk = with_contact(load("rolling_circle"), roll_law="sign", roll_sharpness=None)
    for scene, law in ((box, "friction_law 'sign'"), (disk, "roll_law 'sign'")):
        step = stable_step(scene, integrator)
        assert step == 0.0 and law in step.reason and "no step size is stable" in step.reason
        assert law in warning(scene, integrator)
        assert stable_step(scene, "implicit_euler") == math.inf
        assert warning(scene, "implicit_euler") is None


# Theory returns the grid point of stability.HW_GRID (5e-4 apart) below the limit.
THEORY_GRID = 1e-3


def test_hunt_crossley_damps_at_the_impact_peak_depth():
    """Semi-implicit Euler on a damped oscillator: h w < 2 (sqrt(1 + zeta^2) - zeta) (Jury), at
    the damper k d D of the deepest point of the impact (found here with scipy) for a point
    dropped without gravity."""
    speed, k, dissipation = 3.0, 1e4, 2.0
    scene = point_scene({"k": k, "damping_law": "hunt_crossley", "dissipation": dissipation}, speed, 1e-4, 0.05,
                        integrator="semi_implicit_euler")
    turn = lambda t, s: s[1]   # noqa: E731 - the deepest point: x' = 0
    turn.terminal = True
    sol = solve_ivp(lambda t, s: [s[1], -k * s[0] * (1.0 + dissipation * s[1])], (0.0, 1.0), [0.0, speed],
                    method="DOP853", rtol=1e-12, atol=1e-15, events=turn)
    depth, w = sol.y_events[0][0][0], math.sqrt(k)
    zeta = k * depth * dissipation / (2.0 * math.sqrt(k))
    jury = 2.0 * (math.sqrt(1.0 + zeta ** 2) - zeta) / w
    assert stable_step(scene) == pytest.approx(jury, rel=THEORY_GRID)


def test_hunt_crossley_at_rest_under_explicit_euler_is_stable_below_depth_times_dissipation():
    """At rest the damper is k d0 D (d0 = m g / k): explicit Euler keeps |1 + h lambda| < 1 for
    h < c / k = d0 D. Theory says so, and a run just below decays, one just above grows."""
    k, dissipation = 1e4, 2.0
    d0 = G / k
    limit = d0 * dissipation
    contact = {"k": k, "damping_law": "hunt_crossley", "dissipation": dissipation}
    scene = point_scene(contact, 0.0, 1e-4, 1.0, integrator="explicit_euler", effects=("gravity", "contact"),
                        depth=d0)
    assert limit_modes(scene)["contact (hunt_crossley damper at the rest depth)"] == pytest.approx(
        limit, rel=THEORY_GRID)
    assert stable_step(scene) <= limit * (1.0 + THEORY_GRID)
    for factor, grows in ((0.9, False), (1.1, True)):
        h = factor * limit
        run = dataclasses.replace(scene, dt=h, duration=2000 * h,
                                  initial=dataclasses.replace(scene.initial, position=(0.0, -d0 + 1e-6)))
        traj = simulate(run)
        early, late = np.abs(traj.vy[:200]).max(), np.abs(traj.vy[-200:]).max()
        assert (late > 10 * early) if grows else (late < 0.1 * early), factor


# ---------------------------------------------------------------------------------------
# One step of every law and integrator against the force written here

LAW_CASES = {   # effect laws on top of compression damping and tanh friction
    "compression": {"damping_law": "compression", "c": 50.0},
    "linear": {"damping_law": "linear", "c": 50.0},
    "unclamped": {"damping_law": "unclamped", "c": 50.0},
    "hunt_crossley": {"damping_law": "hunt_crossley", "dissipation": 2.0},
    "ramp": {"friction_law": "ramp", "alpha": 5.0},
    "smooth_coulomb": {"friction_law": "smooth_coulomb", "alpha": 5.0},
    "sign": {"friction_law": "sign"},
    "roll tanh": {"roll_law": "tanh", "roll_sharpness": 50.0},
    "roll sign": {"roll_law": "sign"},
}
BOX, DISK = (0.2, 0.1), 0.1        # m


def law_scene(case: str, integrator: str, h: float = 1e-4, initial: dict | None = None):
    """A box (or, for the rolling laws, a disk) under LAW_CASES[case]; the other laws the seed's
    (compression with c = 50 N s/m, tanh with alpha = 20 s/m)."""
    contact = {"k": 1e4, "mu": 0.6, "mu_roll": 0.004, **LAW_CASES[case]}
    if contact.get("damping_law") != "hunt_crossley":
        contact.setdefault("c", 50.0)
    if contact.get("friction_law") != "sign":
        contact.setdefault("alpha", 20.0)
    disk = case.startswith("roll")
    body = ({"shape": "circle", "mass": 0.8, "radius": DISK} if disk
            else {"shape": "box", "mass": 1.2, "size": list(BOX)})
    effects = ["gravity", "contact", "friction"] + (["rolling_friction"] if disk else [])
    return parse_scene({"duration": h, "dt": h, "integrator": integrator, "effects": effects, "body": body,
                        "contact": contact, "initial": initial or {"position": [0.0, 1.0]}}, file="<test>")


def arms(scene, theta):
    """The contact points' arms r (n, 2) at angle theta: a box's corners turn, the disk's point stays below."""
    if scene.body.shape == "circle":
        return np.array([[0.0, -DISK]])
    c, s = math.cos(theta), math.sin(theta)
    corners = [(sx * BOX[0] / 2, sy * BOX[1] / 2) for sx in (-1, 1) for sy in (-1, 1)]
    return np.array([(c * lx - s * ly, s * lx + c * ly) for lx, ly in corners])


def hand_normal(ct, d, vn):
    if ct.damping_law == "compression":
        return ct.k * d + ct.c * max(0.0, -vn)
    if ct.damping_law == "linear":
        return max(0.0, ct.k * d - ct.c * vn)
    if ct.damping_law == "unclamped":
        return ct.k * d - ct.c * vn
    return max(0.0, ct.k * d * (1.0 - ct.dissipation * vn))          # hunt_crossley


def hand_friction(ct, fn, v):
    if ct.friction_law == "tanh":
        return -ct.mu * fn * math.tanh(ct.alpha * v)
    if ct.friction_law == "ramp":
        return -ct.mu * fn * min(1.0, max(-1.0, ct.alpha * v))
    if ct.friction_law == "smooth_coulomb":
        return -ct.mu * fn * v / math.sqrt(v * v + 1.0 / ct.alpha ** 2)
    return -ct.mu * fn * float(np.sign(v))                            # sign


def hand_roll(ct, fn, om):
    shape = math.tanh(ct.roll_sharpness * om) if ct.roll_law == "tanh" else float(np.sign(om))
    return -ct.mu_roll * fn * shape


def hand_acceleration(scene, z):
    """(a (3,), the size of its terms (3,)): gravity and each touching point's law, from the formulas."""
    ct, m = scene.contact, scene.body.mass
    inertia = m * (BOX[0] ** 2 + BOX[1] ** 2) / 12 if scene.body.shape == "box" else m * DISK ** 2 / 2
    force, size = np.array([0.0, -m * G, 0.0]), np.array([0.0, m * G, 0.0])
    for rx, ry in arms(scene, z[2]):
        d = -(z[1] + ry)
        if d <= 0.0:
            continue
        fn = hand_normal(ct, d, z[4] + z[5] * rx)
        ft = hand_friction(ct, fn, z[3] - z[5] * ry)
        roll = hand_roll(ct, fn, z[5]) if scene.has("rolling_friction") else 0.0
        force += (ft, fn, rx * fn - ry * ft + roll)
        size += (abs(ft), abs(fn), abs(rx * fn) + abs(ry * ft) + abs(roll))
    inv = np.array([1.0 / m, 1.0 / m, 1.0 / inertia])
    return force * inv, size * inv


def hand_step(scene, z0):
    """One step of the scene's integrator with hand_acceleration, and the force terms' size (3,)."""
    h, q, v = scene.dt, z0[:3], z0[3:]
    a, size = hand_acceleration(scene, z0)
    if scene.integrator == "explicit_euler":
        return np.concatenate([q + h * v, v + h * a]), size
    if scene.integrator == "semi_implicit_euler":
        v1 = v + h * a
        return np.concatenate([q + h * v1, v1]), size
    f = lambda z: np.concatenate([z[3:], hand_acceleration(scene, z)[0]])   # noqa: E731
    k1 = f(z0)
    k2 = f(z0 + h / 2 * k1)
    k3 = f(z0 + h / 2 * k2)
    k4 = f(z0 + h * k3)
    return z0 + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4), size


def touching_states(scene, count: int, seed: int):
    """States with a point 0.2 to 3 mm deep and every point at least 0.2 mm from the ground (no
    point touches down or leaves within a step), slips above 0.05 m/s and spins above 0.3 rad/s
    (the sign laws' kick, h mu Fn / m_t ~ 5e-3 m/s, cannot reverse them within a step)."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < count:
        theta = rng.uniform(-0.5, 0.5) if scene.body.shape == "box" else 0.0
        r = arms(scene, theta)
        z = np.array([0.0, -r[:, 1].min() - rng.uniform(2e-4, 3e-3), theta,
                      rng.uniform(-1, 1), rng.uniform(-0.3, 0.3), rng.uniform(-2, 2)])
        depth = -(z[1] + r[:, 1])
        slip = z[3] - z[5] * r[:, 1]
        if np.abs(depth).min() < 2e-4 or np.abs(slip[depth > 0]).min() < 0.05 or abs(z[5]) < 0.3:
            continue
        out.append(z)
    return out


def custom_step(scene, z0):
    stepper = Stepper(scene, watch_chatter=False)
    stepper.reset(z0)
    return stepper.advance(1).copy()


@pytest.mark.parametrize("integrator", list(INTEGRATORS))
@pytest.mark.parametrize("case", list(LAW_CASES))
def test_one_step_of_every_law_against_the_formula_written_here(case, integrator):
    scene = law_scene(case, integrator)
    h = scene.dt
    for z0 in touching_states(scene, 12, seed=list(LAW_CASES).index(case)):
        z1 = custom_step(scene, z0)
        if integrator == "implicit_euler":   # v1 = v0 + h a(q0 + h v1, v1)
            a, _ = hand_acceleration(scene, z1)
            assert np.abs(z1[3:] - z0[3:] - h * a).max() <= IMPLICIT_RESIDUAL, (case, z0)
            assert np.allclose(z1[:3], z0[:3] + h * z1[3:], rtol=0.0, atol=ROUNDOFF_ULPS * EPS), (case, z0)
            continue
        expected, size = hand_step(scene, z0)
        scale = np.concatenate([np.abs(z0[:3]) + h * np.abs(z0[3:]) + h * h * size, np.abs(z0[3:]) + h * size])
        assert np.all(np.abs(z1 - expected) <= ROUNDOFF_ULPS * EPS * scale), (case, z0, z1 - expected)


# ---------------------------------------------------------------------------------------
# The analytic Jacobian of every law (implicit Euler's), against central differences

FD_STEP = 1e-7        # central differences on O(1) states: truncation ~1e-14 f''', round-off
FD_REL = 1e-5         # ~1e-16 |f| / 1e-7 = 1e-9 |f|: 1e-5 relative is safe (accelerations ~1e2..1e3)
KINK_MARGIN = 1e-4    # a state this close to a kink or jump is skipped (FD_STEP could cross it)


def near_a_kink(scene, z) -> bool:
    """True near a contact switch, a clamp, the compression damper's v_n = 0, the ramp's
    |alpha v| = 1, a sign law's v = 0 (any law: its derivative jumps there)."""
    ct = scene.contact
    if scene.has("rolling_friction") and abs(z[5]) < KINK_MARGIN:
        return True
    for rx, ry in arms(scene, z[2]):
        d, vn, slip = -(z[1] + ry), z[4] + z[5] * rx, z[3] - z[5] * ry
        if abs(d) < KINK_MARGIN:
            return True
        if d > 0 and (abs(vn) < KINK_MARGIN or abs(slip) < KINK_MARGIN
                      or (ct.alpha and abs(abs(ct.alpha * slip) - 1.0) < KINK_MARGIN * ct.alpha)
                      or abs(hand_normal(ct, d, vn)) < KINK_MARGIN * ct.k):
            return True
    return False


@pytest.mark.parametrize("case", [c for c in LAW_CASES if c not in ("compression", "linear")])
def test_jacobian_of_every_law_against_finite_differences(case):
    from custom_sim.forces import acceleration_jacobian, accelerations
    from custom_sim.model import build_model

    scene = law_scene(case, "implicit_euler")
    model, points = build_model(scene)
    rng = np.random.default_rng(11)
    jac, checked = np.zeros((3, 6)), 0
    for _ in range(80):
        theta = rng.uniform(-0.6, 0.6) if scene.body.shape == "box" else 0.0
        z = np.array([0.0, -arms(scene, theta)[:, 1].min() - rng.uniform(-2e-3, 5e-3), theta,
                      rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), rng.uniform(-3, 3)])
        if near_a_kink(scene, z):
            continue
        acceleration_jacobian(model, points, z, jac)
        fd = np.zeros((3, 6))
        for j in range(6):
            dz = np.zeros(6)
            dz[j] = FD_STEP
            fd[:, j] = (np.array(accelerations(model, points, z + dz, 0.0, 0.0, 0.0))
                        - np.array(accelerations(model, points, z - dz, 0.0, 0.0, 0.0))) / (2 * FD_STEP)
        assert np.allclose(jac, fd, rtol=FD_REL, atol=FD_REL * (np.abs(fd).max() + 1)), (case, z)
        checked += 1
    assert checked >= 40, f"only {checked} of 80 states away from kinks"


# ---------------------------------------------------------------------------------------
# The batched loop reads every law as simulate does; the seed's law did not move a bit


def test_batch_runs_every_law_as_simulate_does():
    from custom_sim.batch import _FLOATS, _SWITCHES, simulate_batch
    from custom_sim.model import Model

    assert _FLOATS + _SWITCHES == Model._fields, "the batch builds Model by position"
    scenes = []
    for case, integrator in (("unclamped", "rk4"), ("hunt_crossley", "implicit_euler"),
                             ("ramp", "semi_implicit_euler"), ("smooth_coulomb", "explicit_euler"),
                             ("sign", "implicit_euler"), ("roll sign", "implicit_euler"), ("roll tanh", "rk4")):
        lowest = DISK if case.startswith("roll") else BOX[1] / 2       # m below the centre of mass
        start = {"position": [0.0, lowest + 0.01], "velocity": [0.8, -0.5], "angular_velocity": 1.0}
        scenes.append(dataclasses.replace(law_scene(case, integrator, 5e-5, start), duration=0.05))
    for scene, run in zip(scenes, simulate_batch(scenes, threads=2)):
        traj = simulate(scene)
        assert np.array_equal(run.states, traj.states()), (scene.contact, scene.integrator)


# sha256 of the float64 states of each run, computed with custom_sim before the other laws came
# (numba 0.68.1 on x86-64, at commit 2854bb7): the seed's trajectories, to the bit.
# A libm whose tanh rounds differently would change them; custom_sim's own code must not.
SEED_HASHES = {
    ("box_drop", "explicit_euler"): "b1fbfccbfe5e06178f51ad2642387b92e9555a1624140a5cd3f576fb578d03f9",
    ("box_drop", "semi_implicit_euler"): "56058a5620da28c03517915c48420a48a73e837cd1fdbeb01b19a8e0eb08e331",
    ("box_drop", "implicit_euler"): "163f82240afc98ea7822a8bb0a6f3b7f69e5e12b669490c56a3c1c26aa730506",
    ("box_drop", "rk4"): "8f805cb7e39e0eb95f549051b92947853d3289c9293fa3cc4bce43221aa504ce",
    ("rolling_circle", "explicit_euler"): "e89dc0b1026688dd3d9df19ee3ca95e808a535c1bcac83661b3cf21fc83cf750",
    ("rolling_circle", "semi_implicit_euler"): "8084719f82f60c98dcb12e055241c5d70cd2c74697eec3fa08f785f17f9e4ecc",
    ("rolling_circle", "implicit_euler"): "3f0e77d17410526f2c607be5fc6d4d2c7663128ff042f12fa28f93d24875b6cf",
    ("rolling_circle", "rk4"): "69e2e260cd44c7fe1df4d47369d6b1b0ead27fa9a07689bedff55ad426c6d6d6",
}


@pytest.mark.parametrize("name,integrator", list(SEED_HASHES))
def test_the_seed_laws_trajectories_are_bit_identical_to_before(name, integrator):
    states = simulate(dataclasses.replace(load(name), integrator=integrator)).states()
    digest = hashlib.sha256(np.ascontiguousarray(states, dtype=np.float64).tobytes()).hexdigest()
    assert digest == SEED_HASHES[(name, integrator)]
