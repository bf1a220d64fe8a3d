"""Observed order of convergence on smooth cases: 1, 1, 1, 4 (explicit, semi-implicit, implicit Euler, RK4).

Smooth means no contact switch and no kink of max(): a point mass and a flat box pressed into
the ground, oscillating about rest while they slide under a gentle tanh friction, with the
linear damping law whose force stays positive. Three step sizes h, h/2, h/4 give the order
without a reference: p = log2(|y_h - y_h/2| / |y_h/2 - y_h/4|) (Richardson).
"""
import dataclasses
import math

import numpy as np
import pytest

from custom_sim import INTEGRATORS, simulate

# The observed order approaches the theoretical one as h -> 0; at these steps the next term
# of the error expansion is a few per cent of the leading one, so p is within 0.15.
ORDER_TOL = 0.15
STEPS = {"explicit_euler": 2e-5, "semi_implicit_euler": 2e-4, "implicit_euler": 2e-4, "rk4": 2e-3}


def smooth_cases(scene_factory):
    common = dict(duration=0.2, effects=["gravity", "contact", "friction"],
                  contact={"k": 1e4, "c": 20.0, "damping_law": "linear", "mu": 0.3, "alpha": 10.0})
    point = scene_factory({"shape": "point", "mass": 1.0, "contact_height": 0.0},
                          {"position": [0.0, -1.5e-3], "velocity": [1.0, 0.0]}, **common)
    # flat box on both lower corners, slightly tilted: rocks and bobs without leaving the ground
    box = scene_factory({"shape": "box", "mass": 1.0, "size": [0.2, 0.1]},
                        {"position": [0.0, 0.05 - 8e-4], "velocity": [1.0, 0.0], "angle": 2e-3}, **common)
    return {"point": point, "box": box}


def end_state(scene, integrator, h):
    s = dataclasses.replace(scene, integrator=integrator, dt=h)
    tr = simulate(s)
    return np.array([tr.x[-1], tr.y[-1], tr.theta[-1], tr.vx[-1], tr.vy[-1], tr.omega[-1]])


@pytest.mark.parametrize("case", ["point", "box"])
@pytest.mark.parametrize("integrator", list(INTEGRATORS))
def test_observed_order(scene_factory, integrator, case):
    scene = smooth_cases(scene_factory)[case]
    h = STEPS[integrator]
    a, b, c = (end_state(scene, integrator, h / 2**i) for i in range(3))
    scale = np.array([1, 1, 1, 100, 100, 100.0])  # velocities weigh like positions x wn
    p = math.log2(np.linalg.norm((a - b) / scale) / np.linalg.norm((b - c) / scale))
    expected = INTEGRATORS[integrator].order
    assert p == pytest.approx(expected, abs=ORDER_TOL), f"{integrator} on {case}: observed order {p:.3f}"
