"""Types that belong to no simulator under test: the scene schema and its contact law, the
trajectory, and the errors for bad input. custom_sim, mujoco_models and the independent
oracle import these and nothing of each other."""
from .errors import BadInput, CsvError, SceneError
from .laws import DAMPING_LAWS, FRICTION_LAWS, ROLL_LAWS, is_seed_law, law_text
from .schema import Body, Contact, Scene, load_scene, parse_scene
from .trajectory import Trajectory, csv_text, read_csv, write_csv

__all__ = ["BadInput", "Body", "Contact", "CsvError", "DAMPING_LAWS", "FRICTION_LAWS", "ROLL_LAWS",
           "Scene", "SceneError", "Trajectory", "is_seed_law", "law_text", "load_scene", "parse_scene",
           "csv_text", "read_csv", "write_csv"]
