"""Types that belong to no simulator under test: the scene schema and its contact law, the
trajectory and the state's components and units, the errors for bad input and the base of every
"diverged" run. custom_sim, mujoco_models and the independent oracle import these and nothing of
each other."""
from .errors import BadInput, CsvError, Diverged, SceneError
from .laws import DAMPING_LAWS, FRICTION_LAWS, ROLL_LAWS, is_seed_law, law_text
from .schema import Body, Contact, Scene, load_scene, parse_scene
from .state import STATE_COMPONENTS, STATE_UNITS, UNIT_OF
from .trajectory import Trajectory, csv_text, read_csv, write_csv

__all__ = ["BadInput", "Body", "Contact", "CsvError", "DAMPING_LAWS", "Diverged", "FRICTION_LAWS", "ROLL_LAWS",
           "STATE_COMPONENTS", "STATE_UNITS", "Scene", "SceneError", "Trajectory", "UNIT_OF", "is_seed_law", "law_text",
           "load_scene", "parse_scene", "csv_text", "read_csv", "write_csv"]
