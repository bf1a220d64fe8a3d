"""Check `identical`: the simulator under test against custom_sim, same integrator and dt.

A simulator that implements the seed's algorithm with the same integrator at the same step
computes the same numbers in another order: it may differ from custom_sim by round-off only,
as the motion carries it (compare/verdict/roundoff.py measures that envelope per scene). Any
modelling difference, however small, is far above it: the smallest mistake the catalogue
holds moves a trajectory by more than 1e-6 m where round-off moves it by 1e-16 to 1e-7 m.

States written to a file with p significant digits also carry that rounding: half a unit
in the p-th digit of each value, added component by component to the envelope.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from custom_sim import INTEGRATORS, Scene, SimulationDiverged, simulate

from .roundoff import roundoff_envelope

ISOLATES = ("the whole implementation at once: same model, integrator and dt as custom_sim, "
            "so anything beyond round-off is a difference of model or code")


def _row(**kw) -> dict:
    row = {"name": "identical", "isolates": ISOLATES, "integrator": None,
           "position_error_max": 0.0, "angle_error_max": 0.0,
           "tolerance_position": None, "tolerance_angle": None, "pass": None, "reason": ""}
    row.update(kw)
    return row


def check_identical(scene: Scene, states: np.ndarray, integrator: str | None, dt: float,
                    written_digits: int | None | str = "auto") -> dict:
    """The check row (CHECKS.md) for states (steps + 1, 6) of the simulator under test, which
    names `integrator` and steps by dt (s). written_digits: significant digits the states
    were stored with (a CSV), None for full double precision, "auto": read off the numbers
    (the fewest digits that reproduce every sampled value; full precision stops at the first
    value that needs 16)."""
    states = np.asarray(states, dtype=float)
    if written_digits == "auto":
        from compare.usersim.loader import written_digits as digits_of
        written_digits = digits_of(states)
    if integrator not in INTEGRATORS:
        return _row(integrator=integrator,
                    reason=f"not judged: integrator {integrator!r} is not one custom_sim has "
                           f"({', '.join(INTEGRATORS)}); the reference, dynamics and contact checks still apply")
    if not np.isclose(dt, scene.dt, rtol=1e-12, atol=0.0):
        return _row(integrator=integrator,
                    reason=f"not judged: dt = {dt:g} s differs from the scene's {scene.dt:g} s")
    run_scene = scene if integrator == scene.integrator else dataclasses.replace(scene, integrator=integrator)
    try:
        ours = simulate(run_scene).states()
        envelope = roundoff_envelope(run_scene)
    except SimulationDiverged as exc:
        return _row(integrator=integrator, reason=f"not judged: custom_sim diverges here ({exc})")
    if states.shape != ours.shape:
        return _row(integrator=integrator,
                    reason=f"not judged: {states.shape[0]} states against custom_sim's {ours.shape[0]}")
    if envelope.horizon <= 1:
        return _row(integrator=integrator, reason="not judged: " + envelope.reason)
    rows = slice(0, envelope.horizon)   # up to the divergence horizon
    states, ours = states[rows], ours[rows]
    diff = states - ours
    dpos = np.hypot(diff[:, 0], diff[:, 1])
    dang = np.abs(diff[:, 2])
    tol_p = envelope.position_t[rows].copy()
    tol_a = envelope.angle_t[rows].copy()
    rounding = ""
    if written_digits is not None:
        half_unit = 0.5 * 10.0 ** (1 - written_digits)   # relative, of each value written
        tol_p = tol_p + half_unit * np.hypot(ours[:, 0], ours[:, 1]) * np.sqrt(2.0)
        tol_a = tol_a + half_unit * np.abs(ours[:, 2])
        rounding = f"; plus the file's rounding at {written_digits} significant digits"
    over = np.flatnonzero((dpos > tol_p) | (dang > tol_a))
    first = int(over[0]) if over.size else None
    comp = None
    if first is not None:
        names = ("x", "y", "theta", "vx", "vy", "omega")
        comp = names[int(np.argmax(np.abs(diff[first]) / np.maximum(np.abs(ours).max(axis=0), 1e-300)))]
    return _row(
        integrator=integrator,
        position_error_max=float(dpos.max()), angle_error_max=float(dang.max()),
        tolerance_position=float(tol_p.max()), tolerance_angle=float(tol_a.max()),
        **{"pass": first is None},
        reason=envelope.reason + rounding,
        first_step_over=first, time_first_over=None if first is None else first * scene.dt,
        component_first_over=comp,
        judged_until=(len(states) - 1) * scene.dt, judged_whole_run=envelope.horizon == len(envelope.position_t),
        roundoff_ensemble_position=envelope.ensemble_position,
        roundoff_initial_ulp_position=envelope.initial_position,
    )
