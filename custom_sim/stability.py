"""The largest stable step by linear theory, for the divergence message and the reports.

Near a contact the body is an oscillator x'' = -wn^2 x - 2 zeta wn x' with wn = sqrt(k / m_eff)
(m_eff the smallest effective mass at a contact point) and zeta = c / (2 sqrt(k m_eff)).
Each method's amplification matrix has spectral radius < 1 when (derived for each):

    explicit Euler       |1 + h lambda| < 1 gives h < 2 zeta / wn for damping both ways; but per
                         step the oscillator's energy grows by 1 + (wn h)^2 while undamped and
                         by 1 - 2 zeta wn h + (wn h)^2 while damped, and the compression law damps
                         half the cycle (the linear law stops at its clamp): h < zeta / wn
    semi-implicit Euler  det = 1 - 2 zeta wn h, trace = 2 - (wn h)^2 - 2 zeta wn h, Jury test:
                         h wn < 2 (sqrt(1 + zeta^2) - zeta)                 (2 without damping)
    implicit Euler       every h
    RK4                  h |lambda| < about 2.8 on the imaginary axis       h wn < 2.8

The tanh friction adds a real rate lambda_f = mu Fn alpha / m_t (m_t the tangential effective
mass) with Fn ~ m g at rest: explicit and semi-implicit Euler need h lambda_f < 2, RK4 < 2.78.
"""
from __future__ import annotations

import math

import numpy as np

from .bodies import mass_properties, min_effective_mass
from .scene import Scene

RK4_IMAGINARY_LIMIT = 2.8   # h |lambda| on the imaginary axis (2 sqrt 2 = 2.83)
RK4_REAL_LIMIT = 2.78       # h |lambda| on the negative real axis


def contact_frequency(scene: Scene) -> tuple[float, float]:
    """(wn rad/s, zeta) of the stiffest contact mode, or (0, 0) without contact."""
    if not scene.has("contact"):
        return 0.0, 0.0
    m_eff = min_effective_mass(mass_properties(scene.body))
    k, c = scene.contact.k, scene.contact.c
    return math.sqrt(k / m_eff), c / (2.0 * math.sqrt(k * m_eff))


def friction_rate(scene: Scene) -> float:
    """lambda_f = mu m g alpha / m_t (1/s): the stiff rate of the tanh law at rest."""
    if not scene.has("friction"):
        return 0.0
    props = mass_properties(scene.body)
    if props.rotates:
        r2 = float(np.max(np.sum(props.points ** 2, axis=1)))
        m_t = 1.0 / (1.0 / props.mass + r2 / props.inertia)
    else:
        m_t = props.mass
    g = scene.g if scene.has("gravity") else 0.0
    return scene.contact.mu * props.mass * g * scene.contact.alpha / m_t


def stable_step(scene: Scene, integrator: str | None = None) -> float:
    """Largest stable step (s) by the theory above; inf when nothing limits it."""
    method = integrator or scene.integrator
    wn, zeta = contact_frequency(scene)
    lam_f = friction_rate(scene)
    if method == "implicit_euler":
        return math.inf
    if method == "explicit_euler":
        h_n = zeta / wn if wn > 0 else math.inf
        h_f = 2.0 / lam_f if lam_f > 0 else math.inf
    elif method == "semi_implicit_euler":
        h_n = 2.0 * (math.sqrt(1.0 + zeta * zeta) - zeta) / wn if wn > 0 else math.inf
        h_f = 2.0 / lam_f if lam_f > 0 else math.inf
    else:
        h_n = RK4_IMAGINARY_LIMIT / wn if wn > 0 else math.inf
        h_f = RK4_REAL_LIMIT / lam_f if lam_f > 0 else math.inf
    return min(h_n, h_f)
