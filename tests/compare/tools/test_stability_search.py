"""Stability limits by bisection, checked against predictions derived independently of the search."""
from __future__ import annotations

import math

import numpy as np
import pytest

from compare.oracle.reference import solve_reference
from compare.scenarios import load
from compare.tools.accuracy.stability_search import (BISECTION_RATIO, ENERGY_GROWTH_LIMIT, custom_limit,
                                      energy_scale, energy_verdict, largest_stable_step, theory)
from compare.tools.accuracy.workprecision import grid_times

# The measured limit sits within this of the prediction: the bisection brackets to 1 %, and
# the growth a 10 % criterion allows moves the threshold by a few % at most (growth is
# geometric in the number of steps once past the limit).
PREDICTION = 0.05


def scale_of(scene) -> float:
    return energy_scale(solve_reference(scene, grid_times(scene)).states, scene)


@pytest.mark.parametrize("threshold", [3.7e-4, 1e-2, 0.0333])
def test_bisection_finds_a_sharp_threshold(threshold):
    lim = largest_stable_step(lambda h: (h <= threshold, "above"), 1e-4)
    assert lim.h_max <= threshold < lim.h_max * BISECTION_RATIO
    assert not lim.capped and not lim.below and lim.reason == "above"


def test_bisection_reports_bounds():
    capped = largest_stable_step(lambda h: (True, ""), 1e-4, max_step=0.05)
    assert capped.capped and capped.h_max == 0.05 and capped.text().startswith(">=")
    below = largest_stable_step(lambda h: (False, "never"), 1e-4, min_step=1e-6)
    assert below.below and below.h_max == 1e-6 and below.text().startswith("<")


def test_energy_verdict_reads_quiet_samples_only():
    """Energy swinging inside a contact (contact energy high) is not growth; energy that is
    higher in free flight than at the start is."""
    scale = 10.0
    contact = np.array([0.0, 5.0, 5.0, 0.0, 0.0])
    swing = np.array([10.0, 14.0, 6.0, 10.0, 10.0])        # +40 % only mid-contact
    assert energy_verdict(swing, contact, scale)[0]
    grown = np.array([10.0, 10.0, 10.0, 10.0, 10.0 + 1.5 * ENERGY_GROWTH_LIMIT * scale])
    ok, why = energy_verdict(grown, contact, scale)
    assert not ok and "energy rose" in why
    assert not energy_verdict(np.array([10.0, math.nan]), np.zeros(2), scale)[0]


def test_explicit_euler_on_an_undamped_bounce_matches_its_growth_rate():
    """Explicit Euler multiplies an undamped oscillator's energy by 1 + (h wn)^2 per step, so by
    about exp(pi h wn) over the pi / (wn h) steps of one contact. elastic_bounce touches the
    ground 3 times in its 3 s, so the energy has grown by 10 % when 3 pi h wn = ln 1.1: there is
    no stable step, and the search must find that one."""
    scene = load("elastic_bounce")
    ref = solve_reference(scene, grid_times(scene))
    contacts = ref.switches["touch"] // 2 + ref.switches["touch"] % 2
    wn = math.sqrt(scene.contact.k / scene.body.mass)
    predicted = math.log(1 + ENERGY_GROWTH_LIMIT) / (contacts * math.pi * wn)
    lim = custom_limit(scene, "explicit_euler", energy_scale(ref.states, scene))
    assert theory(scene, "explicit_euler")["spring"] == 0.0  # no damping: never stable in theory
    assert abs(lim.h_max / predicted - 1) < PREDICTION, (lim.h_max, predicted, contacts)


def resting_slider(scene_factory, c):
    """A point mass resting in a Kelvin-Voigt contact (wn = 100 rad/s), 0.02 mm above its
    equilibrium depth (0.98 mm), sliding without friction at 1 m/s: a linear oscillator in y as
    long as it stays in contact, with 0.5 J of motion whose energy an instability must disturb.
    The small offset keeps it in contact even near h wn = 2, where symplectic Euler's discrete
    orbit is stretched by sqrt((2 + h wn) / (2 - h wn)) (14x at h wn = 1.98)."""
    k, m, g = 1e4, 1.0, 9.81
    return scene_factory({"shape": "point", "mass": m, "contact_height": 0.0},
                         {"position": [0.0, -m * g / k + 2e-5], "velocity": [1.0, 0.0]},
                         effects=["gravity", "contact"], duration=3.0,
                         contact={"k": k, "c": c, "damping_law": "linear"})


@pytest.mark.parametrize("c", [20.0, 0.0])
def test_limit_of_a_resting_contact_is_the_linear_theory(scene_factory, c):
    """Semi-implicit Euler: past h wn = 2 (sqrt(1 + zeta^2) - zeta) (Jury test) an eigenvalue
    leaves the unit circle at -1, the vibration grows by a fixed factor per step, it is thrown
    off the ground and the energy criterion fires just past the theory. (RK4 is left out: past
    h wn = 2 sqrt 2 its growth saturates once the point starts leaving the one-sided spring,
    and the energy rises by only 1 % until h wn = 3.1; the sweep's table shows that.)"""
    integrator = "semi_implicit_euler"
    scene = resting_slider(scene_factory, c)
    wn, zeta = 100.0, c / (2 * math.sqrt(1e4))
    predicted = 2 * (math.sqrt(1 + zeta ** 2) - zeta) / wn
    lim = custom_limit(scene, integrator, scale_of(scene))
    assert abs(lim.h_max / predicted - 1) < PREDICTION, (lim, predicted)
    assert abs(theory(scene, integrator)["spring"] / predicted - 1) < 0.02  # custom_sim's theory agrees


def test_implicit_euler_has_no_limit_on_a_point_mass():
    scene = load("point_drop")
    lim = custom_limit(scene, "implicit_euler", scale_of(scene))
    assert lim.capped, lim
