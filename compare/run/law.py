"""`run --law`: the contact law every check judges the scenes under, in place of each scene's own."""
from __future__ import annotations


def under_law(scenes, law: str, simulator, skipped: dict | None = None):
    """The scenes under `--law`: a law file's [contact] laid over each scene's, or the law
    `identify` finds in the simulator under test (its bad input raised before anything runs).
    A scene the simulator skips keeps its own law (its run skips it too); `skipped`, if given,
    gets each such scene's name and reason."""
    from scene_types import BadInput
    from scene_types.law_file import load_law, with_law

    if law != "identified":
        table = load_law(law)
        return [with_law(s, table, law) for s in scenes]
    if simulator is None:
        raise BadInput("--law identified: expected --sim MODULE:FUNCTION (a step function, or with --whole "
                       "a whole run) or --trajectories DIR, whose law `identify` can find")
    from ..identification import NotIdentified, identified_contact, identify
    from ..usersim import SceneSkipped, UserCodeError, UserFault
    out = []
    for scene in scenes:
        try:
            out.append(with_law(scene, identified_contact(scene, identify(simulator, scene)), "identified"))
        except SceneSkipped as exc:   # a scene the simulator does not do: as it is, its run skips it too
            out.append(scene)
            if skipped is not None:
                skipped[scene.name] = exc.reason
        except NotIdentified as exc:
            raise BadInput(f"--law identified: {exc} (`python -m compare identify` shows each effect)") from None
        except UserFault as exc:
            raise UserCodeError(f"--law identified: {scene.name}: {exc}", getattr(exc, "details", "")) from None
        except UserCodeError as exc:
            raise UserCodeError(f"--law identified: {scene.name}: {exc}", exc.details) from None
    return out
