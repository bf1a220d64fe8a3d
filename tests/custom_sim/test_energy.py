"""elastic_bounce (no damping, no friction): the energy behaviour each integrator must show.

Symplectic (semi-implicit) Euler keeps a modified energy: its error stays bounded, of order
h wn times the energy stored in the spring, and does not grow with the number of bounces.
Explicit Euler multiplies the oscillator's amplitude by |1 + i h wn| = sqrt(1 + (h wn)^2) per
step in contact: energy grows at every bounce. Implicit Euler divides by it: energy decays.
"""
import dataclasses

import numpy as np

from custom_sim import load_scene, simulate

SCENE = load_scene("scenarios/elastic_bounce.toml")
# semi-implicit Euler: the energy error within a contact is O(h wn) E = 1e-2 E at h wn = 1e-2;
# outside contact it is exact to O(h^2 g^2 m) (the drop's discretisation), and bounded.
SEMI_IMPLICIT_BOUND = 0.02


def run(integrator):
    tr = simulate(dataclasses.replace(SCENE, integrator=integrator))
    return tr.energy / tr.energy[0]


def test_semi_implicit_energy_stays_bounded():
    e = run("semi_implicit_euler")
    assert np.max(np.abs(e - 1.0)) < SEMI_IMPLICIT_BOUND, f"max |E/E0 - 1| = {np.max(np.abs(e - 1)):.4f}"
    # and does not drift: the last second's mean within the same bound of the first
    n = len(e) // 3
    assert abs(e[-n:].mean() - e[:n].mean()) < SEMI_IMPLICIT_BOUND / 4


def test_explicit_euler_energy_grows_every_bounce():
    e = run("explicit_euler")
    assert e[-1] > 1.05, f"E/E0 at the end {e[-1]:.4f}"
    # monotone growth across bounces: energy in flight is higher after each contact
    flight = np.asarray(simulate(dataclasses.replace(SCENE, integrator="explicit_euler")).energy_contact == 0.0)
    levels = e[flight]
    assert np.all(np.diff(levels[::1000]) >= -1e-9)


def test_implicit_euler_energy_decays():
    e = run("implicit_euler")
    assert e[-1] < 0.95, f"E/E0 at the end {e[-1]:.4f}"
    assert np.max(e) <= 1.0 + 1e-9


def test_rk4_energy_error_is_far_smaller_than_semi_implicit():
    e4 = run("rk4")
    e1 = run("semi_implicit_euler")
    assert np.max(np.abs(e4 - 1)) < 0.1 * np.max(np.abs(e1 - 1))
