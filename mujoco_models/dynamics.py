"""MuJoCo's dynamics under our contact law: the dynamics twin.

The same body as the native twin (rigid_body.py's mass, COM and inertia in an explicit
<inertial>, the same joints), but no contact pair: the ground's force is the scene's penalty law,
any family of scene_types.laws (contact_law.py), evaluated by a compiled passive-force callback
(passive.py) at the contact sites, from MuJoCo's own site positions and Jacobians. MuJoCo does
everything else: mass matrix, gravity, the Jacobian transpose that turns contact forces into
joint forces, and the integration. Run with MuJoCo's Euler (velocities first, then positions
with the new velocities: our semi-implicit Euler) or RK4 (classical, on qpos and qvel), it
takes the same steps as a correct simulator of the scene, to round-off.

MuJoCo's implicit integrators are refused: they leave custom passive forces out of the
derivatives they treat implicitly, so they would integrate the contact explicitly while
claiming otherwise.

    simulate_dynamics(scene, integrator="Euler", dt=None)   -> Trajectory ("mujoco_dynamics")

Switches for the attribution ladder (see passive.py): native_normal=True keeps MuJoCo's own
normal contact (condim-1 pairs, the scene's solref mapping) and adds only our friction and
rolling resistance; friction_at="midpoint" applies friction where MuJoCo puts its contact point.
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
    native_normal, friction_at: module docstring; solref: the mapping of the native normal
    contact (default the scene's)."""
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

