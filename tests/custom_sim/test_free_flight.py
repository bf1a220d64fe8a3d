"""Free flight is exactly ballistic: no contact force and no damping in the air.

Under constant gravity each integrator has a closed-form discrete solution (n steps of h):
    RK4                 y_n = y0 + v0 t - g t^2 / 2          (exact for a quadratic)
    semi-implicit Euler y_n = y0 + v0 t - g h^2 n (n + 1) / 2
    explicit Euler      y_n = y0 + v0 t - g h^2 n (n - 1) / 2
    implicit Euler      same as semi-implicit (a = -g does not depend on the state)
and vx, omega never change.
"""
import numpy as np
import pytest

from custom_sim import INTEGRATORS, simulate

ROUNDOFF = 1e-12  # m: a few ulps of the 1 m scale after 2000 additions


def closed_form(name, y0, v0, g, h, n):
    k = np.arange(n + 1)
    t = k * h
    if name == "rk4":
        return y0 + v0 * t - 0.5 * g * t * t
    if name == "explicit_euler":
        return y0 + v0 * t - 0.5 * g * h * h * k * (k - 1)
    return y0 + v0 * t - 0.5 * g * h * h * k * (k + 1)


@pytest.mark.parametrize("integrator", list(INTEGRATORS))
@pytest.mark.parametrize("shape", ["box", "circle", "point"])
def test_ballistic_with_contact_enabled(scene_factory, integrator, shape):
    body = {"box": {"shape": "box", "mass": 1.3, "size": [0.2, 0.1]},
            "circle": {"shape": "circle", "mass": 1.3, "radius": 0.1},
            "point": {"shape": "point", "mass": 1.3, "contact_height": 0.05}}[shape]
    spin = 0.0 if shape == "point" else 3.0
    scene = scene_factory(body, {"position": [0.1, 2.0], "velocity": [0.7, 1.5],
                                 "angular_velocity": spin},
                          duration=0.2, dt=1e-4, integrator=integrator,
                          effects=["gravity", "contact", "friction"],
                          contact={"k": 1e5, "c": 50.0, "mu": 0.9})
    tr = simulate(scene)
    assert tr.y.min() > 1.0, "the body must stay in the air for this test"
    expected = closed_form(integrator, 2.0, 1.5, 9.81, 1e-4, scene.steps)
    assert np.max(np.abs(tr.y - expected)) < ROUNDOFF
    assert np.all(tr.vx == 0.7), "no horizontal force in the air"
    assert np.all(tr.omega == spin), "no torque in the air"
    assert np.all(tr.energy_contact == 0.0)
