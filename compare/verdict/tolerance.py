"""The full-effects comparison against MuJoCo's native contact: shown, with its attribution,
not judged by an upper bound.

With every effect on, custom_sim and MuJoCo's native contact differ by causes that are models,
not mistakes (the friction law, the shared cone, the mid-penetration contact point, the damping
law, the mapping). Upper bounds on them exceeded the motion itself (0.38 m on a box that moves
0.3 m), so they could not tell a right simulator from a wrong one. Instead:

    judged     check `contact` (contact_check.py): native contact, friction off, the linear law,
               against the mapping's measured error and the motion's sensitivity to it
    measured   the difference with every effect on, split cause by cause (attribution.py)

`derive` is kept for its callers: it returns the full comparison's Tolerance, which is "not
judged" (checked False, position and angle None) unless the scene file sets a [tolerance],
the user's own bound with its reason, which is then judged.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from custom_sim import Scene

NOT_JUDGED = ("not judged: with every effect on the two differ by named models (friction law, "
              "contact point, damping law, mapping), each measured in the attribution; the judged "
              "comparison is check `contact` (friction off)")


@dataclass(frozen=True)
class Tolerance:
    position: float | None       # m, on the maximum position difference (None: not judged)
    angle: float | None          # rad, on the maximum angle difference (None: not judged)
    terms: dict = field(default_factory=dict)   # kept for callers: no bound terms any more
    reason: str = NOT_JUDGED
    checked: bool = False        # True only for a tolerance set in the scene file


def derive(scene: Scene, mapping: str | None = None) -> Tolerance:
    """The full comparison's tolerance for `mapping` (default the scene's): not judged, unless
    the scene file sets one (then judged against the scene's own mapping only)."""
    mapping = mapping or scene.mujoco.solref
    own = scene.tolerance
    if (own.position is not None or own.angle is not None) and mapping == scene.mujoco.solref:
        return Tolerance(own.position, own.angle,
                         reason=f"set in the scene file: {own.reason or 'no reason given'}", checked=True)
    return Tolerance(None, None)


def judge(tol: Tolerance, metrics: dict) -> bool:
    """Within tolerance (always True for a comparison that is not judged)."""
    if not tol.checked:
        return True
    return ((tol.position is None or metrics["position_error_max"] <= tol.position)
            and (tol.angle is None or metrics["angle_error_max"] <= tol.angle))
