"""Friction against textbook results: a sliding box, a disk that starts to roll, rolling resistance."""
import numpy as np
import pytest

from custom_sim import load_scene, simulate
from custom_sim.bodies import disk_inertia

G = 9.81


def test_box_sliding_flat_decelerates_at_mu_g():
    scene = load_scene("scenarios/box_slide.toml")
    tr = simulate(scene)
    mu = scene.contact.mu
    # fit the velocity while it is well above the tanh width 1/alpha = 0.01 m/s
    sliding = (tr.vx > 0.2) & (tr.t > 0.02)
    slope = np.polyfit(tr.t[sliding], tr.vx[sliding], 1)[0]
    # tanh(alpha v) at v >= 0.2 m/s and alpha = 100 s/m differs from 1 by < 1e-17; what
    # remains is the small pitching of the box on its corner springs (< 1 %)
    assert -slope == pytest.approx(mu * G, rel=0.01), f"deceleration {-slope:.4f} vs mu g {mu * G:.4f}"
    # at rest where v0^2 / (2 mu g) puts it
    assert tr.x[-1] == pytest.approx(2.0**2 / (2 * mu * G), rel=0.01)
    assert abs(tr.vx[-1]) < 1e-3


def test_disk_launched_without_spin_ends_rolling_at_two_thirds(scene_factory):
    """Friction's impulse J: v = v0 - J/m, omega R = J R^2 / I; rolling when v = omega R,
    so v = v0 / (1 + I / (m R^2)) = 2 v0 / 3 for a disk, whatever mu."""
    R, m, v0 = 0.1, 1.0, 2.0
    for mu in (0.2, 0.6):
        scene = scene_factory({"shape": "circle", "mass": m, "radius": R},
                              {"position": [0.0, R - m * G / 1e5], "velocity": [v0, 0.0]},
                              duration=1.0, dt=2e-5, effects=["gravity", "contact", "friction"],
                              contact={"k": 1e5, "c": 200.0, "mu": mu, "alpha": 1000.0})
        tr = simulate(scene)
        expected = v0 / (1 + disk_inertia(m, R) / (m * R * R))
        # rolling: slip v - omega R (the contact point is ~1 mm lower than R: 1e-2 relative)
        assert tr.vx[-1] == pytest.approx(expected, rel=2e-3), f"mu={mu}"
        slip = tr.vx[-1] + tr.omega[-1] * R
        assert abs(slip) < 0.01 * v0


def test_rolling_resistance_decelerates_at_2_mu_roll_g_over_3R():
    """Rolling without slip under torque -mu_roll m g: (m + I/R^2) a = -mu_roll m g / R,
    a = -2 mu_roll g / (3 R) for a disk."""
    scene = load_scene("scenarios/rolling_circle.toml")
    tr = simulate(scene)
    R, mu_roll = scene.body.radius, scene.contact.mu_roll
    rolling = tr.t > 0.5  # the slide ends at v0 / (3 mu g) = 0.23 s
    slope = np.polyfit(tr.t[rolling], tr.vx[rolling], 1)[0]
    expected = 2 * mu_roll * G / (3 * R)
    # the disk rests ~1 mm into the ground: the lever of friction is R - d, 1 % shorter
    assert -slope == pytest.approx(expected, rel=0.02), f"deceleration {-slope:.5f} vs {expected:.5f}"
    slide_end = tr.t[np.argmax(np.abs(tr.vx + tr.omega * R) < 0.01)]
    assert slide_end == pytest.approx(2.0 / (3 * scene.contact.mu * G), rel=0.05)
