"""A user's simulator under test: loading it (step function, whole run, CSV files), running
it on a scene, and diagnosing where it departs from the seed's algorithm."""
from .errors import SceneSkipped, UserCodeError, UserFault
from .loader import StepFunction, TrajectoryFiles, UserRun, WholeFunction, load_simulator, preflight
from .diagnosis import diagnosis, diagnosis_markdown, render_markdown
from .run_user import run_user
from .scene_dict import scene_dict

__all__ = ["SceneSkipped", "StepFunction", "TrajectoryFiles", "UserCodeError", "UserFault", "UserRun", "WholeFunction", "diagnosis", "diagnosis_markdown",
           "load_simulator", "preflight", "render_markdown", "run_user", "scene_dict"]
