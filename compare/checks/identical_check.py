"""Check `identical`: the simulator under test against custom_sim, same integrator and dt.

A simulator that implements the seed's algorithm with the same integrator at the same step
computes the same numbers in another order: it may differ from custom_sim by round-off only,
as the motion carries it (compare/checks/roundoff.py measures that envelope per scene). Any
modelling difference, however small, is far above it: the smallest mistake the catalogue
holds moves a trajectory by more than 1e-6 m where round-off moves it by 1e-16 to 1e-7 m.

States written to a file also carry the file's rounding (compare/oracle/one_step.Rounding,
found from the file's text): half a unit of the last digit written, absolute for a fixed number
of decimals (%.6f: 5e-7, whatever the value) or relative for significant digits (%.8g: 5e-8
of each value), added to the envelope row by row (position: both coordinates' half units,
angle: theta's). Where that rounding, counted as the distance it can move the body's points
(the centre's half units plus the body's size times theta's), exceeds ROUNDING_JUDGE_FRACTION
of the motion's size, the file cannot tell a mistake from its rounding: a pass there is "not
judged" (a difference beyond the tolerance still fails).
"""
from __future__ import annotations

import numpy as np

from custom_sim import INTEGRATORS, Scene, SimulationDiverged
from scene_types.state import STATE_COMPONENTS

from .case import as_case
from ..oracle.one_step import Rounding
from .row import CheckRow

# A file whose rounding moves the body's points by more than this fraction of the motion's size
# (the larger of the body's extent and the distance its centre travels) leaves nothing to judge:
# a mistake moving the body by less would pass.
ROUNDING_JUDGE_FRACTION = 0.1

ISOLATES = ("the whole implementation at once: same model, integrator and dt as custom_sim, "
            "so anything beyond round-off is a difference of model or code")


def _row(integrator: str | None, reason: str, **values) -> CheckRow:
    return CheckRow("identical", ISOLATES, integrator, reason=reason, **values)


def check_identical(scene: Scene, states: np.ndarray, integrator: str | None, dt: float,
                    rounding: Rounding | int | None | str = "auto", case=None) -> CheckRow:
    """The check row for states (steps + 1, 6) of the simulator under test, which
    names `integrator` and steps by dt (s). rounding: how the states were written (a CSV's
    Rounding, from its text), None for full double precision, an int for that many
    significant digits, "auto": read off the numbers alone (csv_files.rounding_of_values).
    case: the scenario's Case (case.py), whose custom_sim run and envelope it takes."""
    states = np.asarray(states, dtype=float)
    if isinstance(rounding, str):   # "auto"
        from compare.usersim.csv_files import rounding_of_values
        rounding = rounding_of_values(states)
    elif isinstance(rounding, (int, np.integer)) and not isinstance(rounding, bool):
        rounding = Rounding("significant", int(rounding))
    written: Rounding | None = rounding if isinstance(rounding, Rounding) else None
    if integrator not in INTEGRATORS:
        return _row(integrator, f"not judged: integrator {integrator!r} is not one custom_sim has "
                                f"({', '.join(INTEGRATORS)}); the reference, dynamics and contact checks still apply")
    if not np.isclose(dt, scene.dt, rtol=1e-12, atol=0.0):
        return _row(integrator, f"not judged: dt = {dt:g} s differs from the scene's {scene.dt:g} s")
    case = as_case(scene, case)
    try:
        ours = case.trajectory(integrator).states()
        envelope = case.envelope(integrator)
    except SimulationDiverged as exc:
        return _row(integrator, f"not judged: custom_sim diverges here ({exc})")
    if states.shape != ours.shape:
        return _row(integrator, f"not judged: {states.shape[0]} states against custom_sim's {ours.shape[0]}")
    if envelope.horizon <= 1:
        return _row(integrator, "not judged: " + envelope.reason)
    rows = slice(0, envelope.horizon)   # up to the divergence horizon
    states, ours = states[rows], ours[rows]
    diff = states - ours
    dpos = np.hypot(diff[:, 0], diff[:, 1])
    dang = np.abs(diff[:, 2])
    tol_p = envelope.position_t[rows].copy()
    tol_a = envelope.angle_t[rows].copy()
    said = ""
    if written is not None:
        # the written value is within a half unit of the simulator's own: of each value written
        half = written.half_unit(states)
        rounded_p = np.hypot(half[:, 0], half[:, 1])
        tol_p = tol_p + rounded_p
        tol_a = tol_a + half[:, 2]
        said = f"; plus the file's rounding at {written.describe()}"
        from custom_sim import mass_properties
        props = mass_properties(scene.body)
        extent = float(np.max(np.hypot(props.points[:, 0], props.points[:, 1]))) if props.rotates else 0.0
        moved = float(np.max(rounded_p + extent * half[:, 2]))
        # beyond the tolerance is a failure whatever the rounding; a pass it swamps is no verdict
        within = not np.any((dpos > tol_p) | (dang > tol_a))
        if within and moved > ROUNDING_JUDGE_FRACTION * envelope.motion_size:
            return _row(integrator, position_error_max=float(dpos.max()), angle_error_max=float(dang.max()),
                        reason=f"not judged: the file's rounding at {written.describe()} moves the body's "
                               f"points by up to {moved:.2g} m, more than {ROUNDING_JUDGE_FRACTION:g} of the "
                               f"motion's size {envelope.motion_size:.3g} m, so a mistake could hide in it; "
                               "write more digits (%.17g keeps a double exactly)")
    over = np.flatnonzero((dpos > tol_p) | (dang > tol_a))
    first = int(over[0]) if over.size else None
    comp = None
    if first is not None:
        comp = STATE_COMPONENTS[int(np.argmax(np.abs(diff[first]) / np.maximum(np.abs(ours).max(axis=0), 1e-300)))]
    return _row(
        integrator, envelope.reason + said,
        position_error_max=float(dpos.max()), angle_error_max=float(dang.max()),
        tolerance_position=float(tol_p.max()), tolerance_angle=float(tol_a.max()), passed=first is None,
        details={"first_step_over": first, "time_first_over": None if first is None else first * scene.dt,
                 "component_first_over": comp, "judged_until": (len(states) - 1) * scene.dt,
                 "judged_whole_run": envelope.horizon == len(envelope.position_t),
                 "roundoff_ensemble_position": envelope.ensemble_position,
                 "roundoff_initial_ulp_position": envelope.initial_position},
    )
