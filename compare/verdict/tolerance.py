"""How close the MuJoCo twin must stay, derived from what the two models share and what not.

Each term is a difference the physics predicts, with its cause written down beside it:

  impedance    MuJoCo's penalty row (flat impedance d = 1e-4, solref scaled by A_hat) applies
               our k r + c v up to a relative d |A / A_hat - 1| (A the contact's true inverse
               inertia): a few 1e-4, taken as 1e-4 on every impulse. Velocities then differ by
               up to 1e-4 of the largest speed the energy allows, v_max = sqrt(v0^2 + 2 g H),
               and positions by 1e-4 v_max T over the run (measured: 1e-4 m on a box, docs/physics.md).
  switching    contact starts and ends on each simulator's own step grid: a switch can be late
               by one step in either, so positions differ by up to 2 v_impact dt.
  damping law  MuJoCo damps both ways, clamped at zero (our "linear" law). With the seed's
               "compression" law the body rebounds higher: e_c vs e_l (tests/test_restitution.py
               derives both). After the first landing the two bounce to different heights and
               land at different times, so they differ by up to the first rebound height H e_c^2.
  friction     with the penalty mapping MuJoCo's friction row is viscous, c_t = mu alpha N_ref
               (N_ref = m g / n, the resting load of each of n points: tanh's slope at rest),
               capped by mu Fn; ours is mu Fn tanh(alpha v). Both brake at mu g while sliding
               fast and enter their linear range at v* = 1/alpha; there a viscous tail runs
               v* / (mu g alpha) = 1 / (mu g alpha^2), a Coulomb stop half that: the gap is
               1 / (2 mu g alpha^2).
  impact       for a body whose corners turn (box, compound) the slip of a landing corner passes
  friction     through zero during the impact, where the two friction laws part: ours within
               1/alpha of zero slip, MuJoCo's (viscous, c_t = mu alpha N_ref with N_ref the resting
               load per point) within mu Fn / c_t = Fn / (alpha N_ref). At the peak force k d_max,
               d_max = v_impact sqrt(m_eff / k), the body leaves the impact with tangential speeds
               up to v_w = k d_max / (alpha N_ref) apart, a gap that can last the rest of the run:
               v_w (T - t_impact). An upper bound; so every friction scene is also compared with
               friction off, where this term and the friction term vanish (see comparison.py).
  rolling      MuJoCo's rolling rows share the elliptic cone with the sliding rows: while a disk
               slides, sliding takes the whole cone and MuJoCo's rolling torque is ~0, ours is
               mu_roll Fn. Over the slide (t_s = v0 / (3 mu g)) ours loses angular momentum about
               the contact point mu_roll m g t_s; rolling, L = (3/2) m R v, so it rolls slower by
               dv = 2 mu_roll g t_s / (3 R) and falls behind by dv (T - t_s).
The angle tolerance takes impedance and switching on the largest spin the energy allows,
omega_max = sqrt(m v_max^2 / I + omega0^2), and the model terms through the arm: dx / r_max.
Other mappings (physical, seed) are shown beside penalty in the report but carry no tolerance:
their error is the subject of the comparison, not a defect.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from custom_sim import Scene, mass_properties
from custom_sim.bodies import contact_points_world, min_effective_mass

IMPEDANCE_ERROR = 1e-4   # relative force error d |A / A_hat - 1| of the penalty mapping (d = 1e-4)
SWITCH_STEPS = 2.0       # steps a contact switch may lag, one per simulator
ANGLE_FLOOR = 1e-6       # rad: for bodies that never turn both angles are exactly 0


@dataclass(frozen=True)
class Tolerance:
    position: float              # m, on the maximum position difference
    angle: float                 # rad, on the maximum angle difference
    terms: dict                  # m, each physical cause
    reason: str
    checked: bool                # False: mapping without a tolerance (shown, not judged)


def impact(scene: Scene) -> tuple[float, float, float]:
    """(drop height H of the lowest point above the ground in m, normal speed at the first
    impact, largest speed the energy allows v_max = sqrt(v0^2 + 2 g H), both in m/s)."""
    props = mass_properties(scene.body)
    i = scene.initial
    _, py = contact_points_world(props, [i.position[0]], [i.position[1]], [i.angle])
    height = max(0.0, float(py.min()))
    g = scene.g if scene.has("gravity") else 0.0
    vx, vy = i.velocity
    normal = math.sqrt(min(vy, 0.0) ** 2 + 2 * g * height)
    return height, normal, math.sqrt(vx * vx + vy * vy + 2 * g * height)


def compression_restitution(zeta: float) -> float:
    """e = exp(-zeta acos(zeta) / sqrt(1 - zeta^2)) of the compression law (0 when overdamped)."""
    if zeta >= 1.0:
        return 0.0
    return math.exp(-zeta * math.acos(zeta) / math.sqrt(1 - zeta * zeta))


def derive(scene: Scene, mapping: str | None = None) -> Tolerance:
    mapping = mapping or scene.mujoco.solref
    props = mass_properties(scene.body)
    height, v_impact, v_max = impact(scene)
    dt = max(scene.dt, scene.mujoco.dt or scene.dt)
    terms = {"impedance": IMPEDANCE_ERROR * (v_max * scene.duration + height)}
    if scene.has("contact"):
        terms["switching"] = SWITCH_STEPS * v_max * dt
        ct = scene.contact
        if ct.damping_law == "compression" and ct.c > 0 and height > 0:
            zeta = ct.c / (2 * math.sqrt(ct.k * props.mass))
            terms["damping law"] = height * compression_restitution(zeta) ** 2
        g = scene.g if scene.has("gravity") else 0.0
        n = 2 if scene.body.shape in ("box", "compound") else 1  # points carrying the weight at rest
        if scene.has("friction") and ct.mu > 0 and g > 0:
            terms["friction"] = 1.0 / (2 * ct.mu * g * ct.alpha**2)
            if props.points_rotate and v_impact > 0 and g > 0:
                d_max = v_impact * math.sqrt(min_effective_mass(props) / ct.k)
                v_w = ct.k * d_max * n / (ct.alpha * props.mass * g)
                t_impact = math.sqrt(2 * height / g) if height > 0 else 0.0
                terms["impact friction"] = v_w * max(0.0, scene.duration - t_impact)
        if scene.has("rolling_friction") and scene.has("gravity") and ct.mu > 0:
            slip = abs(scene.initial.velocity[0] + scene.initial.angular_velocity * scene.body.radius)
            t_slide = min(slip / (3 * ct.mu * scene.g), scene.duration)
            dv = 2 * ct.mu_roll * scene.g * t_slide / (3 * scene.body.radius)
            terms["rolling"] = dv * (scene.duration - t_slide)
    position = sum(terms.values())
    angle = ANGLE_FLOOR
    if props.rotates:
        arm = float(np.max(np.hypot(props.points[:, 0], props.points[:, 1])))
        spin = math.sqrt(props.mass * v_max**2 / props.inertia + scene.initial.angular_velocity**2)
        numerical = IMPEDANCE_ERROR * spin * scene.duration + (SWITCH_STEPS * spin * dt if scene.has("contact") else 0.0)
        model = sum(v for k, v in terms.items() if k not in ("impedance", "switching"))
        angle = numerical + model / arm
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
