"""The reference's own mass properties (Green's theorem over the polygons) against hand values,
against custom_sim's parallel-axis formulas, and never taken from custom_sim."""
from __future__ import annotations

import numpy as np
import pytest

import custom_sim
from compare.oracle import rigid_body as rb
from compare.oracle.reference import Equations
from compare.scenarios import load, load_builtins

# Two ways of summing the same moments in double precision (a few operations on numbers of
# order 1e-2): a relative difference of a few ulps.
SAME_SUM = 1e-13
ALL_SCENES = load_builtins() + load_builtins("stress")


def test_triangle_moments_by_hand():
    """Right triangle (0,0), (b,0), (0,c): A = b c / 2, centroid (b/3, c/3), and
    int (x^2 + y^2) dA = b c (b^2 + c^2) / 12 about the right-angle corner."""
    b, c = 0.3, 0.2
    area, sx, sy, polar = rb.area_moments(np.array([[0, 0], [b, 0], [0, c]], float))
    assert area == pytest.approx(b * c / 2, rel=SAME_SUM)
    assert sx / area == pytest.approx(b / 3, rel=SAME_SUM)
    assert sy / area == pytest.approx(c / 3, rel=SAME_SUM)
    assert polar == pytest.approx(b * c * (b * b + c * c) / 12, rel=SAME_SUM)


def test_box_drop_by_hand():
    """2 kg, 0.2 x 0.1 m: I = 2 (0.04 + 0.01) / 12 = 8.3333e-3 kg m^2, corners at (+-0.1, +-0.05)."""
    body = rb.rigid_body(load("box_drop").body)
    assert body.mass == 2.0
    assert body.inertia == pytest.approx(2 * 0.05 / 12, rel=SAME_SUM)
    assert sorted(body.points) == sorted([(-0.1, -0.05), (0.1, -0.05), (0.1, 0.05), (-0.1, 0.05)])


def test_t_shape_by_hand():
    """t_shape_drop: bar 0.9 kg (0.30 x 0.06 at y = 0.12), stem 0.6 kg (0.06 x 0.24 at 0).
    COM y = 0.9 * 0.12 / 1.5 = 0.072 m. About the COM: bar 0.9 (0.09 + 0.0036)/12 + 0.9 0.048^2
    = 9.09e-3; stem 0.6 (0.0036 + 0.0576)/12 + 0.6 0.072^2 = 6.174e-3; I = 0.015264 kg m^2."""
    body = rb.rigid_body(load("t_shape_drop").body)
    assert body.mass == pytest.approx(1.5)
    assert body.com[1] == pytest.approx(0.072, rel=SAME_SUM)
    assert body.inertia == pytest.approx(0.015264, rel=SAME_SUM)
    assert (-0.03, -0.192) in [tuple(round(v, 12) for v in p) for p in body.points]  # foot of the stem


def test_disk_and_point():
    disk = rb.rigid_body(load("rolling_circle").body)
    assert disk.inertia == pytest.approx(0.5 * 2.0 * 0.1 ** 2) and disk.points == ((0.0, -0.1),)
    assert disk.rotates and not disk.turning
    point = rb.rigid_body(load("point_drop").body)
    assert point.points == ((0.0, -0.05),) and not point.rotates and point.inertia == 0.0


@pytest.mark.parametrize("scene", ALL_SCENES, ids=lambda s: s.name)
def test_agrees_with_custom_sim(scene):
    """Two different derivations of the same quantities: equal to round-off."""
    ours, theirs = rb.rigid_body(scene.body), custom_sim.mass_properties(scene.body)
    assert ours.mass == pytest.approx(theirs.mass, rel=SAME_SUM)
    assert ours.inertia == pytest.approx(theirs.inertia, rel=SAME_SUM, abs=0.0)
    assert np.allclose(ours.com, theirs.com, rtol=0, atol=SAME_SUM)
    assert np.allclose(np.array(ours.points), theirs.points, rtol=0, atol=SAME_SUM)
    assert (ours.turning, ours.rotates) == (theirs.points_rotate, theirs.rotates)


def test_reference_does_not_read_custom_sims_geometry(monkeypatch):
    """A wrong inertia or a missing corner in custom_sim's mass properties leaves the
    reference's equations unchanged."""
    import compare.oracle.reference as reference
    scene = load("box_drop")
    before = Equations.from_scene(scene)

    def broken(body):
        raise AssertionError("the reference asked custom_sim for its mass properties")
    monkeypatch.setattr(custom_sim, "mass_properties", broken)
    monkeypatch.setattr(custom_sim.bodies, "mass_properties", broken)
    assert not hasattr(reference, "mass_properties")
    assert Equations.from_scene(scene) == before
