"""Hard scenes stay stable: the invariants every integrator keeps on each scene of scenarios/stress/.

Each case runs one stress scene with one integrator at a step inside that integrator's
stability limit (`step_inside_limit`) and checks it against physics the simulator does not
compute (energies and contact depths are recomputed here from the states):

  finite       the run completes: no NaN or inf, no SimulationDiverged
  energy       E(t) <= E(0) + budget: every stress scene dissipates (damping on compression,
               friction against the slip), so the exact motion never gains energy; the budget
               is the integrator's own error, derived term by term in `energy_budget`
  penetration  the deepest contact point stays within the energy-balance bound `penetration_bound`
  rest         a body left resting carries its weight on the touching points (sum k d_i = m g,
               no torque: m g / k shared by lever arms, m g / (2 k) per corner of a flat box) and
               neither creeps nor jitters over its last seconds

Implicit Euler keeps them at ten times the theory limit of semi-implicit Euler, and a run that
blows up stops at once with SimulationDiverged (step, state, a stable step that is stable).

Durations are the scenes' own: the long runs are the point of two scenes (60 s at rest, a
million steps); the slowest case, implicit Euler's million steps, takes about 2 s.

The largest stable step of every scene and integrator, by bisection (about a minute):

    python -m tests.test_stress [SCENE ...]
"""
from __future__ import annotations

import dataclasses
import functools
import math
import re
import sys

import numpy as np
import pytest

from compare.scenarios import builtin_paths
from custom_sim import (INTEGRATORS, SimulationDiverged, load_scene, mass_properties, simulate,
                        stable_step)
from custom_sim.bodies import min_effective_mass
from custom_sim.stability import contact_frequency, limits

STRESS = {p.stem: p for p in builtin_paths("stress")}
METHODS = tuple(INTEGRATORS)

# Fraction of the theory limit the invariant runs use: far enough inside that the linear
# theory's neglect of the contact switch and of the impact's peak force does not matter.
SAFETY = 0.5

# Relative to the energy's size max(|E0|, E_osc): each step leaves a few ulps (2.2e-16) of
# round-off in the state, which wanders like a random walk: sqrt(1e6) ulps = 2e-13 after the
# longest run. 1e-10 leaves a factor 500 and is far below every physical term of the budget.
ENERGY_ROUNDOFF = 1e-10

# At rest only round-off is left: y carries |y| eps ~ 1e-17 m against depths of 1e-4 m, i.e.
# 1e-13 of the weight; 1e-9 leaves room for accumulation and is still 1e5 below any residual
# motion (a stable rest decays as exp(-zeta wn t / 2): e^-500 after the 50 s these scenes wait).
REST_FORCE_RTOL = 1e-9
# m and rad over the last REST_WINDOW: creep by tanh chatter moves ~h mu g = 5e-4 m/s, a stable
# rest nothing but round-off (1e-17 m a step, 5e4 steps).
REST_DRIFT = 1e-9
REST_WINDOW = 5.0  # s
# the scenes that end at rest
REST_SCENES = ("resting_60s", "million_steps")


# ---------------------------------------------------------------------------------------
# Theory the checks use


def gravity(scene) -> float:
    return scene.g if scene.has("gravity") else 0.0


def step_inside_limit(scene, integrator: str) -> float:
    """The invariant runs' step: the scene's dt, or SAFETY times the theory limit if smaller."""
    return min(scene.dt, SAFETY * stable_step(scene, integrator))


def contact_depths(props, states: np.ndarray):
    """Depths d (m, > 0 touching) and lever arms r_x (m) of the contact points, shape (T, n),
    from states (T, 6): r = R(theta) l for points that turn, r = l for those that do not."""
    states = np.atleast_2d(states)
    y, theta = states[:, 1:2], states[:, 2:3]
    lx, ly = props.points[:, 0], props.points[:, 1]
    if props.points_rotate:
        c, s = np.cos(theta), np.sin(theta)
        rx, ry = c * lx - s * ly, s * lx + c * ly
    else:
        rx, ry = np.broadcast_to(lx, (len(y), len(lx))), ly
    return -(y + ry), rx


def energies(scene, props, states: np.ndarray) -> np.ndarray:
    """E = m |v|^2 / 2 + I omega^2 / 2 + m g y + sum of k d^2 / 2 over touching points (J)."""
    states = np.atleast_2d(states)
    vx, vy, om = states[:, 3], states[:, 4], states[:, 5]
    e = 0.5 * props.mass * (vx * vx + vy * vy) + 0.5 * props.inertia * om * om
    e = e + props.mass * gravity(scene) * states[:, 1]
    if scene.has("contact"):
        d, _ = contact_depths(props, states)
        e = e + 0.5 * scene.contact.k * np.sum(np.maximum(d, 0.0) ** 2, axis=1)
    return e


def clearance(props, samples: int = 7200) -> float:
    """c0 (m): the least height of the centre of mass above its lowest contact point, over all
    angles (point: contact_height; circle: R; box: min(w, h) / 2). Sampled for bodies whose
    points turn; the support function is |r|-Lipschitz in theta, so subtracting |r| dtheta / 2
    keeps it a lower bound."""
    pts = props.points
    if not props.points_rotate:
        return float(-pts[:, 1].min())
    th = np.linspace(0.0, 2.0 * np.pi, samples, endpoint=False)[:, None]
    lowest = np.max(-(np.sin(th) * pts[:, 0] + np.cos(th) * pts[:, 1]), axis=1)
    r = float(np.sqrt((pts ** 2).sum(axis=1)).max())
    return float(lowest.min()) - r * np.pi / samples


def initial_state(scene) -> np.ndarray:
    i = scene.initial
    return np.array([*i.position, i.angle, *i.velocity, i.angular_velocity])


def available_energy(scene, props) -> float:
    """E0 - m g c0 (J): the energy above the body's lowest pose, all of which could end up in
    the contact springs."""
    e0 = float(energies(scene, props, initial_state(scene))[0])
    return max(0.0, e0 - props.mass * gravity(scene) * clearance(props))


def penetration_bound(scene, extra_energy: float = 0.0) -> float:
    """Deepest penetration (m) energy allows. With E(t) <= E0 + extra (dissipation), KE >= 0,
    k d_max^2 / 2 <= sum k d_i^2 / 2 and the centre of mass at least c0 - d_max high:
        k d^2 / 2 <= E0 + extra - m g (c0 - d) = E_avail + extra + m g d,
        d <= (m g + sqrt((m g)^2 + 2 k (E_avail + extra))) / k.
    For a point dropped from rest this is the undamped spring's exact maximum."""
    props = mass_properties(scene.body)
    w, k = props.mass * gravity(scene), scene.contact.k
    return (w + math.sqrt(w * w + 2.0 * k * (available_energy(scene, props) + extra_energy))) / k


def energy_budget(scene, integrator: str, h: float) -> dict[str, float]:
    """How far E(t) may rise above E(0) (J) with this integrator and step h, term by term.

    E_osc = E_avail + (m g)^2 / (2 k): the energy above the bottom of the contact well;
    v_n = sqrt(2 E_avail / m_eff): the fastest a contact point can approach the ground
    (Cauchy-Schwarz on m |v|^2 + I omega^2 with the smallest effective mass m_eff);
    n contact points, contact frequency wn (at m_eff).

    contact switch     methods that take the force from the start of a step (all but implicit
                       Euler) let a point enter the ground unopposed for part of a step, storing
                       k d^2 / 2 with d <= v_n h, and push a leaving point for a step too long:
                       at most k (v_n h)^2 per point
    friction chatter   at an impact Fn reaches k d + c v_n, far above m g, and the tanh's rate
                       mu alpha Fn / m_eff can exceed 2 / h. The tanh saturates, so the slip
                       velocity only flips within the friction impulse h mu Fn / m_eff: a
                       tangential energy of at most (h mu Fn)^2 / (2 m_eff); rolling likewise
    shadow energy      semi-implicit Euler conserves v^2 + wn^2 x^2 - h wn^2 x v, not the energy:
                       the energy read at step ends swings by a factor (1 + h wn/2)/(1 - h wn/2)
    undamped expansion explicit Euler multiplies the oscillator energy by 1 + (h wn)^2 per step
                       while undamped: the rebound (a quarter period, pi / (2 h wn) steps) gains
                       exp(pi h wn / 2) - 1 of E_osc
    free flight        explicit Euler gains m g^2 h^2 / 2 per step of flight
    round-off          ENERGY_ROUNDOFF of the energy's size
    Implicit Euler has none of the others: with the force taken at the end of the step it is
    dissipative (for a point: E1 - E0 <= -m h^2 a1^2 / 2 by convexity of the contact potential).
    """
    props = mass_properties(scene.body)
    m, k, g = props.mass, scene.contact.k, gravity(scene)
    e_avail = available_energy(scene, props)
    e_osc = e_avail + (m * g) ** 2 / (2.0 * k)
    e0 = float(energies(scene, props, initial_state(scene))[0])
    terms = {"round-off": ENERGY_ROUNDOFF * max(abs(e0), e_osc)}
    if not scene.has("contact") or integrator == "implicit_euler":
        return terms
    m_eff = min_effective_mass(props)
    vn = math.sqrt(2.0 * e_avail / m_eff)
    wn, _ = contact_frequency(scene)
    n = len(props.points)
    terms["contact switch"] = n * k * (vn * h) ** 2
    fn = n * (k * penetration_bound(scene, terms["contact switch"]) + scene.contact.c * vn)
    if scene.has("friction"):
        terms["friction chatter"] = (h * scene.contact.mu * fn) ** 2 / (2.0 * m_eff)
    if scene.has("rolling_friction"):
        terms["rolling chatter"] = (h * scene.contact.mu_roll * fn) ** 2 / (2.0 * props.inertia)
    if integrator == "semi_implicit_euler":  # beyond h wn = 2 nothing bounds it: unstable
        terms["shadow energy"] = h * wn / (1.0 - h * wn / 2.0) * e_osc if h * wn < 2.0 else math.inf
    if integrator == "explicit_euler":
        terms["undamped expansion"] = math.expm1(math.pi * h * wn / 2.0) * e_osc
        terms["free flight"] = m * g * g * h * scene.duration / 2.0
    return terms


# ---------------------------------------------------------------------------------------
# The invariants, each a function of (scene, trajectory) that asserts with the observed value


def check_finite(scene, traj):
    states = traj.states()
    assert np.all(np.isfinite(states)), f"non-finite state at step {np.argmin(np.isfinite(states).all(axis=1))}"
    assert traj.steps == scene.steps


def check_energy(scene, traj):
    props = mass_properties(scene.body)
    e = energies(scene, props, traj.states())
    assert np.allclose(traj.energy, e, rtol=1e-12, atol=1e-12 * np.abs(e).max()), \
        "custom_sim's energy differs from the CONTRACT formula"
    budget = energy_budget(scene, scene.integrator, scene.dt)
    rise = float(e.max() - e[0])
    terms = ", ".join(f"{name} {v:.3g}" for name, v in budget.items())
    assert rise <= sum(budget.values()), \
        f"energy rose {rise:.4g} J above E0 = {e[0]:.4g} J at step {int(e.argmax())}; budget {terms} J"


def check_penetration(scene, traj):
    props = mass_properties(scene.body)
    d, _ = contact_depths(props, traj.states())
    deepest = float(d.max())
    bound = penetration_bound(scene, sum(energy_budget(scene, scene.integrator, scene.dt).values()))
    assert deepest <= bound, f"penetration {deepest:.4g} m beyond the energy bound {bound:.4g} m"


def check_rest(scene, traj):
    props = mass_properties(scene.body)
    window = slice(-int(round(REST_WINDOW / scene.dt)) - 1, None)
    states = traj.states()[window]
    for i, name in ((0, "x"), (1, "y"), (2, "theta")):
        drift = float(np.ptp(states[:, i]))
        assert drift <= REST_DRIFT, f"{name} moved {drift:.3g} over the last {REST_WINDOW} s (creep or jitter)"
    d, rx = contact_depths(props, states[-1])
    d, rx = d[0], rx[0]
    touching = d > 0.0
    m, g, k = props.mass, gravity(scene), scene.contact.k
    weight = m * g
    carried = float(np.sum(k * d[touching]))
    assert abs(carried - weight) <= REST_FORCE_RTOL * weight, \
        f"the contacts carry {carried:.12g} N, the weight is {weight:.12g} N"
    torque = float(np.sum(k * d[touching] * rx[touching]))
    arm = float(np.abs(rx).max())
    assert abs(torque) <= REST_FORCE_RTOL * weight * arm, f"contact torque {torque:.3g} N m at rest"
    if touching.sum() == 2:
        # two points share m g / k in inverse proportion to their lever arms (what the two
        # balances above imply, stated: each balance's error moves a share by a few times
        # REST_FORCE_RTOL when the arms are unequal)
        a = np.abs(rx[touching])
        share = weight / k * a[::-1] / a.sum()
        assert np.allclose(d[touching], share, rtol=10 * REST_FORCE_RTOL), (d[touching], share)


INVARIANTS = {"finite": check_finite, "energy": check_energy, "penetration": check_penetration,
              "rest": check_rest}


@functools.lru_cache(maxsize=1)
def run(name: str, integrator: str, h: float):
    """One stress run (cached: the invariants of a case run one after another on it)."""
    scene = dataclasses.replace(load_scene(STRESS[name]), integrator=integrator, dt=h)
    return scene, simulate(scene)


def invariant_cases():
    for name in STRESS:
        for method in METHODS:
            for inv in INVARIANTS:
                if inv == "rest" and name not in REST_SCENES:
                    continue
                marks = KNOWN_FAILURES.get((name, method, inv), ()) + ((pytest.mark.slow,) if name in SLOW else ())
                # a run's invariants on one worker, one after another: run() computes it once
                marks += (pytest.mark.xdist_group(f"stress-{name}-{method}"),)
                yield pytest.param(name, method, inv, id=f"{name}-{method}-{inv}", marks=marks)


# Implicit Euler's Newton iteration (custom_sim/integrators.py) takes its last iterate when it
# has not converged in NEWTON_MAX_ITERATIONS; at a touchdown the tanh friction and the contact
# switch make plain Newton cycle, and that iterate is a free-flight step ending deep in the
# ground (fast_impact: E rises 1.3e-3 J where implicit Euler must dissipate). A damped Newton
# (halve the update until |G| falls) fixes every case: see the report of issue 6.
KNOWN_FAILURES = {}
SLOW = ("million_steps", "fast_impact", "stiff_contact")   # the longest runs: CI's step for slow checks


@pytest.mark.parametrize("name, integrator, invariant", list(invariant_cases()))
def test_invariant(name, integrator, invariant):
    base = load_scene(STRESS[name])
    scene, traj = run(name, integrator, step_inside_limit(base, integrator))
    INVARIANTS[invariant](scene, traj)


def test_every_stress_scene_has_a_stable_step_and_a_description():
    """The scene files themselves: dt inside the default integrator's theory limit, and a
    description a user reads in `list`."""
    assert len(STRESS) == 10
    for name, path in STRESS.items():
        scene = load_scene(path)
        assert scene.dt <= SAFETY * stable_step(scene), (name, scene.dt, stable_step(scene))
        assert len(scene.description) > 40, name


def test_the_stress_cases_are_what_the_issue_asks():
    s = {name: load_scene(path) for name, path in STRESS.items()}
    assert s["stiff_contact"].contact.k == 1e7 and s["stiff_contact"].body.mass == 0.01
    assert math.hypot(*s["fast_impact"].initial.velocity) >= 30.0
    corner = s["corner_landing"]
    assert corner.initial.angle == pytest.approx(math.pi / 4, abs=1e-15) and corner.body.size[0] == corner.body.size[1]
    assert s["spinning_circle"].initial.angular_velocity == 100.0 and s["spinning_circle"].body.shape == "circle"
    assert abs(s["grazing_contact"].initial.velocity[1]) <= 1e-3
    assert s["resting_60s"].duration == 60.0
    assert s["sharp_friction"].contact.alpha == 1e5
    assert s["million_steps"].steps == 1_000_000


def test_grazing_penetration_follows_the_normal_speed():
    """The energy bound counts the horizontal motion too, so for the grazing scene it is loose
    (1 cm). The spring at the one touching corner can only store the normal motion's energy:
    with m >= m_eff, d <= v_n sqrt(m / k), plus the onset overshoot v_n h; friction's impulse
    (at most mu times the normal one) may add as much again through the torque: a factor 1 + mu."""
    scene = load_scene(STRESS["grazing_contact"])
    props = mass_properties(scene.body)
    vn = abs(scene.initial.velocity[1])
    bound = vn * math.sqrt(props.mass / scene.contact.k) * (1.0 + scene.contact.mu) + vn * scene.dt
    for method in METHODS:
        traj = simulate(dataclasses.replace(scene, integrator=method))
        deepest = float(contact_depths(props, traj.states())[0].max())
        assert 0.0 < deepest <= bound, (method, deepest, bound)


# forces.py applies rolling resistance as -mu_roll Fn sign(omega): a torque that never
# vanishes near omega = 0 flips omega's sign every step (implicit Euler: no root, Newton fails
# on every step), so a disk that rolling resistance has stopped keeps rocking and creeps
@pytest.mark.parametrize("integrator", METHODS)
def test_rolling_resistance_stops_a_disk(integrator):
    """The spinning_circle disk rolling at 1 cm/s: rolling resistance decelerates it at
    2 mu_roll g / (3 R) = 0.13 m/s^2, so it stops within 0.08 s; it must then stay put."""
    base = load_scene(STRESS["spinning_circle"])
    R, v = base.body.radius, 0.01
    scene = dataclasses.replace(
        base, integrator=integrator, duration=1.0,
        initial=dataclasses.replace(base.initial, position=(0.0, R - base.body.mass * base.g / base.contact.k),
                                    velocity=(v, 0.0), angular_velocity=-v / R))
    scene = dataclasses.replace(scene, dt=step_inside_limit(scene, integrator))
    traj = simulate(scene)
    window = slice(-int(round(0.5 / scene.dt)), None)
    drift = float(np.ptp(traj.x[window]))
    assert drift <= REST_DRIFT, f"the stopped disk moved {drift:.3g} m in its last 0.5 s"


# ---------------------------------------------------------------------------------------
# Implicit Euler at ten times semi-implicit Euler's limit


@pytest.mark.parametrize("name", list(STRESS))
def test_implicit_euler_is_stable_at_ten_times_the_semi_implicit_limit(name):
    base = load_scene(STRESS[name])
    h = min(10.0 * stable_step(base, "semi_implicit_euler"), base.duration / 20.0)
    scene = dataclasses.replace(base, integrator="implicit_euler", dt=h)
    traj = simulate(scene)
    check_finite(scene, traj)
    check_energy(scene, traj)
    check_penetration(scene, traj)
    if name in REST_SCENES:
        check_rest(scene, traj)


# ---------------------------------------------------------------------------------------
# Divergence is caught at once, with a stable step that is stable


@pytest.mark.parametrize("integrator", ["explicit_euler", "semi_implicit_euler"])
def test_divergence_stops_at_once_with_step_state_and_a_stable_step(integrator):
    base = load_scene(STRESS["stiff_contact"])
    h = 5.0 * stable_step(base, integrator)
    scene = dataclasses.replace(base, integrator=integrator, dt=h)
    with pytest.raises(SimulationDiverged) as info:
        simulate(scene)
    exc = info.value
    assert 1 <= exc.step <= scene.steps and exc.state.shape == (6,)
    assert exc.stable_dt == stable_step(base, integrator)
    message = str(exc)
    assert f"step {exc.step}" in message and f"{exc.stable_dt:.3g}" in message and integrator in message
    # at once: the steps before it are healthy, so the run stopped at the first bad state
    before = simulate(dataclasses.replace(scene, duration=(exc.step - 1) * h))
    assert np.all(np.isfinite(before.states()))


def test_run_writes_no_report_for_a_diverging_scene(tmp_path, capsys):
    """`python -m compare run` on a scene that blows up: exit status 1, the divergence in the
    scene's row (once, with its name), no folder for the scene, and nothing non-finite in
    anything it did write."""
    pytest.importorskip("compare.commands.run")
    from compare.cli import main

    base = load_scene(STRESS["stiff_contact"])
    h = 5.0 * limits(base, "semi_implicit_euler")["contact"]   # past the spring: a blow-up, not chatter
    text = re.sub(r"(?m)^dt = .*$", f"dt = {h!r}", STRESS["stiff_contact"].read_text())
    text = re.sub(r"(?m)^duration = .*$", "duration = 0.3", text)
    path = tmp_path / "stiff_blowup.toml"
    path.write_text(text)
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--jobs", "1"]) == 1
    printed = capsys.readouterr().out
    assert printed.count("diverged at step") == 1 and "stiff_blowup         unstable: " in printed, printed
    assert not (out / "stiff_blowup").exists()
    for written in out.rglob("*"):
        if written.is_file() and written.suffix in (".md", ".json", ".csv"):
            assert not re.search(r"\b(nan|inf)\b", written.read_text(), re.IGNORECASE), written


@pytest.mark.parametrize("integrator", ["explicit_euler", "semi_implicit_euler", "rk4"])
def test_the_suggested_stable_step_is_stable(integrator):
    """The step SimulationDiverged suggests ("below stable_dt"), taken at 90 % of it, keeps
    the invariants on the stiffest scene."""
    base = load_scene(STRESS["stiff_contact"])
    scene = dataclasses.replace(base, integrator=integrator, dt=0.9 * stable_step(base, integrator))
    traj = simulate(scene)
    check_finite(scene, traj)
    check_energy(scene, traj)
    check_penetration(scene, traj)


def test_undamped_explicit_euler_gains_what_theory_says():
    """Explicit Euler is unstable without damping, so instead of "energy never rises" it must
    show its theory: on x'' = -wn^2 x a step maps (wn x, v) by [[1, h wn], [-h wn, 1]], whose
    norm grows by exactly 1 + (h wn)^2. A point on an undamped, frictionless spring ground is
    that oscillator about x = y + m g / k while it touches, so from the first step taken in
    contact to the state after the last, E_osc = m vy^2 / 2 + k (y + m g / k)^2 / 2 grows by
    (1 + (h wn)^2)^N over the N steps whose force was on. Exact, up to round-off."""
    base = load_scene(STRESS["stiff_contact"])
    k, m, h = 1e4, 1.0, 5e-4
    wn, d_eq = math.sqrt(k / m), m * base.g / k
    scene = dataclasses.replace(
        base, integrator="explicit_euler", dt=h, duration=0.3, effects=("gravity", "contact"),
        body=dataclasses.replace(base.body, mass=m),
        contact=dataclasses.replace(base.contact, k=k, c=0.0))
    traj = simulate(scene)
    touching = traj.y < 0.0
    first = int(np.argmax(touching))                       # first state in contact
    after = first + int(np.argmin(touching[first:]))       # first state out of it again
    n = after - first
    e_osc = 0.5 * m * traj.vy ** 2 + 0.5 * k * (traj.y + d_eq) ** 2
    gain = e_osc[after] / e_osc[first]
    predicted = (1.0 + (h * wn) ** 2) ** n
    assert n > 50 and traj.vy[after] > 0.0
    assert gain == pytest.approx(predicted, rel=1e-9), (gain, predicted, n)
    assert gain > 1.1  # a bounce higher than the drop: why the damped scenes need h wn < zeta


# ---------------------------------------------------------------------------------------
# The largest stable step, by bisection (python -m tests.test_stress)


def run_is_stable(scene, integrator: str, h: float) -> tuple[bool, str]:
    """The scene's own run at step h is stable when it completes, keeps the energy invariant and,
    for the scenes that come to rest, comes to rest (tanh chatter is bounded, so only this shows it)."""
    s = dataclasses.replace(scene, integrator=integrator, dt=h)
    try:
        traj = simulate(s)
    except SimulationDiverged as exc:
        return False, f"diverged at step {exc.step}"
    checks = [check_finite, check_energy] + ([check_rest] if scene.name in REST_SCENES else [])
    for check in checks:
        try:
            check(s, traj)
        except AssertionError as exc:
            return False, str(exc).splitlines()[0]
    return True, ""


REST_PROBE_DURATION = 1.0   # s: 20 periods of the slowest contact mode of these scenes


def rest_is_stable(scene, integrator: str, h: float) -> tuple[bool, str]:
    """The situation stability.py's theory is derived for (Fn = m g): the scene's body resting
    flat on its lowest points, nudged within the linear range, once downwards (a thousandth of
    the resting depth: the contact mode) and once sideways (a slip of 0.01 / alpha: the tanh
    friction mode). Stable at step h when neither nudge has grown after REST_PROBE_DURATION
    (the vertical one by its energy above rest, the sideways one by its kinetic energy).
    Rolling resistance is left out: its sign(omega) has no linear range (see
    test_rolling_resistance_stops_a_disk)."""
    props = mass_properties(scene.body)
    m, k, g = props.mass, scene.contact.k, gravity(scene)
    low = props.points[:, 1].min()
    n = int(np.sum(props.points[:, 1] <= low + 1e-12))
    depth = m * g / (n * k)
    wn, _ = contact_frequency(scene)
    rest = np.array([0.0, -low - depth, 0.0, 0.0, 0.0, 0.0])
    effects = tuple(e for e in scene.effects if e != "rolling_friction")
    nudges = {"vertical": (0.0, 1e-3 * depth * wn)}
    if "friction" in effects:
        nudges["sideways"] = (0.01 / scene.contact.alpha, 0.0)
    for kind, velocity in nudges.items():
        s = dataclasses.replace(
            scene, integrator=integrator, dt=h, duration=max(REST_PROBE_DURATION, h), effects=effects,
            initial=dataclasses.replace(scene.initial, position=tuple(rest[:2]), angle=0.0,
                                        velocity=velocity, angular_velocity=0.0))
        try:
            traj = simulate(s)
        except SimulationDiverged as exc:
            return False, f"{kind} nudge diverged at step {exc.step}"
        ends = traj.states()[[0, -1]]
        if kind == "vertical":
            size = energies(s, props, ends) - energies(s, props, rest)[0]
        else:
            size = 0.5 * m * (ends[:, 3] ** 2 + ends[:, 4] ** 2) + 0.5 * props.inertia * ends[:, 5] ** 2
        if not size[1] <= size[0]:
            return False, f"the {kind} nudge grew from {size[0]:.3g} J to {size[1]:.3g} J"
    return True, ""


def largest_stable_step(is_stable, h_start: float, h_max: float, ratio: float = 1.02) -> tuple[float, str]:
    """Bisection in log h between a stable and an unstable step, from h_start, below h_max."""
    lo = h_start
    ok, why = is_stable(lo)
    while not ok:
        lo /= 2.0
        ok, why = is_stable(lo)
    hi = None
    while hi is None:
        trial = min(4.0 * lo, h_max)
        ok, why = is_stable(trial)
        if not ok:
            hi, reason = trial, why
        elif trial >= h_max:
            return trial, f"stable up to {h_max:.3g} s"
        else:
            lo = trial
    while hi / lo > ratio:
        mid = math.sqrt(lo * hi)
        ok, why = is_stable(mid)
        if ok:
            lo = mid
        else:
            hi, reason = mid, why
    return lo, f"at {hi:.3g} s: {reason}"


def main(names: list[str]) -> None:
    """Print theory, the largest step of the scene's own run, and of the body at rest."""
    print(f"{'scene':16s} {'integrator':20s} {'theory':>9s} {'run':>9s} {'at rest':>9s}  first unstable step (run; at rest)")
    for name in names or STRESS:
        scene = load_scene(STRESS[name])
        for method in METHODS:
            h0, h_max = step_inside_limit(scene, method), scene.duration / 20.0
            h_run, why_run = largest_stable_step(lambda h: run_is_stable(scene, method, h), h0, h_max)
            h_rest, why_rest = math.nan, "no rest without gravity"
            if scene.has("gravity"):
                h_rest, why_rest = largest_stable_step(lambda h: rest_is_stable(scene, method, h), h0, h_max)
            print(f"{name:16s} {method:20s} {stable_step(scene, method):9.3g} {h_run:9.3g} {h_rest:9.3g}  "
                  f"{why_run}; {why_rest}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
