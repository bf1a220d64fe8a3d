"""A hand-written 2D penalty contact simulator: point mass, box, compound body, rolling circle."""
from .bodies import MassProperties, mass_properties
from .compile_cache import warm_up
from .integrators import INTEGRATORS, Integrator
from scene_types import Scene, SceneError, load_scene, parse_scene
from .runner import SimulationChattered, SimulationDiverged, Stepper, simulate
from .stability import stable_step
from scene_types import CsvError, Trajectory, read_csv, write_csv

__all__ = [
    "CsvError", "INTEGRATORS", "Integrator", "MassProperties", "Scene", "SceneError", "SimulationChattered",
    "SimulationDiverged",
    "Stepper", "Trajectory", "load_scene", "mass_properties", "parse_scene", "read_csv",
    "simulate", "stable_step", "warm_up", "write_csv",
]
