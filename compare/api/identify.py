"""compare.identify(sim, scenes): which contact law a simulator implements, scene by scene, as
`identify --json` prints it (one Identification per scene)."""
from __future__ import annotations

from .identification import Identification


def identify_scenes(sim, scenes=None, *, whole: bool = False) -> tuple[Identification, ...]:
    """identify's answer for each scene (None: every built-in), in order. sim: "MODULE:FUNCTION",
    a step function (with whole=True simulate(scene): by regression over its run), or
    compare.Process("COMMAND"). A scene the code does not do is an Identification with
    `skipped` (the reason) and no effects. Bad input, or a step that fails on a designed probe, raises
    compare.BadInput naming the function and the probe (identify's exit status 2)."""
    from ..identification import identify
    from ..scenarios import load_all
    from ..usersim import SceneSkipped, UserCodeError, UserFault
    from .judge import scene_specs
    from .subject import simulator_of

    simulator = simulator_of(sim, whole)
    if simulator is None:
        raise UserCodeError("identify: expected sim (\"MODULE:FUNCTION\", a step function, or compare.Process)")
    out = []
    for scene in load_all(scene_specs(scenes)):
        try:
            out.append(Identification.from_result(identify(simulator, scene)))
        except SceneSkipped as exc:   # a scene the code does not do: the object identify --json prints for it
            out.append(Identification.from_result({"scene": scene.name, "skipped": exc.reason}))
        except UserFault as exc:
            raise UserCodeError(str(exc).removeprefix("--sim ")) from None
    return tuple(out)
