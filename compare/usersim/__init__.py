"""The subject: a user's simulator under test, loaded (step function, whole run, CSV files, a
process in any language), called behind a guard, and run on a scene. The lowest layer that
touches the user's code: it imports no check, no diagnosis and no report."""
from .errors import SceneSkipped, UserCodeError, UserFault
from .loader import StepFunction, TrajectoryFiles, UserRun, WholeFunction, load_simulator, preflight
from .run_user import run_user
from .scene_dict import scene_dict

__all__ = ["SceneSkipped", "StepFunction", "TrajectoryFiles", "UserCodeError", "UserFault", "UserRun", "WholeFunction",
           "load_simulator", "preflight", "run_user", "scene_dict"]
