"""Which contact law a user's simulator implements: each effect's family and parameters, or none."""
from .contact import NotIdentified, identified_contact, identified_scene
from .from_step import identify_step
from .whole_run import identify_run

__all__ = ["NotIdentified", "identified_contact", "identified_scene", "identify", "identify_run", "identify_step"]


def identify(simulator, scene) -> dict:
    """The identification of one scene for the simulator under test (compare.usersim): from
    designed calls of a step function, else by regression over its run (a whole run, CSVs).
    SceneSkipped for a scene the simulator does not do (its SHAPES: before any call)."""
    from ..usersim.errors import SceneSkipped
    reason = simulator.skip_reason(scene) if hasattr(simulator, "skip_reason") else None
    if reason:
        raise SceneSkipped(reason)
    if simulator.kind == "step":
        return identify_step(simulator, scene)
    run = simulator.run(scene)
    return identify_run(run.states, scene, run.rounding, simulator.kind)

