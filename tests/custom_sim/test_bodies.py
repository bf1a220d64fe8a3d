"""Mass, centre of mass, inertia and contact points of every shape, against hand calculation."""
import math

import numpy as np
import pytest

from custom_sim import load_scene, mass_properties
from scene_types.schema import Body, Part

REL = 1e-12  # exact formulas: only floating-point round-off separates the two sides


def test_box_inertia_and_corners():
    p = mass_properties(Body(shape="box", mass=2.0, size=(0.3, 0.1)))
    assert p.inertia == pytest.approx(2.0 * (0.09 + 0.01) / 12, rel=REL)
    assert sorted(map(tuple, p.points)) == sorted([(-0.15, -0.05), (0.15, -0.05), (0.15, 0.05), (-0.15, 0.05)])
    assert p.rotates and p.points_rotate


def test_disk_has_one_point_below_the_centre():
    p = mass_properties(Body(shape="circle", mass=3.0, radius=0.2))
    assert p.inertia == pytest.approx(0.5 * 3.0 * 0.04, rel=REL)
    assert p.points.tolist() == [[0.0, -0.2]]
    assert p.rotates and not p.points_rotate


def test_point_mass_touches_at_contact_height_and_never_turns():
    p = mass_properties(Body(shape="point", mass=1.0, contact_height=0.05))
    assert p.points.tolist() == [[0.0, -0.05]]
    assert not p.rotates


def test_t_shape_by_hand():
    """The built-in T: bar 0.30 x 0.06 of 0.9 kg at y = 0.12, stem 0.06 x 0.24 of 0.6 kg at 0."""
    p = mass_properties(load_scene("scenarios/t_shape_drop.toml").body)
    # COM: y = (0.9 * 0.12 + 0.6 * 0) / 1.5 = 0.072 m
    assert p.mass == pytest.approx(1.5, rel=REL)
    assert p.com == pytest.approx((0.0, 0.072), rel=REL)
    # bar: 0.9 (0.09 + 0.0036) / 12 = 7.02e-3, plus 0.9 * 0.048^2 = 2.0736e-3
    # stem: 0.6 (0.0036 + 0.0576) / 12 = 3.06e-3, plus 0.6 * 0.072^2 = 3.1104e-3
    assert p.inertia == pytest.approx(7.02e-3 + 2.0736e-3 + 3.06e-3 + 3.1104e-3, rel=1e-9)
    # eight corners relative to the COM: the stem's foot at y = -0.12 - 0.072
    assert len(p.points) == 8
    assert p.points[:, 1].min() == pytest.approx(-0.192, rel=REL)


def test_compound_of_one_part_is_a_box():
    part = Part(size=(0.2, 0.1), offset=(0.3, -0.1), mass=1.5)
    c = mass_properties(Body(shape="compound", mass=1.5, parts=(part,)))
    b = mass_properties(Body(shape="box", mass=1.5, size=(0.2, 0.1)))
    assert c.inertia == pytest.approx(b.inertia, rel=REL)
    assert np.allclose(c.points, b.points, atol=1e-15)
    assert c.com == pytest.approx((0.3, -0.1), rel=REL)


def test_parallel_axis_against_numerical_integration():
    """Inertia of an L of two boxes by summing r^2 dm over a fine grid (independent of the formula)."""
    parts = (Part((0.4, 0.1), (0.0, 0.0), 2.0), Part((0.1, 0.3), (0.15, 0.2), 1.0))
    p = mass_properties(Body(shape="compound", mass=3.0, parts=parts))
    n = 400
    total, first, second = 0.0, np.zeros(2), 0.0
    samples = []
    for part in parts:
        w, h = part.size
        u = (np.arange(n) + 0.5) / n
        gx, gy = np.meshgrid(part.offset[0] + (u - 0.5) * w, part.offset[1] + (u - 0.5) * h)
        dm = part.mass / n**2
        samples.append((gx.ravel(), gy.ravel(), dm))
    for gx, gy, dm in samples:
        total += dm * gx.size
        first += dm * np.array([gx.sum(), gy.sum()])
    com = first / total
    for gx, gy, dm in samples:
        second += dm * np.sum((gx - com[0]) ** 2 + (gy - com[1]) ** 2)
    assert p.com == pytest.approx(tuple(com), rel=1e-9)
    # midpoint rule on a 400 x 400 grid: relative error ~ 1 / (12 n^2) = 5e-7
    assert p.inertia == pytest.approx(second, rel=1e-5)
    assert math.isclose(p.mass, 3.0)
