"""Check `contact`: the trajectory under test against MuJoCo's own contact (penalty mapping),
friction off, held to a tolerance set by the mapping's measured error and the motion's
sensitivity to it.

What is compared: the scene with friction and rolling resistance off and the linear damping
law (MuJoCo's contact damps both ways and never pulls: the seed's compression law is not in
it), run by the simulator under test and by MuJoCo's native contact with the penalty mapping.
The two then share every modelled force; what separates them is known and measured:

1. the mapping's force error e (impedance.py): MuJoCo's force is k depth - c v - e, read from
   MuJoCo's own rows along its run, eps = max sum |e| / sum f (a few 1e-4);
2. the motion's sensitivity to that error: an ensemble of custom_sim runs whose contact force
   (k, c) or contact torque (inverse inertia) is off by up to eps (sensitivity.py). Its spread
   s(t) is how far a force error of eps moves the body by time t;
3. the integrator, when the one under test is not MuJoCo's (explicit or implicit Euler against
   MuJoCo's Euler, or another dt): the measured difference between custom_sim's run with the
   scene's integrator and dt and with MuJoCo's.

Tolerance = SENSITIVITY_MARGIN x max s + the integrator term + ROUND_OFF, on the largest
difference in the judged window. No tolerance may exceed a tenth of the motion it judges
(MOTION_SHARE; the motion is the range of the COM path, and of the angle, over the window):
where the spread grows past that (a tumbling body, whose motion amplifies any difference), the
comparison stops at the divergence horizon, the last time at which it still holds. Where the
horizon comes before the first contact has done anything, the check is not judged, and says
why. The angle is judged only for a body that turns by more than ten times its tolerance.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from custom_sim import INTEGRATORS, Scene, SimulationDiverged
from custom_sim.bodies import contact_points_world
from scene_types.integrators import SAME_UPDATE

from ..store import cached
from ..oracle.reference import ReferenceFailed as NoReference
from .case import as_case
from .impedance import NativeDiverged, native_run
from .row import CheckRow
from .sensitivity import spread

NAME = "contact"
ISOLATES = ("MuJoCo's own contact (penalty mapping), friction off: the normal contact force, "
            "the body's mass and inertia and the contact points' kinematics")
# The ensemble perturbs the force by constant shares of eps; MuJoCo's error varies within
# the run (A / A_hat runs from 1.5 to 5.3 along a box's tumble) and between corners, so its
# effect can exceed every member's. Measured on every built-in and stress scene, the twin's
# difference reached 1.47 times the spread (resting_60s's angle; docs/differences-from-mujoco.md).
SENSITIVITY_MARGIN = 2.0
MOTION_SHARE = 0.1      # no judged tolerance above a tenth of the motion it judges
# Two codes adding the same forces in another order part by rounding: about 1e-16 of each
# coordinate per step, 1e-16 * 1e5 steps * 1 m = 1e-11 m; the floor is a hundred times that.
ROUND_OFF_POSITION = 1e-9   # m
ROUND_OFF_ANGLE = 1e-9      # rad


def contact_scene(scene: Scene) -> Scene:
    """The scene the check runs: friction and rolling resistance off, the linear damping law.
    A simulator under test must be run on this scene for states_under_test."""
    effects = tuple(e for e in scene.effects if e not in ("friction", "rolling_friction"))
    return dataclasses.replace(scene, effects=effects,
                               contact=dataclasses.replace(scene.contact, damping_law="linear"))


# In the friction-off variant no horizontal force acts (the normal force and gravity are
# vertical): every integrator keeps vx exactly (vx + h * 0). A change beyond a few ulps of vx is
# a horizontal force of the step's own.
FRICTION_OFF_ULPS = 4.0


def horizontal_force(scene: Scene, states: np.ndarray) -> dict | None:
    """Where a run states (steps + 1, 6) of contact_scene(scene) changes vx, which no force of
    that variant does: {step, time, dvx (m/s), force (N, m dvx / dt), text}; else None."""
    vx = np.asarray(states, dtype=float)[:, 3]
    dvx = np.diff(vx)
    bound = FRICTION_OFF_ULPS * np.finfo(float).eps * np.maximum(np.abs(vx[:-1]), np.abs(vx[1:]))
    off = np.flatnonzero(np.abs(dvx) > bound)
    if not off.size:
        return None
    i = int(off[0])
    force = scene.body.mass * dvx[i] / scene.dt
    return {"step": i + 1, "time": (i + 1) * scene.dt, "dvx": float(dvx[i]), "force": float(force),
            "text": (f"your step applied a horizontal force in this friction-off variant (effects "
                     f"{', '.join(scene.effects)}): vx changed by {dvx[i]:+.3g} m/s at step {i + 1} "
                     f"(t = {(i + 1) * scene.dt:.6g} s), a force of {force:+.3g} N where none acts (does "
                     "it read scene['effects']?)")}


def converged(scene: Scene, t: np.ndarray) -> np.ndarray:
    """The scene's model solved to convergence (the reference), at times t (s): (len(t), 6)."""
    from ..oracle.reference import solve_reference
    return solve_reference(scene, t).states


def _row(integrator: str, reason: str, **values) -> CheckRow:
    return CheckRow(NAME, ISOLATES, integrator, reason=reason, **values)


def not_judged(integrator: str, why: str) -> CheckRow:
    """The row of a contact check that could not be judged, and why."""
    return _row(integrator, f"not judged: {why}")


def _motion(states: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Range of the COM path (m) and of the angle (rad) over [0, t], for every t."""
    def running_range(a):
        return np.maximum.accumulate(a) - np.minimum.accumulate(a)
    return np.hypot(running_range(states[:, 0]), running_range(states[:, 1])), running_range(states[:, 2])


def _on_grid(t_from: np.ndarray, states: np.ndarray, t: np.ndarray) -> np.ndarray:
    return np.column_stack([np.interp(t, t_from, states[:, j]) for j in range(6)])


def check_contact(scene: Scene, states_under_test: np.ndarray | None = None, integrator: str | None = None,
                  case=None) -> CheckRow:
    """The contact check's row (docs/report-files.md). states_under_test: (steps + 1, 6) states of
    contact_scene(scene) at the scene's dt from the simulator under test; None: custom_sim.
    integrator: the one the simulator under test steps with (default: the scene's); for one the
    harness does not know ("other:NAME"), the integrator term is MuJoCo's own integration error
    against the converged solution, and the simulator's own error counts against it. case: the
    scenario's Case (case.py), which runs each custom_sim variant once."""
    case = as_case(scene, case)
    bare = contact_scene(scene)
    integrator = integrator or scene.integrator
    known = integrator in INTEGRATORS
    if known and integrator != bare.integrator:
        bare = dataclasses.replace(bare, integrator=integrator)
    if not bare.has("contact"):
        return _row(integrator, "not judged: the scene has no contact, so there is no contact to isolate")
    try:
        under = case.states(bare, bare.integrator, bare.dt) if states_under_test is None \
            else np.asarray(states_under_test, dtype=float)
        # 1. the mapping's force error, read from MuJoCo along the same run
        native, twin, error = cached(native_run)(bare)
    except (SimulationDiverged, NativeDiverged) as exc:
        return _row(integrator, f"not judged: with friction off the run diverged ({exc})")
    if under.ndim != 2 or under.shape[1] != 6 or len(under) < 2:
        return _row(integrator, f"not judged: the states under test have shape {under.shape}, "
                                f"expected (steps + 1, 6)")
    # finite: the run under test is validated once where it is collected, the user's run of the
    # variant where it is read (compare/usersim run_user: the healthy range)
    t_under = np.arange(len(under)) * bare.dt
    t = np.arange(len(native)) * twin.dt
    t = t[t <= t_under[-1] + 1e-12]
    native = native[:len(t)]
    tested = _on_grid(t_under, under, t)

    # 2. the motion's sensitivity to the force error
    same = SAME_UPDATE[twin.integrator]
    try:
        centre, s_pos, s_ang, chosen = spread(bare, error.relative, same, twin.dt, error.torque_relative,
                                              centre=case.states(bare, same, twin.dt))
        # 3. the integrator and step, when the one under test is not MuJoCo's
        if not known:
            own = converged(bare, t)
            integ_pos = np.hypot(own[:, 0] - centre[:len(t), 0], own[:, 1] - centre[:len(t), 1])
            integ_ang = np.abs(own[:, 2] - centre[:len(t), 2])
        elif (same, twin.dt) != (bare.integrator, bare.dt):
            own = _on_grid(t_under, case.states(bare, bare.integrator, bare.dt), t)
            integ_pos = np.hypot(own[:, 0] - centre[:len(t), 0], own[:, 1] - centre[:len(t), 1])
            integ_ang = np.abs(own[:, 2] - centre[:len(t), 2])
        else:
            integ_pos = integ_ang = np.zeros(len(t))
    except SimulationDiverged as exc:
        return _row(integrator, f"not judged: custom_sim's ensemble diverged ({exc})")
    except NoReference as exc:
        return _row(integrator, f"not judged: {integrator} is an integrator the harness does not know, and the "
                                f"converged solution that would stand in for it could not be found ({exc})")
    s_pos, s_ang = s_pos[:len(t)], s_ang[:len(t)]

    d_pos = np.hypot(tested[:, 0] - native[:, 0], tested[:, 1] - native[:, 1])
    d_ang = np.abs(tested[:, 2] - native[:, 2])
    tol_pos = SENSITIVITY_MARGIN * np.maximum.accumulate(s_pos) + np.maximum.accumulate(integ_pos) + ROUND_OFF_POSITION
    tol_ang = SENSITIVITY_MARGIN * np.maximum.accumulate(s_ang) + np.maximum.accumulate(integ_ang) + ROUND_OFF_ANGLE
    motion_pos, motion_ang = _motion(native)
    turns = twin.props.rotates
    # the divergence horizon: the last time at which the tolerance is within a tenth of the motion
    # (tolerance and motion only grow, so the window [0, t] then obeys the rule); for a body that
    # has turned by ten times its angle tolerance, the angle's too
    ok = tol_pos <= MOTION_SHARE * motion_pos
    if turns:
        turned = np.logical_or.accumulate(tol_ang <= MOTION_SHARE * motion_ang)
        ok &= ~turned | (tol_ang <= MOTION_SHARE * motion_ang)
    ok[0] = False
    end = int(np.flatnonzero(ok)[-1]) + 1 if np.any(ok) else 1
    horizon = float(t[end - 1])
    _, py = contact_points_world(twin.props, native[:end, 0], native[:end, 1], native[:end, 2])
    touched = np.flatnonzero(np.any(py < 0.0, axis=1))
    extra = {"judged_until": horizon, "duration": float(t[-1]), "mapping_error": error.as_dict(),
             "ensemble": [{"force_scale": f, "torque_scale": q} for f, q in chosen],
             "sensitivity_margin": SENSITIVITY_MARGIN,
             "spread_position_max": float(s_pos[:end].max()), "spread_angle_max": float(s_ang[:end].max()),
             "integrator_position_max": float(integ_pos[:end].max()),
             "motion_position": float(motion_pos[end - 1]), "motion_angle": float(motion_ang[end - 1]),
             "mujoco_integrator": twin.integrator, "mujoco_dt": twin.dt,
             "position_error_max_run": float(d_pos.max()), "angle_error_max_run": float(d_ang.max())}
    if len(touched) == 0 or end - touched[0] < 2:
        why = ("the body never touches the ground" if end == len(t) else
               "the motion's sensitivity to the mapping's force error (and the integrator's difference) "
               f"stays above a tenth of the motion after t = {horizon:.4g} s, before any contact")
        return _row(integrator, f"not judged: {why}", position_error_max=float(d_pos.max()),
                    angle_error_max=float(d_ang.max()), details=extra)
    pos_max, ang_max = float(d_pos[:end].max()), float(d_ang[:end].max())
    tp, ta = float(tol_pos[end - 1]), float(tol_ang[end - 1])
    judge_angle = turns and motion_ang[end - 1] >= ta / MOTION_SHARE
    passed = pos_max <= tp and (ang_max <= ta if judge_angle else True)
    window = "the whole run" if end == len(t) else (
        f"up to the divergence horizon t = {horizon:.4g} s of {t[-1]:.4g} s (beyond it the motion's "
        f"sensitivity to the mapping's error exceeds a tenth of the motion)")
    reason = (f"{SENSITIVITY_MARGIN:g} x the spread of {len(chosen)} custom_sim runs whose contact force or "
              f"torque is off by up to the penalty mapping's measured error ({error.relative:.2g} of the force, "
              f"{error.torque_relative:.2g} of the torque; MuJoCo's "
              f"A / A_hat from {error.ratio_min:.3g} to {error.ratio_max:.3g})"
              + ((f", plus the integrator difference ({bare.integrator}, dt {bare.dt:g} s against MuJoCo's "
                  f"{twin.integrator}, dt {twin.dt:g} s)" if known else
                  f", plus MuJoCo's own integration error ({twin.integrator}, dt {twin.dt:g} s) against the "
                  f"converged solution: {integrator} is not an integrator the harness can run, so its own error "
                  "counts against it") if extra["integrator_position_max"] > 0 else "")
              + f"; over {window}, where MuJoCo's run (friction off) moves by {motion_pos[end - 1]:.3g} m"
              + (f" and turns by {motion_ang[end - 1]:.3g} rad" if turns else "")
              + (f" (the tolerance is at most {MOTION_SHARE:g} of that)")
              + ("" if judge_angle or not turns else
                 f"; the angle is shown, not judged: the body turns by less than {1 / MOTION_SHARE:g} times "
                 f"its tolerance ({ta:.3g} rad)"))
    first = np.flatnonzero(d_pos[:end] > tp)
    extra["first_exceeding_time"] = float(t[first[0]]) if len(first) else None
    return _row(integrator, reason, position_error_max=pos_max, angle_error_max=ang_max, tolerance_position=tp,
                tolerance_angle=ta if judge_angle else None, passed=passed, details=extra)
