"""Effects on demand: a term the scene does not list is never evaluated.

The model sets the parameters of an unlisted effect to NaN (custom_sim/model.py). Evaluating
such a term would put NaN into the state, which stops the run; so a finite trajectory proves
the term was never evaluated. The positive controls show the poison does reach the state
when a term is evaluated.
"""
import dataclasses

import numpy as np
import pytest

from custom_sim import load_scene, simulate
from custom_sim.integrators import INTEGRATORS, integrate
from custom_sim.model import build_model, initial_state
from custom_sim.bodies import mass_properties
from custom_sim.runner import blowup_guard

ROLLING = load_scene("scenarios/rolling_circle.toml")


def run_model(model, points, scene, method="semi_implicit_euler"):
    z = initial_state(scene)
    out = np.empty((scene.steps, 6))
    guard = blowup_guard(scene, mass_properties(scene.body), z, applied_input=False)
    failed = integrate(model, points, z, scene.dt, scene.steps, INTEGRATORS[method].code,
                       np.zeros((1, 3)), out, np.zeros(4, np.int64), guard, np.empty((0, 8)))
    return failed, out


@pytest.mark.parametrize("integrator", list(INTEGRATORS))
@pytest.mark.parametrize("effects", [("gravity",), ("gravity", "contact"), ("gravity", "contact", "friction"),
                                     ("contact", "friction", "rolling_friction"), ()])
def test_unlisted_terms_are_never_evaluated(effects, integrator):
    scene = dataclasses.replace(ROLLING, effects=effects, integrator=integrator, duration=0.3)
    model, _ = build_model(scene)
    for name, on in (("g", "gravity"), ("mu", "friction"), ("alpha", "friction"), ("mu_roll", "rolling_friction")):
        assert np.isnan(getattr(model, name)) == (on not in effects), name
    tr = simulate(scene)  # raises SimulationDiverged on a NaN
    assert np.all(np.isfinite(tr.states()))


def test_the_poison_reaches_the_state_when_a_term_is_evaluated():
    """Positive control: switch friction on while its parameters are NaN -> the run stops."""
    scene = dataclasses.replace(ROLLING, effects=("gravity", "contact"), duration=0.05)
    model, points = build_model(scene)
    failed, _ = run_model(model._replace(friction=True), points, scene)
    assert failed == 1, "the first step in contact must produce NaN"
    spinning = dataclasses.replace(scene, initial=dataclasses.replace(scene.initial, angular_velocity=1.0))
    failed, _ = run_model(model._replace(rolling=True), points, spinning)
    assert failed == 1


def test_effects_change_the_motion_as_expected():
    base = dataclasses.replace(ROLLING, duration=0.5)
    # without gravity the disk, which starts 1 mm into the ground, is pushed off and flies
    # away at constant speed: nothing pulls it back
    no_gravity = simulate(dataclasses.replace(base, effects=("contact", "friction")))
    assert no_gravity.vy[-1] > 0 and np.all(np.diff(no_gravity.vy[-100:]) == 0.0)
    no_friction = simulate(dataclasses.replace(base, effects=("gravity", "contact")))
    assert np.all(no_friction.omega == 0.0) and no_friction.vx[-1] == pytest.approx(2.0, abs=1e-12)
    no_roll = simulate(dataclasses.replace(base, effects=("gravity", "contact", "friction")))
    rolled = simulate(base)
    assert rolled.vx[-1] < no_roll.vx[-1]


def test_applied_force_accelerates_as_newton_says():
    """Constant Fx on a free body: x = F t^2 / (2 m) exactly for RK4 (a quadratic)."""
    scene = dataclasses.replace(ROLLING, effects=(), integrator="rk4", duration=0.5)
    tr = simulate(scene, external=(3.0, 0.0, 0.2))
    m, inertia = scene.body.mass, 0.5 * scene.body.mass * scene.body.radius ** 2
    assert tr.x[-1] == pytest.approx(2.0 * 0.5 + 3.0 * 0.25 / (2 * m), rel=1e-12)
    assert tr.omega[-1] == pytest.approx(0.2 * 0.5 / inertia, rel=1e-12)
    per_step = np.tile([3.0, 0.0, 0.2], (scene.steps, 1))
    assert np.array_equal(simulate(scene, external=per_step).x, tr.x)
