"""MuJoCo twins of the scenes, built with MjSpec from the scene file alone and run by MuJoCo,
returned as the same Trajectory type as custom_sim.simulate. Nothing here is derived from
custom_sim: only the shared types (scene_types: the scene, its law, the Trajectory) are imported.

    native     MuJoCo's own contact, one of three solref mappings (penalty | physical | seed)
               simulate_mujoco(scene, solref=None, integrator=None, dt=None)          run.py
    dynamics   the scene's contact law applied by a passive-force callback (passive.py)
               simulate_dynamics(scene, integrator="Euler", dt=None, ...)              dynamics.py

    build_twin / build_spec / build_model / to_mjcf   spec.py (geometry, inertial, sites, sensors, effects)
    solref_for, contact_parameters                    solref.py (friction.py)
    energy from MuJoCo's sensors, blow-up guard       energy.py, guard.py

The whole design: docs/mujoco-twins.md.
"""
from .dynamics import simulate_dynamics
from .rigid_body import RigidBody, rigid_body
from .run import MujocoDiverged, simulate_mujoco
from .solref import MAPPINGS, ContactParameters, contact_parameters, solref_for
from .spec import Twin, build_model, build_spec, build_twin, to_mjcf

__all__ = [
    "MAPPINGS", "ContactParameters", "MujocoDiverged", "RigidBody", "Twin", "build_model",
    "build_spec", "build_twin", "contact_parameters", "rigid_body", "simulate_dynamics",
    "simulate_mujoco", "solref_for", "to_mjcf",
]
