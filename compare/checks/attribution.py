"""Every difference measured: a ladder of runs from MuJoCo's native contact to custom_sim, each
rung removing one named cause.

    native          MuJoCo's own contact, penalty mapping, every effect of the scene
    friction law    MuJoCo's normal contact; friction (and rolling resistance) ours, mu Fn tanh(alpha v),
                    applied where MuJoCo puts its contact point, mid-way through the penetration
    shared cone     (scenes with rolling resistance: removed with the friction law, see below)
    contact point   the same, with friction applied and slip measured at our contact point
    mapping         custom_sim with the linear damping law: our exact spring-damper k d - c v in place of
                    MuJoCo's penalty row (and custom_sim's integrator at MuJoCo's update and step)
    integrator      custom_sim with the scene's integrator and step (only when MuJoCo has neither)
    damping law     custom_sim itself, with the scene's damping law (any family but linear)

Each rung is one run; its position_error_max and angle_error_max are measured against
custom_sim's run of the scene, and its share the fall of those from the rung before (negative
when removing the cause moved the run away). `step_position` is the largest distance between
the rung's run and the one before: what that cause changes on its own.

MuJoCo's rolling rows share the elliptic cone with the sliding rows, and MuJoCo cannot have its
own sliding friction without them: the friction-law rung therefore also removes the shared cone
and rolling, and says so. The rungs with our friction inside MuJoCo use the dynamics twin
(mujoco_models.simulate_dynamics, friction through the passive-force callback).
"""
from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np

from custom_sim import Scene, SimulationDiverged
from scene_types.integrators import SAME_UPDATE

from ..store import cached
from .case import as_case


CAUSES = {
    "native": "MuJoCo's own contact with the penalty mapping and every effect of the scene: all the "
              "causes below together.",
    "friction law": "MuJoCo's friction is viscous, c_t v with the scene law's slope at the resting load, capped "
                    "at mu Fn; ours is {friction}, whose grip grows with the load, so during an impact "
                    "(loads of tens of m g) ours stops a sliding contact much sooner.",
    "friction law and shared cone": "MuJoCo's friction is viscous, capped at mu Fn, and its rolling resistance "
                                    "shares that one cap (the elliptic cone) with sliding, so while a disk "
                                    "slides it has almost none; ours is {friction} with mu_roll Fn of "
                                    "rolling resistance beside it.",
    "contact point": "MuJoCo puts a contact's point mid-way through the penetration, d/2 above our corner "
                     "(d reaches about a centimetre at an impact), and applies friction and measures slip "
                     "there: the friction's lever arm about the centre of mass is shorter than ours.",
    "mapping": "MuJoCo's penalty row gives our spring-damper only up to a relative d (A / A_hat - 1) "
               "(a few 1e-4: A the contact's true inverse inertia, A_hat MuJoCo's constant estimate), "
               "and tumbling motion amplifies that small force difference.",
    "integrator": "custom_sim's own integrator and step, which MuJoCo has not (MuJoCo has no explicit or "
                  "implicit Euler for contact forces).",
    "damping law": "{damping}; MuJoCo's contact is a spring-damper that damps both ways and never pulls (our "
                   "linear law).",
}
# what each family is, for the causes above
FRICTION_PHRASE = {"tanh": "mu Fn tanh(alpha v)", "ramp": "a stiction ramp mu Fn clamp(alpha v, -1, 1)",
                   "smooth_coulomb": "mu Fn v / sqrt(v^2 + 1/alpha^2)", "sign": "bare Coulomb mu Fn sign(v)"}
DAMPING_PHRASE = {
    "compression": "the scene's compression law damps only while a point approaches the ground, so the body "
                   "leaves the ground faster and bounces higher than under MuJoCo's",
    "linear": "the scene's linear law is MuJoCo's kind",
    "unclamped": "the scene's unclamped law k d - c v_n pulls the body down while a point separates fast",
    "hunt_crossley": "the scene's Hunt-Crossley law k d (1 - dissipation v_n) has no damping at touchdown and "
                     "damps in proportion to the depth; MuJoCo's penalty twin of it is an undamped spring "
                     "(c = 0), so the whole dissipation is this rung's",
}


def cause(name: str, scene: Scene) -> str:
    """The rung's cause in words, naming the scene's own friction and damping families."""
    ct = scene.contact
    return CAUSES[name].format(friction=FRICTION_PHRASE[ct.friction_law], damping=DAMPING_PHRASE[ct.damping_law])


def _linear(scene: Scene) -> Scene:
    return dataclasses.replace(scene, contact=dataclasses.replace(scene.contact, damping_law="linear"))


def _distance(a: np.ndarray, b: np.ndarray) -> tuple[float, float]:
    n = min(len(a), len(b))
    return (float(np.max(np.hypot(a[:n, 0] - b[:n, 0], a[:n, 1] - b[:n, 1]))),
            float(np.max(np.abs(a[:n, 2] - b[:n, 2]))))


def _on_grid(states: np.ndarray, dt_from: float, dt_to: float, steps: int) -> np.ndarray:
    if dt_from == dt_to:
        return states
    t_from = np.arange(len(states)) * dt_from
    t = np.arange(steps + 1) * dt_to
    t = t[t <= t_from[-1] + 1e-12]
    return np.column_stack([np.interp(t, t_from, states[:, j]) for j in range(6)])


def rungs(scene: Scene, native_run=None, case=None) -> list[tuple[str, Callable[[], np.ndarray]]]:
    """(name, run) of each rung; run() returns states at the scene's dt (steps + 1, 6).
    native_run: the native twin's Trajectory (penalty mapping) when already run; case: the
    scenario's Case, which runs each custom_sim variant once."""
    from mujoco_models import simulate_mujoco

    case = as_case(scene, case)
    ours = case.states
    mj_integrator = scene.mujoco.integrator
    mj_dt = scene.mujoco.dt or scene.dt
    same = SAME_UPDATE[mj_integrator]
    callback_integrator = mj_integrator if mj_integrator in ("Euler", "RK4") else "Euler"

    def mujoco_states(traj):
        return _on_grid(traj.states(), traj.dt, scene.dt, scene.steps)

    def native():
        return mujoco_states(native_run or cached(simulate_mujoco)(scene, solref="penalty"))

    def ours_inside_mujoco(at):
        def run():
            from mujoco_models import simulate_dynamics
            # the friction's load Fn is the scene's law at the site's depth (MuJoCo solves its own
            # normal force after the passive forces): the linear law, which MuJoCo's normal follows
            return mujoco_states(cached(simulate_dynamics)(_linear(scene), callback_integrator, mj_dt,
                                                   native_normal=True, friction_at=at, solref="penalty"))
        return run

    out = [("native", native)]
    if scene.has("contact") and (scene.has("friction") or scene.has("rolling_friction")):
        name = "friction law and shared cone" if scene.has("rolling_friction") else "friction law"
        out += [(name, ours_inside_mujoco("midpoint")), ("contact point", ours_inside_mujoco("corner"))]
    if scene.has("contact"):
        lin = _linear(scene)
        out.append(("mapping", lambda: _on_grid(ours(lin, same, mj_dt), mj_dt, scene.dt, scene.steps)))
        if (same, mj_dt) != (scene.integrator, scene.dt):
            out.append(("integrator", lambda: ours(lin, scene.integrator, scene.dt)))
        if scene.contact.damping_law != "linear":
            out.append(("damping law", lambda: ours(scene, scene.integrator, scene.dt)))
    return out


def attribute(scene: Scene, native=None, case=None) -> list[dict]:
    """The ladder (module docstring): one dict per rung with name, cause, position_error_max (m),
    angle_error_max (rad) against custom_sim, share_position / share_angle (the fall from the rung
    before, m / rad), step_position / step_angle (distance to the rung before), measured (bool),
    and note (why a rung could not be run). native: the native twin's Trajectory with the
    penalty mapping, if the caller has run it."""
    from mujoco_models import MujocoDiverged

    case = as_case(scene, case)
    reference = case.states(scene, scene.integrator, scene.dt)
    out: list[dict] = []
    before: tuple[np.ndarray, dict] | None = None
    for name, run in rungs(scene, native, case):
        row = {"name": name, "cause": cause(name, scene), "measured": False, "note": "",
               "position_error_max": None, "angle_error_max": None, "share_position": None,
               "share_angle": None, "step_position": None, "step_angle": None}
        try:
            states = run()
        except (SimulationDiverged, MujocoDiverged) as exc:
            row["note"] = f"diverged: {exc}"
            out.append(row)
            before = None
            continue
        except ImportError:
            row["note"] = "needs the dynamics twin (mujoco_models.simulate_dynamics)"
            out.append(row)
            before = None
            continue
        pos, ang = _distance(states, reference)
        row.update(measured=True, position_error_max=pos, angle_error_max=ang)
        if before is not None:
            prev_states, prev = before
            row["share_position"] = prev["position_error_max"] - pos
            row["share_angle"] = prev["angle_error_max"] - ang
            row["step_position"], row["step_angle"] = _distance(states, prev_states)
        out.append(row)
        before = (states, row)
    return out
