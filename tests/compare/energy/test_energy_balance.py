"""The work-energy balance (compare/energy, docs/energy-balance.md) against closed forms,
exact motions and the integrators' known energy errors."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import custom_sim
from compare.energy import balance, metrics_block
from compare.energy.column import energy_column_check
from compare.energy.law import accelerations, body_of, loads
from compare.energy.terms import energy_terms
from compare.scenarios import load
from custom_sim import parse_scene
from scene_types.trajectory import read_csv, write_csv

EULERS = ("explicit_euler", "semi_implicit_euler", "implicit_euler")
# An order measured from one halving of h, log2(R(h) / R(h/2)), differs from the asymptotic
# order p by about log2(1 + s), s the next order's share of R at the larger step. On the
# oscillator s is at most 2.5 h wn (its measured remainders), below 0.1 on every ladder here
# (h wn <= 0.03 for the Euler methods, <= 0.06 for RK4): log2(1.1) = 0.14.
ORDER_SLACK = 0.15
EPS = np.finfo(float).eps
# the native balance from states against MuJoCo's rows: the two read a contact's depth
# differently (MuJoCo's collision distance, the states' geometry), which moves the stored
# k d^2 / 2 by ~2e-7 J on box_drop and R by ~5e-9 J; agreement to a ten-thousandth of R's
# largest value says both measure the same integrator error
FROM_STATES_AGREEMENT = 1e-4
DYNAMICS_TOLERANCE = 1e-9      # m: the dynamics check's bound between custom_sim and the dynamics twin
# the penalty mapping's relative force error on a box (README, physics.md section 7): it moves
# the native twin's resting depth m g / (2 k) by that fraction, and its energy with it
MAPPING_FORCE_ERROR = 5e-4

# the damped oscillator: a point mass resting on the contact spring, linear law, never leaving
M, K, C, G = 0.5, 1e4, 20.0, 9.81
A = 1e-4                                  # m below the rest depth m g / k = 4.9e-4 m: stays touching
WN = math.sqrt(K / M)
SIGMA = C / (2 * M)
WD = math.sqrt(WN ** 2 - SIGMA ** 2)
Y_REST = -M * G / K
T_PHASE = 0.028   # s: wd T = 3.9 rad, where v (y - y_rest) is large (a multiple of every step below)


def oscillator(integrator="semi_implicit_euler", dt=1e-4, duration=T_PHASE):
    """The oscillator as a scene: a point mass pressed A below its rest depth, released at rest."""
    return parse_scene({"duration": duration, "dt": dt, "integrator": integrator, "effects": ["gravity", "contact"],
                        "body": {"shape": "point", "mass": M, "contact_height": 0.0},
                        "contact": {"k": K, "c": C, "damping_law": "linear"},
                        "initial": {"position": [0.0, Y_REST - A]}})


def exact(t):
    """(y, vy, ay) of the oscillator's exact motion, released at rest A below its rest depth."""
    t = np.asarray(t, dtype=float)
    e = np.exp(-SIGMA * t)
    y = Y_REST - A * e * (np.cos(WD * t) + SIGMA / WD * np.sin(WD * t))
    v = A * WN ** 2 / WD * e * np.sin(WD * t)
    return y, v, (-K * (y - Y_REST) - C * v) / M


def exact_damping_work(t):
    """c int_0^t v^2 ds of the exact motion, in closed form (J)."""
    t = np.asarray(t, dtype=float)
    s = complex(-2 * SIGMA, 2 * WD)
    mean = (1 - np.exp(-2 * SIGMA * t)) / (4 * SIGMA)
    wave = 0.5 * np.real((np.exp(s * t) - 1) / s)
    return C * (A * WN ** 2 / WD) ** 2 * (mean - wave)


def run(scene, integrator=None, **changes):
    scene = dataclasses.replace(scene, integrator=integrator or scene.integrator, **changes)
    traj = custom_sim.simulate(scene)
    return scene, traj, balance(scene, traj.t, traj.states(), scene.integrator)


def orders(values):
    values = np.abs(np.asarray(values))
    return np.log2(values[:-1] / values[1:])


def test_exact_oscillator_loses_the_closed_form_work():
    """The exact motion sampled finely, W by the trapezoid rule (integrator unknown): W is
    c int v^2 in closed form and R = 0, both to the rule's stated bound, which shrinks as h^2."""
    errors = []
    for h in (2e-5, 1e-5):
        t = np.arange(round(0.2 / h) + 1) * h
        y, v, _ = exact(t)
        states = np.zeros((len(t), 6))
        states[:, 1], states[:, 4] = y, v
        b = balance(oscillator(dt=h, duration=0.2), t, states)
        assert b.rule.startswith("the trapezoid rule")
        closed = exact_damping_work(t)
        assert np.all(b.W[:, 1:] == 0.0)
        assert abs(b.W[-1, 0] - closed[-1]) <= b.quadrature_bound
        assert np.max(np.abs(b.R)) <= b.quadrature_bound   # the states are exact: R is the rule's error
        errors.append(np.max(np.abs(b.W[:, 0] - closed)))
    assert closed[-1] > 0.99 * K * A ** 2 / 2     # nearly all of the spring's start energy went
    assert orders(errors)[0] >= 2 - ORDER_SLACK


LAW_CASES = ([(d, "tanh", None) for d in ("compression", "linear", "unclamped", "hunt_crossley")]
             + [("linear", f, None) for f in ("ramp", "smooth_coulomb", "sign")]
             + [("linear", "tanh", r) for r in ("tanh", "sign")])


def tumbling(damping, friction, roll, dt=1e-4):
    """A box landing on a corner while it turns (a spinning disk with a rolling law), 0.3 s."""
    contact = {"k": 1e4, "mu": 0.5, "damping_law": damping, "friction_law": friction}
    contact.update({"dissipation": 0.5} if damping == "hunt_crossley" else {"c": 20.0})
    contact.update({} if friction == "sign" else {"alpha": 100.0})
    body = {"shape": "box", "mass": 1.0, "size": [0.2, 0.1]}
    initial = {"position": [0.0, 0.12], "velocity": [0.5, -1.0], "angle": 0.3, "angular_velocity": 2.0}
    effects = ["gravity", "contact", "friction"]
    if roll:
        body = {"shape": "circle", "mass": 1.0, "radius": 0.1}
        initial = {"position": [0.0, 0.12], "velocity": [1.0, -1.0], "angular_velocity": 5.0}
        effects.append("rolling_friction")
        contact.update({"mu_roll": 0.01, "roll_law": roll}, **({"roll_sharpness": 100.0} if roll == "tanh" else {}))
    return parse_scene({"duration": 0.3, "dt": dt, "effects": effects, "body": body, "contact": contact,
                        "initial": initial})


@pytest.mark.parametrize("damping, friction, roll", LAW_CASES)
def test_each_law_keeps_the_exact_balance(damping, friction, roll):
    """dE/dt = (Fn - k d) v_n + Ft v_slip + tau omega holds for every law, clamps and pulls
    included: the motion integrated exactly (DOP853, rtol 1e-10, whose error is far below the
    bound) keeps R within the trapezoid rule's bound."""
    scene = tumbling(damping, friction, roll)
    rb = body_of(scene)

    def rhs(_, z):
        Z = z[None, :]
        return np.concatenate([z[3:], accelerations(scene, rb, Z, loads(scene, rb, Z))[0]])

    i = scene.initial
    z0 = [*i.position, i.angle, *i.velocity, i.angular_velocity]
    sol = solve_ivp(rhs, (0.0, 0.3), z0, method="DOP853", rtol=1e-10, atol=1e-12, dense_output=True)
    t = np.linspace(0.0, 0.3, 60001)
    b = balance(scene, t, sol.sol(t).T)
    lost = b.E[0] - b.E[-1]
    assert lost > 0.5 and b.W[-1, 0] > 0.3 and b.W[-1, 1] > 0.2
    assert not roll or b.W[-1, 2] > 0.1
    assert np.max(np.abs(b.R)) <= b.quadrature_bound
    # sharp enough to see a clamp miscounted: the spring energy k d^2 / 2 at the clamp,
    # d = c v_n / k ~ 2 mm at 1 m/s, is 0.02 J, ten times this
    assert b.quadrature_bound < 2e-3 * lost


@pytest.mark.parametrize("damping, friction, roll", LAW_CASES)
def test_each_law_reproduces_custom_sims_steps(damping, friction, roll):
    """custom_sim under every law and integrator: the balance's own law (compare/energy/law.py)
    takes each recorded step again to round-off, so each rule counts the load custom_sim
    applied (implicit Euler's bare sign law: the value of its set the step took). RK4's R, of
    order h^2 per contact event, is below semi-implicit Euler's, of order h, by about h wn
    (3e-3 here) and so below a hundredth of it; semi-implicit Euler's stays below explicit
    Euler's, which only grows."""
    scene = tumbling(damping, friction, roll, dt=2e-5)
    R = {}
    for integrator in (*EULERS, "rk4"):
        _, traj, b = run(scene, integrator)
        assert np.max(b.step_mismatch) <= 64 * EPS * np.max(np.abs(traj.states())), (integrator, b.step_mismatch)
        R[integrator] = np.max(np.abs(b.R))
    assert R["rk4"] < 1e-2 * R["semi_implicit_euler"]
    assert R["semi_implicit_euler"] < R["explicit_euler"]


def test_integrators_energy_error_at_their_order_on_a_smooth_stretch():
    """The oscillator mid-swing (no contact switch): R(T) of explicit, semi-implicit and implicit
    Euler is first order with the leading terms derived in docs/energy-balance.md, evaluated on
    the exact motion (their remainder is second order), and RK4's is fourth order."""
    y, v, a = exact(T_PHASE)
    t = np.linspace(0.0, T_PHASE, 200001)
    _, vv, aa = exact(t)
    spread = np.trapezoid(M * aa ** 2 + K * vv ** 2, t)        # int |Q|^2/m + v^T H v dt
    conservative_power = v * (-K * y - M * G)                   # v . Q_c at T (0 at the start)
    first_order = {"explicit_euler": 0.5 * spread, "implicit_euler": -0.5 * spread,
                   "semi_implicit_euler": -0.5 * conservative_power + 0.5 * C * v * v / 2}
    steps = (2e-4, 1e-4, 5e-5, 2.5e-5)
    for integrator in EULERS:
        R = np.array([run(oscillator(integrator, h))[2].R[-1] for h in steps])
        predicted = first_order[integrator] * np.array(steps)
        assert np.all(np.abs(orders(R) - 1) <= ORDER_SLACK), (integrator, orders(R))
        assert np.all(orders(R - predicted) >= 2 - ORDER_SLACK), (integrator, orders(R - predicted))
    R = [run(oscillator("rk4", h))[2].R[-1] for h in (4e-4, 2e-4, 1e-4, 5e-5)]
    assert np.all(np.abs(orders(R) - 4) <= ORDER_SLACK), orders(R)


def test_sliding_block_friction_work_is_its_kinetic_energy():
    """box_slide (tanh friction) stops at its start height: friction took its kinetic energy but
    for the pitch the friction's torque tau = mu m g h/2 excites twice (at the start and at the
    stop, a load step on the corners' rotational spring k w^2 / 2 dissipates at most
    tau^2 / (2 k_rot) each) and R; R is first order for the Euler methods and fourth for RK4."""
    scene = load("box_slide")
    ct, (w, height), m = scene.contact, scene.body.size, scene.body.mass
    kinetic = 0.5 * m * scene.initial.velocity[0] ** 2
    tau = ct.mu * m * scene.g * height / 2
    pitch = tau ** 2 / (ct.k * w ** 2 / 2)
    _, traj, b = run(scene)
    assert abs(traj.vx[-1]) < 1e-9
    assert abs(b.W[-1, 1] - kinetic) <= pitch + abs(b.R[-1])
    assert b.W[-1, 0] <= pitch
    for integrator in EULERS:
        R = [run(scene, integrator, dt=scene.dt / 2 ** j)[2].R[-1] for j in range(3)]
        assert np.all(np.abs(orders(R) - 1) <= ORDER_SLACK), (integrator, R)
        assert np.sign(R[0]) == (1 if integrator == "explicit_euler" else -1)
    R = [run(scene, "rk4", dt=h)[2].R[-1] for h in (4e-4, 2e-4, 1e-4)]
    assert np.all(np.abs(orders(R) - 4) <= ORDER_SLACK), R


def test_rolling_resistance_accounts_for_the_energy_a_rolling_disk_loses():
    """rolling_circle: W_rolling is mu_roll m g times the angle rolled, less what the tanh
    regularisation leaves out while the disk spins up (pi^2 / 24 mu_roll m g / (S^2 w'), w' the
    spin-up rate, between 2 (mu R - mu_roll) g / R^2 and 2 mu g / R); once the disk rolls, the
    energy it loses is W_rolling plus the friction's creep, Ft^2 / (mu m g alpha), Ft =
    2 m mu_roll g / (3 R), to tanh's next order (Ft / (mu m g))^2, and R."""
    scene = load("rolling_circle")
    ct, m, radius, g = scene.contact, scene.body.mass, scene.body.radius, scene.g
    regularised = [ct.mu_roll * m * g * math.pi ** 2 / 24 / (ct.roll_sharpness ** 2 * rate)
                   for rate in (2 * ct.mu * g / radius, 2 * (ct.mu * radius - ct.mu_roll) * g / radius ** 2)]
    _, traj, b = run(scene, "rk4")
    short = ct.mu_roll * m * g * abs(traj.theta[-1] - traj.theta[0]) - b.W[-1, 2]
    assert min(regularised) <= short <= max(regularised)
    for integrator in ("semi_implicit_euler", "rk4"):
        _, traj, b = run(scene, integrator)
        i = int(round(0.5 / scene.dt))                         # rolling since 0.24 s
        force = 2 * m * ct.mu_roll * g / (3 * radius)
        creep = force ** 2 / (ct.mu * m * g * ct.alpha) * (traj.t[-1] - traj.t[i])
        lost = b.E[i] - b.E[-1]
        rolling = b.W[-1, 2] - b.W[i, 2]
        assert rolling > 0.99 * lost
        assert abs(lost - rolling - creep) <= creep * (force / (ct.mu * m * g)) ** 2 + abs(b.R[-1] - b.R[i])


def test_semi_implicit_euler_stays_bounded_for_a_million_steps_and_explicit_euler_grows():
    """The undamped bounce, 1e6 steps of 1e-5 s: semi-implicit Euler's R is -(h/2) (v . Q_c)
    (its modified energy), bounded, to the next order (h wn of it); explicit Euler's grows at
    every step (h^2 |Q|^2 / 2m plus the spring's convexity, both >= 0) by (h/2) int (|Q|^2/m +
    k v_n^2) dt to the next order."""
    scene = dataclasses.replace(load("elastic_bounce"), dt=1e-5, duration=10.0)
    wn = math.sqrt(scene.contact.k / scene.body.mass)
    rb = body_of(scene)
    _, traj, b = run(scene, "semi_implicit_euler")
    assert traj.steps == 1_000_000
    Z = traj.states()
    power = Z[:, 4] * (loads(scene, rb, Z).elastic.sum(axis=1) - rb.mass * scene.g)
    assert np.max(np.abs(b.R + 0.5 * scene.dt * power)) <= wn * scene.dt * 0.5 * scene.dt * np.max(np.abs(power))
    tenth = len(b.R) // 10
    assert np.max(np.abs(b.R[-tenth:])) <= (1 + wn * scene.dt) * np.max(np.abs(b.R[:tenth]))
    _, traj, b = run(scene, "explicit_euler")
    Z = traj.states()
    ld = loads(scene, rb, Z[:-1])
    touching = ld.d > 0.0
    growth = (rb.mass * accelerations(scene, rb, Z[:-1], ld)[:, 1] ** 2
              + scene.contact.k * (touching * Z[:-1, 4:5] ** 2).sum(axis=1))
    predicted = 0.5 * scene.dt ** 2 * growth.sum()
    assert np.all(np.diff(b.R) >= -8 * EPS * b.E[0])
    assert abs(b.R[-1] - predicted) <= wn * scene.dt * predicted
    assert b.R[-1] > 50 * np.max(np.abs(b.R[:1000]))


def test_implicit_euler_touchdown_jump_is_counted_at_its_filippov_share():
    """resting_60s under implicit Euler has one step that lands a corner on the ground with the
    damper partly on (custom_sim/filippov.py): the balance finds it, and with that share the
    step is implicit Euler's to round-off."""
    scene = dataclasses.replace(load("resting_60s"), duration=0.1)
    _, traj, b = run(scene, "implicit_euler")
    assert b.jump_steps == 1
    assert np.max(b.step_mismatch) <= 64 * EPS * np.max(np.abs(traj.states()))


def test_energy_column_check_names_the_missing_term():
    """box_drop's own energy column passes, in memory and written to a CSV (10 digits); with
    the rotation's or the contact's energy left out it fails and names what is missing."""
    scene = load("box_drop")
    traj = custom_sim.simulate(scene)
    states = traj.states()
    terms = energy_terms(scene, body_of(scene), states)
    assert energy_column_check(scene, states, traj.energy).agrees
    cases = {"rotational kinetic energy I omega^2 / 2 missing": traj.energy - terms["rotation"],
             "the contact's k d^2 / 2 missing": traj.energy - terms["contact"]}
    for said, column in cases.items():
        verdict = energy_column_check(scene, states, column)
        assert not verdict.agrees and verdict.explained_by == (said,), verdict.text
    verdict = energy_column_check(scene, states, traj.energy + 0.02 * terms["gravity"])
    assert verdict.explained_by == ("gravitational energy m g y off by a factor 1.02",)


def test_energy_column_check_allows_the_csv_rounding(tmp_path):
    scene = load("box_drop")
    traj = custom_sim.simulate(dataclasses.replace(scene, duration=0.5))
    terms = energy_terms(scene, body_of(scene), traj.states())
    for column, agrees in ((traj.energy, True), (traj.energy - terms["rotation"], False)):
        write_csv(dataclasses.replace(traj, energy_kinetic=column, energy_gravity=0 * column,
                                      energy_contact=0 * column), tmp_path / "run.csv")
        read = read_csv(tmp_path / "run.csv")
        states = np.column_stack([read[c] for c in ("x", "y", "theta", "vx", "vy", "omega")])
        verdict = energy_column_check(scene, states, read["energy"])
        assert verdict.agrees == agrees, verdict.text


def test_metrics_block_contract():
    scene, traj, b = run(load("box_slide"))
    block = metrics_block(b)
    assert set(block) == {"delta_E", "dissipated", "residual_end", "residual_max"}
    assert set(block["dissipated"]) == {"damping", "friction", "rolling"}
    assert block["delta_E"] == pytest.approx(traj.energy[-1] - traj.energy[0], abs=1e-12)
    total = sum(block["dissipated"].values())
    assert block["residual_end"] == pytest.approx(block["delta_E"] + total, abs=1e-12)
    assert block["residual_max"] >= abs(block["residual_end"])


@pytest.mark.slow
def test_mujoco_twins_on_box_drop():
    """The dynamics twin (our law through MuJoCo's callback) has custom_sim's R to within what
    the dynamics check's DYNAMICS_TOLERANCE allows. The native twin (penalty mapping: its normal
    row is our spring-damper to the mapping's force error) has R of the same size, first order
    in dt as MuJoCo's Euler is, and ends with custom_sim's delta_E: at rest, where physics alone
    sets it, to the mapping's force error on the resting depth."""
    pytest.importorskip("mujoco")
    from compare.energy.mujoco_side import dynamics_balance, native_balance

    scene = load("box_drop")
    _, traj, custom = run(scene)
    rb = body_of(scene)
    states = traj.states()
    force = rb.mass * np.max(np.abs(accelerations(scene, rb, states, loads(scene, rb, states))[:, :2]))
    speed = np.max(np.abs(states[:, 3:5]))
    wn = math.sqrt(len(rb.points) * scene.contact.k / rb.mass)   # the fastest rate of the motion
    # two trajectories within d of each other have E, and every step's work, within about
    # F_max d + m v_max (wn d) of each other
    allowed = 2 * (force + rb.mass * speed * wn) * DYNAMICS_TOLERANCE
    dyn = dynamics_balance(scene)
    assert np.max(np.abs(dyn.R - custom.R)) <= allowed

    native = native_balance(scene)
    weight = rb.mass * scene.g
    rest = 2 * MAPPING_FORCE_ERROR * weight * weight / (2 * scene.contact.k)
    assert abs((native.E[-1] - native.E[0]) - (custom.E[-1] - custom.E[0])) <= rest
    assert np.max(np.abs(native.R)) <= 2 * np.max(np.abs(custom.R))
    landing = [np.max(np.abs(native_balance(dataclasses.replace(scene, duration=0.5, dt=h)).R))
               for h in (scene.dt, scene.dt / 2)]
    assert abs(orders(landing)[0] - 1) <= ORDER_SLACK


def test_mujoco_native_residual_by_mapping():
    """elastic_bounce: under the penalty mapping MuJoCo's Euler on its spring has custom_sim's R
    to the mapping's force error times the spring energy it stores; under the physical mapping
    (a spring that is not the scene's k) R is the Euler step's kinetic-energy defect
    -sum dv^T M dv / 2 of MuJoCo's own states, to round-off."""
    pytest.importorskip("mujoco")
    from compare.energy.mujoco_side import native_balance
    from mujoco_models.run import simulate_mujoco

    scene = load("elastic_bounce")
    _, traj, custom = run(scene)
    native = native_balance(scene)
    spring = np.max(energy_terms(scene, body_of(scene), traj.states())["contact"])
    assert np.max(np.abs(native.R - custom.R)) <= MAPPING_FORCE_ERROR * spring
    physical = native_balance(scene, solref="physical")
    mj = simulate_mujoco(scene, solref="physical").states()
    dv = np.diff(mj[:, 3:5], axis=0)
    defect = -np.concatenate([[0.0], np.cumsum(scene.body.mass * (dv * dv).sum(axis=1) / 2)])
    assert np.max(np.abs(physical.R - defect)) <= 64 * EPS * physical.E[0] * np.sqrt(len(defect))


@pytest.mark.parametrize("name", [pytest.param("box_drop", marks=pytest.mark.slow),
                                  pytest.param("rolling_circle", marks=pytest.mark.slow), "elastic_bounce"])
def test_mujocos_balance_from_its_states_is_its_balance_row_by_row(name):
    """The native twin's balance from its states alone (as `run` computes it) against the one
    summed from MuJoCo's constraint rows at every step: the same R, since MuJoCo's Euler
    step is v1 = v0 + h M^-1 (f_c + m g) with a constant M. The split by effect is read at the
    touching points' mean arm, and MuJoCo applies friction mid-way through the penetration: the
    effects' shares may differ by that lever, their sum may not."""
    from compare.energy.mujoco_side import native_balance, native_from_run
    from mujoco_models import simulate_mujoco

    scene = load(name)
    run = simulate_mujoco(scene)
    fast = native_from_run(scene, run.t, run.states(), run.integrator, scene.mujoco.solref)
    rows = native_balance(scene)
    bound = FROM_STATES_AGREEMENT * float(np.max(np.abs(rows.R)))
    assert np.max(np.abs(fast.R - rows.R)) < bound, (np.max(np.abs(fast.R - rows.R)), bound)
    reading = float(np.max(np.abs(fast.E - rows.E)))   # the two depths' stored energies
    assert abs(fast.W[-1].sum() - rows.W[-1].sum()) < reading + bound


def test_mujocos_rk4_balance_is_not_measured_from_its_states():
    """RK4's stage forces are not in MuJoCo's states: R is null with the reason, never a
    quadrature's error shown as the integrator's."""
    from compare.energy.mujoco_side import native_from_run
    from mujoco_models import simulate_mujoco

    scene = dataclasses.replace(load("spinning_box"), duration=0.3)
    run = simulate_mujoco(scene)
    assert run.integrator == "RK4"
    b = native_from_run(scene, run.t, run.states(), run.integrator, scene.mujoco.solref)
    block = metrics_block(b)
    assert block["residual_end"] is None and block["residual_max"] is None
    assert b.rule.startswith("not measured") and math.isfinite(block["delta_E"])


# Three halvings of dt on a whole built-in run, contact switches included: each Euler method's
# R(end) falls at first order, the fitted slope within this of 1 (measured 0.96 to 1.08)
EULER_ORDER_SLACK = 0.15


@pytest.mark.parametrize("name", [n if n in ("box_slide", "point_drop") else pytest.param(n, marks=pytest.mark.slow)
                                  for n in ("box_drop", "box_slide", "elastic_bounce", "point_drop", "rolling_circle",
                                            "spinning_box", "t_shape_drop")])
def test_each_euler_methods_residual_falls_at_first_order_on_every_builtin(name):
    from compare.tools.accuracy.workprecision import custom_residual

    scene = load(name)
    dts = [scene.dt, scene.dt / 2, scene.dt / 4]
    for integrator in EULERS:
        r = [abs(custom_residual(scene, integrator, dt)[0]) for dt in dts]
        order = np.polyfit(np.log(dts), np.log(r), 1)[0]
        assert abs(order - 1.0) < EULER_ORDER_SLACK, (name, integrator, r, order)
