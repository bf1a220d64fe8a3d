"""MuJoCo's dynamics under our contact law: the dynamics twin.

The native twin's body and joints, but no contact pair: the scene's contact law, any family
(contact_law.py), is applied by a compiled passive-force callback (passive.py) at the contact
sites; MuJoCo does everything else. MuJoCo's Euler (our semi-implicit Euler) or RK4 integrates;
its implicit integrators are refused (they leave passive forces out of their derivatives).

    simulate_dynamics(scene, integrator="Euler", dt=None, *, native_normal=False,
                      friction_at="corner")   -> Trajectory ("mujoco_dynamics"), dt in s

native_normal and friction_at are the attribution ladder's switches.
See docs/mujoco-twins.md#the-dynamics-twin-dynamicspy-passivepy-contact_lawpy.
"""
from __future__ import annotations

from scene_types.laws import law_text
from scene_types.integrators import MUJOCO_TWIN, SAME_UPDATE
from scene_types.schema import Scene
from scene_types.trajectory import Trajectory

from .passive import installed, law_parameters
from .run import setup_rollout, timed_rollout, trajectory_from
from .sites import contact_below_site

INTEGRATORS = ("Euler", "RK4")
STAGES = {"Euler": 1, "RK4": 4}   # mj_forward calls per mj_step: the law is evaluated once per call


def simulate_dynamics(scene: Scene, integrator: str = "Euler", dt: float | None = None, *,
                      native_normal: bool = False, friction_at: str = "corner",
                      solref: str | None = None) -> Trajectory:
    """Run the dynamics twin for the scene's duration. integrator: Euler | RK4 (MuJoCo's names;
    semi_implicit_euler and rk4 are accepted too); dt (s), default the scene's dt.
    native_normal, friction_at: the switches of docs/mujoco-twins.md; solref: the mapping of the
    native normal contact (default the scene's)."""
    integrator = MUJOCO_TWIN.get(integrator, integrator)
    if integrator not in INTEGRATORS:
        raise ValueError(f"the dynamics twin runs MuJoCo's Euler or RK4, not {integrator!r}: MuJoCo's "
                         f"implicit integrators leave passive forces out of their derivatives")
    dt = float(dt or scene.dt)
    pairs = "normal" if native_normal and scene.has("contact") else "none"
    twin, model, data, start, n = setup_rollout(scene, solref, integrator, dt, pairs=pairs)
    below = contact_below_site(scene.body)
    params = law_parameters(scene, twin.props, below, native_normal=native_normal, friction_at=friction_at)
    with installed(model, data, params) as reg:
        rows, sensors, wall = timed_rollout(model, data, start, n, before_timed=reg.reset_calls)
        evals = reg.calls
        meta = {
            "contact_law": "callback",
            "law": law_text(scene.contact),
            "native_normal": bool(native_normal),
            "friction_at": friction_at,
            "contact_pairs": twin.n_pairs,
            "contact_sites": int(model.nsite),
            "same_update_as": SAME_UPDATE[integrator],
            "mass": float(model.body_mass[1]),
            "inertia": list(map(float, model.body_inertia[1])),
            "com": list(twin.props.com),
            "gravity": list(map(float, model.opt.gravity)),
        }
        if native_normal:
            meta.update(solref_mapping=twin.contact.mapping, solref=list(twin.contact.solref),
                        solimp=list(twin.contact.solimp))
        return trajectory_from(twin, model, data, rows, sensors, wall, "mujoco_dynamics", evals, meta)

