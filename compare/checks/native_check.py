"""Check `native`: the full-effects comparison against MuJoCo's own contact, shown beside the
judged checks, with its attribution, and judged only by a bound the scene file sets.

With every effect on, custom_sim and MuJoCo's native contact differ by causes that are models,
not mistakes (the friction law, the shared cone, the mid-penetration contact point, the damping
law, the mapping). Upper bounds on them exceeded the motion itself (0.38 m on a box that moves
0.3 m), so they could not tell a right simulator from a wrong one. Instead:

    judged     check `contact` (contact_check.py): native contact, friction off, the linear law,
               against the mapping's measured error and the motion's sensitivity to it
    measured   the difference with every effect on, split cause by cause (attribution.py)

A [tolerance] table in the scene file is the user's own bound with its reason: the native
comparison is then judged by it.
"""
from __future__ import annotations

from custom_sim import Scene

from .row import CheckRow

ISOLATES = "MuJoCo's own contact with every effect on (the scene's solref mapping)"
NOT_JUDGED = ("not judged: with every effect on the two differ by named models (friction law, "
              "contact point, damping law, mapping), each measured in the attribution; the judged "
              "comparison is check `contact` (friction off)")


def native_row(scene: Scene, metrics: dict) -> CheckRow:
    """The check row of the full comparison (metrics of the scene's own mapping)."""
    own = scene.tolerance
    judged = own.position is not None or own.angle is not None
    passed = None
    if judged:
        passed = ((own.position is None or metrics["position_error_max"] <= own.position)
                  and (own.angle is None or metrics["angle_error_max"] <= own.angle))
    return CheckRow("native", ISOLATES, position_error_max=metrics["position_error_max"],
                    angle_error_max=metrics["angle_error_max"], tolerance_position=own.position,
                    tolerance_angle=own.angle, passed=passed,
                    reason=f"set in the scene file: {own.reason or 'no reason given'}" if judged else NOT_JUDGED,
                    details={"mapping": scene.mujoco.solref})
