"""MuJoCo twins of the scenes: MJCF generated with MjSpec from the same scene file that drives
custom_sim, run with MuJoCo's own loop, returned as the same Trajectory type.

    build_spec / build_model / to_mjcf   spec.py      the model (geometry.py, inertial.py, effects.py)
    solref_for, contact_parameters       solref.py    penalty | physical | seed (friction.py)
    simulate_mujoco                      run.py       rollout, energy, meta["approximations"]
"""
from .dynamics import simulate_dynamics
from .run import MujocoDiverged, simulate_mujoco
from .solref import MAPPINGS, ContactParameters, contact_parameters, solref_for
from .spec import Twin, build_model, build_spec, build_twin, to_mjcf

__all__ = [
    "MAPPINGS", "ContactParameters", "MujocoDiverged", "Twin", "build_model", "build_spec",
    "build_twin", "contact_parameters", "simulate_dynamics", "simulate_mujoco", "solref_for", "to_mjcf",
]
