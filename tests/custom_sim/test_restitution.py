"""Restitution and contact time of the penalty laws, gravity off, against derived formulas.

Let d be the depth, d(0) = 0, d'(0) = v0 > 0 (approaching), wn = sqrt(k/m), wd = wn sqrt(1 - z^2).

Textbook (Kelvin-Voigt, damping both ways, force may pull): d = (v0/wd) e^{-z wn t} sin(wd t),
    contact time pi / wd, restitution e = exp(-pi z / sqrt(1 - z^2)).

"linear" (our law: Fn = max(0, k d + c d'), never pulls). The force reaches zero before d does,
    when wn^2 d + 2 z wn d' = 0, i.e. tan(wd t) = -2 z sqrt(1-z^2) / (1 - 2 z^2) = -tan(2 asin z):
    wd t_s = pi - 2 asin z. At t_s the speed is |d'| = v0 e^{-z wn t_s} (the bracket works out
    to exactly wd), so e = exp(-z (pi - 2 asin z) / sqrt(1 - z^2)): shorter contact, *more* bounce
    than the textbook, because the pulling tail that would brake the body is cut off.

"compression" (seed Algorithm 1: Fn = k d + c max(0, d')). Damped until d' = 0, at
    wd t1 = acos z, depth d1 = (v0/wn) e^{-z wn t1}; then an undamped spring gives the speed back:
    wn d1. So e = exp(-z acos(z) / sqrt(1 - z^2)) and the contact lasts acos(z)/wd + pi/(2 wn).
"""
import math

import numpy as np
import pytest

from custom_sim import simulate

# Measured with RK4 at h wn = 1e-3: its error (h wn)^4 is negligible; the step grid resolves
# the contact switch to within one step, a relative error of h / t_contact ~ 1e-3 at most.
RESTITUTION_REL = 2e-3
CONTACT_TIME_REL = 2e-3


def linear_law(z):
    ts_wd = math.pi - 2 * math.asin(z)
    return math.exp(-z * ts_wd / math.sqrt(1 - z * z)), ts_wd / math.sqrt(1 - z * z)


def compression_law(z):
    e = math.exp(-z * math.acos(z) / math.sqrt(1 - z * z))
    return e, math.acos(z) / math.sqrt(1 - z * z) + math.pi / 2


def textbook(z):
    return math.exp(-math.pi * z / math.sqrt(1 - z * z)), math.pi / math.sqrt(1 - z * z)


def bounce(scene_factory, law, zeta, k=1e4, m=1.0, v0=1.0):
    wn = math.sqrt(k / m)
    c = 2 * zeta * math.sqrt(k * m)
    h = 1e-3 / wn
    scene = scene_factory({"shape": "point", "mass": m, "contact_height": 0.0},
                          {"position": [0.0, 0.0], "velocity": [0.0, -v0]},
                          duration=8.0 / wn, dt=h, integrator="rk4", effects=["contact"],
                          contact={"k": k, "c": c, "damping_law": law})
    tr = simulate(scene)
    ay = np.diff(tr.vy)
    pushing = np.nonzero(ay != 0.0)[0]
    contact_time = (pushing[-1] + 1) * h
    return tr.vy[-1] / v0, contact_time * wn


@pytest.mark.parametrize("zeta", [0.05, 0.2, 0.5])
@pytest.mark.parametrize("law,formula", [("linear", linear_law), ("compression", compression_law)])
def test_restitution_and_contact_time(scene_factory, law, formula, zeta):
    e, t_wn = bounce(scene_factory, law, zeta)
    e_expected, t_expected = formula(zeta)
    assert e == pytest.approx(e_expected, rel=RESTITUTION_REL), f"{law} zeta={zeta}: e={e:.5f}"
    assert t_wn == pytest.approx(t_expected, rel=CONTACT_TIME_REL), f"{law} zeta={zeta}: wn t={t_wn:.5f}"


def test_clamping_bounces_higher_than_the_textbook_and_compression_only_higher_still():
    for zeta in (0.1, 0.3):
        assert textbook(zeta)[0] < linear_law(zeta)[0] < compression_law(zeta)[0]


def test_undamped_contact_is_perfectly_elastic(scene_factory):
    e, t_wn = bounce(scene_factory, "linear", 0.0)
    assert e == pytest.approx(1.0, abs=RESTITUTION_REL)
    assert t_wn == pytest.approx(math.pi, rel=CONTACT_TIME_REL)
