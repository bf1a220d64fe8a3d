"""The simulator under test, brought in one of three ways, each giving states (steps + 1, 6).

    --sim MODULE:FUNCTION           step(state, scene, dt) -> state          StepFunction
    --sim MODULE:FUNCTION --whole   simulate(scene) -> array (steps + 1, 6)   WholeFunction
    --trajectories DIR              DIR/<scene name>.csv                      TrajectoryFiles
    --sim-process "COMMAND"         a step function in any language           Process (process.py)

state = [x, y, theta, vx, vy, omega] (m, m, rad, m/s, m/s, rad/s) of the centre of mass; scene
= scene_dict(scene), the resolved scene as plain dicts and floats. MODULE is a dotted module
name (importable from the current folder) or a path to a .py file. A simulator may name the
integrator it implements in a module-level INTEGRATOR (a string; default: the scene's), and a
--whole function may return a 7th column, the energy (J). A module's SHAPES (e.g. ("box",)), or
NotImplementedError from its function, skips a scene: SceneSkipped, never judged. A folder of trajectories may hold a
simulator.toml with `integrator = "..."`.

A fault of the protocol (a module that does not import, a wrong return, a misspelled
INTEGRATOR, ending the process) is a UserCodeError: bad input, exit 2, naming the function or
the file (row, column), what was wrong and what was expected. A fault of one scene's run (an
exception, a NaN, a blow-up) is a UserFault: that scene's error row.
"""
from __future__ import annotations

from .base import UserRun
from .csv_files import TrajectoryFiles
from .errors import UserCodeError
from .functions import StepFunction, WholeFunction
__all__ = ["StepFunction", "TrajectoryFiles", "UserRun", "WholeFunction", "load_simulator", "preflight"]


def preflight(simulator, scenes) -> None:
    """Find bad input before any scene runs, without calling the user's code (a call here would
    leave its module in another state than the one each scene starts from): the integrator it
    declares for every scene, and every scene's CSV read and checked. A function's faults show
    when its scene runs (a wrong return is still bad input: nothing is written)."""
    for scene in scenes:
        simulator.integrator_for(scene)
        if simulator.kind == "trajectories":
            simulator.run(scene)


def load_simulator(spec: str | None = None, whole: bool = False, trajectories: str | None = None,
                   process: str | None = None):
    """The simulator under test: --sim spec (a step function, or with whole=True a simulate
    function), trajectories=DIR (a folder of CSVs), or process=COMMAND (--sim-process, a step
    function in any language). None when none is given (custom_sim)."""
    if process is not None:
        if spec is not None or trajectories is not None or whole:
            raise UserCodeError("--sim-process: expected one simulator under test (not with --sim, "
                                "--trajectories or --whole)")
        from .process import Process
        return Process(process)
    if trajectories is not None:
        if spec is not None:
            raise UserCodeError("--sim and --trajectories: expected one simulator under test, got both")
        return TrajectoryFiles(trajectories)
    if spec is None:
        if whole:
            raise UserCodeError("--whole: expected it with --sim MODULE:FUNCTION")
        return None
    return WholeFunction(spec) if whole else StepFunction(spec)
