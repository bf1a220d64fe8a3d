"""How close the MuJoCo twin must stay, derived from what the two models share and what not.

Each term is a difference the physics predicts, with its cause written down beside it:

  impedance    MuJoCo's penalty row applies d (k r + c v) with impedance d = 0.9999, a
               relative force error of 1e-4; over a run it moves the body by about
               1e-4 of its travel (PHYSICS.md measured 1e-4 m on a bouncing box).
  switching    contact starts and ends on each simulator's own step grid: a switch can be late
               by one step in either, so positions differ by up to 2 v_impact dt.
  damping law  MuJoCo damps both ways, clamped at zero (our "linear" law). With the seed's
               "compression" law the body rebounds higher: e_c vs e_l (tests/test_restitution.py
               derives both). After the first landing the two bounce to different heights and
               land at different times, so they differ by up to the first rebound height H e_c^2.
  friction     with the penalty mapping MuJoCo's friction is viscous (c per contact) capped by
               mu Fn, ours mu Fn tanh(alpha v). Both brake at mu g while sliding fast; they part
               in the slow tail: a viscous tail from v* = mu g m / (n c) runs v* m / (n c), a
               Coulomb stop v*^2 / (2 mu g): half of it, mu g (m / (n c))^2 / 2, is the gap.
Other mappings (physical, seed) are shown beside penalty in the report but carry no tolerance:
their error is the subject of the comparison, not a defect.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from custom_sim import Scene, mass_properties
from custom_sim.bodies import contact_points_world

IMPEDANCE_ERROR = 1e-4   # 1 - d for d0 = dwidth = 0.9999 (flat solimp of the penalty mapping)
SWITCH_STEPS = 2.0       # steps a contact switch may lag, one per simulator
ANGLE_FLOOR = 1e-6       # rad: for bodies that never turn both angles are exactly 0


@dataclass(frozen=True)
class Tolerance:
    position: float              # m, on the maximum position difference
    angle: float                 # rad, on the maximum angle difference
    terms: dict                  # m, each physical cause
    reason: str
    checked: bool                # False: mapping without a tolerance (shown, not judged)


def impact(scene: Scene) -> tuple[float, float]:
    """(drop height H of the lowest point above the ground, speed at first impact) in m, m/s."""
    props = mass_properties(scene.body)
    i = scene.initial
    _, py = contact_points_world(props, [i.position[0]], [i.position[1]], [i.angle])
    height = max(0.0, float(py.min()))
    g = scene.g if scene.has("gravity") else 0.0
    vy = i.velocity[1]
    speed = math.sqrt(vy * vy + 2 * g * height) + abs(i.velocity[0])
    return height, speed


def compression_restitution(zeta: float) -> float:
    """e = exp(-zeta acos(zeta) / sqrt(1 - zeta^2)) of the compression law (0 when overdamped)."""
    if zeta >= 1.0:
        return 0.0
    return math.exp(-zeta * math.acos(zeta) / math.sqrt(1 - zeta * zeta))


def derive(scene: Scene, mapping: str | None = None) -> Tolerance:
    mapping = mapping or scene.mujoco.solref
    props = mass_properties(scene.body)
    height, v_impact = impact(scene)
    dt = max(scene.dt, scene.mujoco.dt or scene.dt)
    travel = height + abs(scene.initial.velocity[0]) * scene.duration + 1e-3
    terms = {"impedance": IMPEDANCE_ERROR * travel}
    if scene.has("contact"):
        terms["switching"] = SWITCH_STEPS * v_impact * dt
        ct = scene.contact
        if ct.damping_law == "compression" and ct.c > 0 and height > 0:
            zeta = ct.c / (2 * math.sqrt(ct.k * props.mass))
            terms["damping law"] = height * compression_restitution(zeta) ** 2
        if scene.has("friction") and ct.c > 0:
            g = scene.g if scene.has("gravity") else 0.0
            n = 2 if scene.body.shape in ("box", "compound") else 1  # points carrying the weight at rest
            terms["friction"] = ct.mu * g * (props.mass / (n * ct.c)) ** 2 / 2
    position = sum(terms.values())
    arm = float(np.max(np.hypot(props.points[:, 0], props.points[:, 1])))
    angle = position / arm if props.rotates and arm > 0 else ANGLE_FLOOR
    reason = "; ".join(f"{name} {value:.2g} m" for name, value in terms.items())
    checked = mapping == "penalty"
    if scene.tolerance.position is not None or scene.tolerance.angle is not None:
        position = scene.tolerance.position or position
        angle = scene.tolerance.angle or angle
        reason = f"set in the scene file: {scene.tolerance.reason or 'no reason given'} (derived: {reason})"
    return Tolerance(position=position, angle=angle, terms=terms, reason=reason, checked=checked)


def judge(tol: Tolerance, metrics: dict) -> bool:
    """Within tolerance (always True for a mapping that carries none)."""
    if not tol.checked:
        return True
    return metrics["position_error_max"] <= tol.position and metrics["angle_error_max"] <= tol.angle
