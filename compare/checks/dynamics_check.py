"""Check `dynamics`: the trajectory under test against MuJoCo integrating the same contact law.

The dynamics twin (mujoco_models.dynamics) takes its mass, COM, inertia and contact points from
the scene file with its own code, its contact-point positions, velocities and Jacobians from
MuJoCo's kinematics, and its integration from MuJoCo's Euler (= semi-implicit Euler) or RK4.
Only the seed's force law is written again, in a passive-force callback. A correct simulator
under the same integrator and dt then differs from it by round-off alone, so whatever is
left is a mistake in the inertia, the torque, the contact-point kinematics or the integrator.

    check_dynamics(scene, states, integrator, dt) -> CheckRow

Tolerance (m, rad), derived:

1. Round-off. Two correct implementations order their floating-point operations differently;
   each step's update q += h v rounds by about an ulp of |q| in each, so they part by up to
   ROUNDOFF_PER_STEP = 2 eps relative per step. Where the motion does not amplify a
   difference (flight, a bounce, a slide, rest) it accumulates at most linearly:
       tol = max(ROUNDOFF_FLOOR, ROUNDOFF_PER_STEP * steps * L),  L = max(1, largest |q|)
   (L in m for positions, rad for the angle). ROUNDOFF_FLOOR = 1e-9 covers that bound for up
   to 2e6 steps at L = 1 (2 * 2.2e-16 * 2e6 = 8.9e-10); the measured differences of a
   correct simulator on every built-in scene are 1e-17 to 2e-13 m where nothing amplifies.
2. Motions that amplify round-off. An explicit friction update is unstable while
   h mu Fn' alpha / m_t > 2 (Fn' the load times tanh's slope, m_t the contact point's
   tangential effective mass): a tilted T landing on a corner reaches 3.5 for 136 steps of its
   impact and grows a 1e-16 difference to 5e-9 m. A box balanced on its corner topples one way
   or the other as round-off decides (1.5 m apart after 3 s). Where the difference exceeds
   bound 1, the check measures the motion's own amplification: two more twin runs with k, c,
   mu, alpha, mu_roll and the step h scaled by 1 +- SENSITIVITY_PERTURBATION (a round-off-sized
   difference in every force and every update, as two implementations have; systematic, so it
   parts faster than round-off's random signs) and the initial angle moved by as much (a pose
   balanced on a corner is tipped by the rounding of its lever arm, which no force scale
   changes). The tolerance becomes SENSITIVITY_SAFETY times their largest
   distance from the twin, and the check judges only up to the horizon where that reaches
   HORIZON_POSITION or HORIZON_ANGLE: past it the motion has forgotten its round-off and a
   difference says nothing about a mistake. The row gives the bound used, the horizon, the
   amplification and the friction step number, so a wider tolerance is a measurement shown
   with its cause.
A wrong inertia, mass or contact point moves the body by 1e-4 to 1e-1 m after the first
impact, far above both.

No judged tolerance exceeds a tenth of the motion it judges (MOTION_SHARE, the contact check's
rule; the motion is the range of the twin's COM path, and of its angle, over the judged window).
A body that does not turn (a point mass, a ball that bounces straight, a box sliding flat
whose angle moves by less than ten times 1e-9 rad) has its angle shown, not judged; a position
whose tolerance does not fit leaves the check not judged. The row says which, with the motion.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from scene_types.integrators import MUJOCO_TWIN
from scene_types.schema import Scene

from ..store import cached
from .row import CheckRow

NAME = "dynamics"
ISOLATES = ("inertia, torque, contact-point kinematics and the integrator: MuJoCo integrates "
            "the same contact law")
EPS = float(np.finfo(float).eps)
ROUNDOFF_PER_STEP = 2.0 * EPS      # relative difference added per step by two correct codes
ROUNDOFF_FLOOR_POSITION = 1e-9     # m, see the module docstring
ROUNDOFF_FLOOR_ANGLE = 1e-9        # rad
SENSITIVITY_PERTURBATION = 4.0 * EPS   # relative, on every force-law parameter
SENSITIVITY_SAFETY = 10.0          # the two ensemble members sample the spread, not its maximum
HORIZON_POSITION = 1e-6            # m: judged while the tolerance stays below this, a thousandth
HORIZON_ANGLE = 1e-5               # rad   of the smallest mistake's effect (1e-3 m, 1e-2 rad)
MOTION_SHARE = 0.1                 # no judged tolerance above a tenth of the motion it judges
FRICTION_STABILITY = 2.0           # explicit step of a decaying rate lambda: stable for h lambda < 2


def check_dynamics(scene: Scene, states, integrator: str, dt: float, rounding=None) -> CheckRow:
    """The `dynamics` row for `states` (steps + 1, 6), a run of `scene` with `integrator` and
    `dt` by the simulator under test (docs/report-files.md). rounding: how the states were written to a
    file (one_step.Rounding), None for full double precision: its half unit of each value is
    added to the tolerance."""
    details: dict = {}
    if integrator not in MUJOCO_TWIN:
        return _row(integrator, details, f"not judged: MuJoCo has no {integrator.replace('_', ' ')} (its implicit "
                                         f"integrators leave passive forces out of their derivatives); check step "
                                         f"judges this integrator")
    states = np.asarray(states, dtype=float)
    from mujoco_models import MujocoDiverged, simulate_dynamics

    run = dataclasses.replace(scene, integrator=integrator, dt=float(dt))
    if states.ndim != 2 or states.shape != (run.steps + 1, 6):
        return _row(integrator, details, f"not judged: the trajectory has shape {states.shape}, expected "
                                         f"({run.steps + 1}, 6) for {run.steps} steps of dt = {dt:g} s")
    # finite: every run judged is validated once where it is collected (compare/run/scenario.py collect_runs)
    try:
        twin = cached(simulate_dynamics)(run, MUJOCO_TWIN[integrator], dt).states()
    except MujocoDiverged as exc:
        return _row(integrator, details, f"not judged: the dynamics twin diverged ({exc})")
    pos = np.hypot(states[:, 0] - twin[:, 0], states[:, 1] - twin[:, 1])
    ang = np.abs(states[:, 2] - twin[:, 2])
    tol_pos, tol_ang = roundoff_tolerance(twin, run.steps)
    if rounding is not None:   # the file's own rounding, on top of the two codes' round-off
        half = rounding.half_unit(states)
        tol_pos += float(np.hypot(half[:, 0], half[:, 1]).max())
        tol_ang += float(half[:, 2].max())
        details["rounding"] = rounding.describe()
    motion_pos, motion_ang = motion(twin)
    # an angle that turns by less than its tolerance / MOTION_SHARE is shown, not judged: its
    # difference neither fails the check nor calls for the sensitivity runs
    judge_angle = tol_ang <= MOTION_SHARE * motion_ang[-1]
    pos_max, ang_max = float(pos.max()), float(ang.max())
    details.update(roundoff_position=tol_pos, roundoff_angle=tol_ang,
                   mujoco_integrator=MUJOCO_TWIN[integrator],
                   friction_step_number_max=friction_step_number(run, twin))
    bound, judged = "round-off", len(pos)
    if pos.max() > tol_pos or (judge_angle and ang.max() > tol_ang):
        spread = sensitivity(run, MUJOCO_TWIN[integrator], dt, twin)
        if spread is None:
            details["sensitivity_position"] = None
        else:
            grow_pos = SENSITIVITY_SAFETY * np.maximum.accumulate(spread[0])
            grow_ang = SENSITIVITY_SAFETY * np.maximum.accumulate(spread[1])
            beyond = (grow_pos > HORIZON_POSITION) | (grow_ang > HORIZON_ANGLE)
            judged = int(np.argmax(beyond)) if beyond.any() else len(pos)
            tol_pos = max(tol_pos, float(grow_pos[judged - 1]))
            tol_ang = max(tol_ang, float(grow_ang[judged - 1]))
            bound = "sensitivity"
            details.update(sensitivity_position=float(spread[0][:judged].max()),
                           sensitivity_angle=float(spread[1][:judged].max()),
                           position_error_max_whole_run=float(pos.max()),
                           angle_error_max_whole_run=float(ang.max()))
            pos_max, ang_max = float(pos[:judged].max()), float(ang[:judged].max())
    # the rule, over the judged window [0, judged - 1] (tolerances only grow and the window
    # only shrinks with the sensitivity bound, so an angle not judged above stays so)
    judge_position = tol_pos <= MOTION_SHARE * motion_pos[judged - 1]
    judge_angle = judge_position and tol_ang <= MOTION_SHARE * motion_ang[judged - 1]
    details.update(motion_position=float(motion_pos[judged - 1]), motion_angle=float(motion_ang[judged - 1]),
                   judged_steps=judged - 1, judged_until=(judged - 1) * float(dt), bound=bound)
    if not judge_position:
        return _row(integrator, details, f"not judged: the tolerance {tol_pos:.3g} m exceeds {MOTION_SHARE:g} of the "
                                         f"motion it would judge ({details['motion_position']:.3g} m up to "
                                         f"t = {details['judged_until']:.6g} s)",
                    position_error_max=pos_max, angle_error_max=ang_max)
    over = (pos[:judged] > tol_pos) | ((ang[:judged] > tol_ang) if judge_angle else False)
    passed = not over.any()
    details["tolerance_angle_shown"] = None if judge_angle else tol_ang
    if not passed:
        i = int(np.argmax(over))
        details.update(first_step_over=i, time_first_over=i * float(dt))
    return _row(integrator, details, _reason(details, judge_angle, passed, run.steps), position_error_max=pos_max,
                angle_error_max=ang_max, tolerance_position=tol_pos, tolerance_angle=tol_ang if judge_angle else None,
                passed=passed)


def _row(integrator: str, details: dict, reason: str, **values) -> CheckRow:
    """A dynamics row: its reason follows every detail."""
    return CheckRow(NAME, ISOLATES, integrator, reason=reason, details=details, reason_at=len(details), **values)


def roundoff_tolerance(states: np.ndarray, steps: int) -> tuple[float, float]:
    """Bound 1 of the module docstring: (m, rad) for a run of `steps` steps through `states`."""
    reach = max(1.0, float(np.max(np.abs(states[:, :2]))))
    turn = max(1.0, float(np.max(np.abs(states[:, 2]))))
    return (max(ROUNDOFF_FLOOR_POSITION, ROUNDOFF_PER_STEP * steps * reach),
            max(ROUNDOFF_FLOOR_ANGLE, ROUNDOFF_PER_STEP * steps * turn))


def motion(states: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Range of the COM path (m) and of the angle (rad) over [0, t], for every t."""
    def running_range(a):
        return np.maximum.accumulate(a) - np.minimum.accumulate(a)
    return np.hypot(running_range(states[:, 0]), running_range(states[:, 1])), running_range(states[:, 2])


def sensitivity(scene: Scene, mujoco_integrator: str, dt: float, twin: np.ndarray):
    """(position (T,) m, angle (T,) rad): at each time, the largest distance from the twin's run
    of two twin runs whose force-law parameters and step are scaled by 1 +- SENSITIVITY_PERTURBATION
    (the step: every update q += h v then rounds differently, as two codes' do) and whose
    initial angle is moved by as much (relative, at least 1 rad: a balanced pose's symmetry is
    broken by the rounding of its lever arms, which no force scale moves); None if one of them
    diverges."""
    from mujoco_models import MujocoDiverged, simulate_dynamics

    spread_pos = np.zeros(len(twin))
    spread_ang = np.zeros(len(twin))
    for sign in (1.0, -1.0):
        f = 1.0 + sign * SENSITIVITY_PERTURBATION
        ct = scene.contact
        ini = scene.initial
        member = dataclasses.replace(
            scene,
            contact=scaled_law(ct, f),
            initial=dataclasses.replace(ini, angle=ini.angle + sign * SENSITIVITY_PERTURBATION * max(1.0, abs(ini.angle))))
        try:
            other = cached(simulate_dynamics)(member, mujoco_integrator, dt * f).states()
        except MujocoDiverged:
            return None
        spread_pos = np.maximum(spread_pos, np.hypot(*(other[:, :2] - twin[:, :2]).T))
        spread_ang = np.maximum(spread_ang, np.abs(other[:, 2] - twin[:, 2]))
    return spread_pos, spread_ang


def scaled_law(contact, f: float):
    """The contact law with each of its parameters scaled by f (a family's absent parameter,
    None under a sign law, stays absent)."""
    names = ("k", "c", "dissipation", "mu", "alpha", "mu_roll", "roll_sharpness")
    return dataclasses.replace(contact, **{n: getattr(contact, n) * f for n in names
                                           if getattr(contact, n) is not None})


def friction_step_number(scene: Scene, states: np.ndarray) -> float:
    """max over the run and the contact points of h mu Fn shape'(v_t) / m_t (tanh: alpha sech^2(alpha v_t)),
    the friction update's h lambda (m_t: 1 / (1/m + r_n^2 / I), r_n the lever normal to the
    ground); above FRICTION_STABILITY an explicit step amplifies any difference. 0 without friction,
    and at a point that carries no load (Fn = 0: no friction whatever the slope, the bare sign's
    infinite one at zero slip too); inf where a loaded point sits on the bare sign's jump."""
    if not (scene.has("contact") and scene.has("friction")):
        return 0.0
    from mujoco_models.rigid_body import rigid_body

    from ..energy.law import normal_law

    rb = rigid_body(scene.body)
    ct = scene.contact
    x, y, th, vx, vy, om = (states[:, j][:, None] for j in range(6))
    lx, ly = rb.points[:, 0], rb.points[:, 1]
    c, s = (np.cos(th), np.sin(th)) if rb.points_rotate else (1.0, 0.0)
    rx, ry = c * lx - s * ly, s * lx + c * ly
    depth = -(y + ry)
    vn, vt = vy + om * rx, vx - om * ry
    fn = np.where(depth > 0.0, normal_law(ct, depth, vn), 0.0)
    inv_mt = 1.0 / rb.mass + (ry * ry / rb.inertia if rb.rotates else 0.0)
    scale, shape = friction_slope(ct, vt)
    inv_mt = np.broadcast_to(inv_mt, fn.shape)
    loaded = fn != 0.0
    rate = np.zeros_like(fn)
    rate[loaded] = scene.dt * ct.mu * scale * fn[loaded] * shape[loaded] * inv_mt[loaded]
    return float(rate.max())


def friction_slope(ct, v):
    """(scale s/m, shape (-)) of each friction family's slope at slip v, d(shape)/dv = scale *
    shape, Ft = -mu Fn shape(v): tanh alpha and sech^2(alpha v); the bare sign's is infinite at
    zero slip (no explicit step is stable there) and 0 elsewhere."""
    if ct.friction_law == "tanh":
        return ct.alpha, 1.0 - np.tanh(ct.alpha * v) ** 2
    if ct.friction_law == "ramp":
        return ct.alpha, np.where(np.abs(ct.alpha * v) < 1.0, 1.0, 0.0)
    if ct.friction_law == "smooth_coulomb":
        return ct.alpha, (1.0 + (ct.alpha * v) ** 2) ** -1.5
    return 1.0, np.where(v == 0.0, np.inf, 0.0)


def _reason(details: dict, judge_angle: bool, passed: bool, steps: int) -> str:
    fr = details["friction_step_number_max"]
    base = (f"round-off of two correct codes, at most {ROUNDOFF_PER_STEP:.2g} relative per step over "
            f"{steps} steps (floor {ROUNDOFF_FLOOR_POSITION:g} m, {ROUNDOFF_FLOOR_ANGLE:g} rad)")
    if details.get("rounding"):
        base += f"; plus the file's rounding at {details['rounding']}"
    if details["bound"] == "sensitivity":
        base += (f"; this motion amplifies round-off: twin runs with the force law scaled by 1 +- "
                 f"{SENSITIVITY_PERTURBATION:.2g} part by {details['sensitivity_position']:.3g} m and "
                 f"{details['sensitivity_angle']:.3g} rad, and the tolerance is {SENSITIVITY_SAFETY:g} times that")
        if details["judged_steps"] < steps:
            base += (f", judged up to t = {details['judged_until']:.6g} s, where it would pass "
                     f"{HORIZON_POSITION:g} m or {HORIZON_ANGLE:g} rad (past it the motion has forgotten "
                     f"its round-off)")
        if fr > FRICTION_STABILITY:
            base += (f"; the friction update is unstable at this step: h mu alpha Fn' / m_t reaches "
                     f"{fr:.3g} > {FRICTION_STABILITY:g}")
    elif "sensitivity_position" in details:
        base += "; the amplification could not be measured (a perturbed twin run diverged)"
    if not judge_angle:
        base += (f"; the angle is shown, not judged: it turns by {details['motion_angle']:.3g} rad in the judged "
                 f"window, less than {1 / MOTION_SHARE:g} times its tolerance "
                 f"{details['tolerance_angle_shown']:.3g} rad")
    if not passed:
        base += (f"; first over at step {details['first_step_over']} (t = {details['time_first_over']:.6g} s): "
                 f"a mistake in the inertia, mass, torque, contact points or the integrator")
    return base


def print_survey(names: list[str]) -> int:
    """custom_sim against the dynamics twin on each scene (default: every built-in and stress
    scene), both integrators, as a Markdown table (`python -m compare tools dynamics-survey`);
    1 when a row fails, else 0."""
    import time

    from compare.scenarios import load
    from compare.table import number, stream
    from custom_sim import simulate

    names = names or _all_scenes()
    failed = 0

    def rows():
        nonlocal failed
        for name in names:
            scene = load(name)
            for integrator in MUJOCO_TWIN:
                begin = time.perf_counter()
                run = dataclasses.replace(scene, integrator=integrator)
                row = check_dynamics(run, simulate(run).states(), integrator, run.dt)
                failed += row.passed is False
                d = row.details
                yield [scene.name, integrator, str(run.steps),
                       *(number(v, none="-") for v in (row.position_error_max, row.angle_error_max,
                                                       row.tolerance_position, row.tolerance_angle)),
                       str(d.get("bound")), number(d.get("judged_until"), none="-"),
                       f"{d.get('friction_step_number_max', 0.0):.3g}", str(row.passed),
                       f"{time.perf_counter() - begin:.1f}"]
    stream(["scene", "integrator", "steps", "position (m)", "angle (rad)", "tolerance (m)", "tolerance (rad)",
            "bound", "judged to (s)", "friction h lambda", "pass", "s"], rows())
    return 1 if failed else 0


def _all_scenes() -> list[str]:
    from pathlib import Path

    root = Path(__file__).resolve().parents[2] / "scenarios"
    return [str(p) for p in sorted(root.glob("*.toml")) + sorted((root / "stress").glob("*.toml"))]
