"""compare/oracle/one_step.py: what the oracle's implicit Euler calls a root under a bare sign law.

A root of G(v1) = v1 - v0 - h a(q0 + h v1, v1) is G = 0 to the round-off of G. Where a slip ends
within rounding of zero the sign may take either side, and the force jumps by 2 mu Fn there; that
jump is what two codes may differ by, not a rounding of a root: a step left on it has no root.
"""
from __future__ import annotations

import numpy as np
import pytest

from compare.oracle.force_law import EPS, accelerations
from compare.oracle.one_step import OWN_SOLVE_TOL, implicit_residual, one_step, undecided
from compare.oracle.reference import Equations

import sign_box

# A root: |G| at most the oracle's solve tolerance OWN_SOLVE_TOL, 1e-13 m/s, which is above
# G's own round-off 4 eps (|v| + h |force terms| / m), about 1e-16 m/s for this box's vertical.
VERTICAL_ROOT = OWN_SOLVE_TOL


def test_a_step_left_on_the_sign_jump_is_no_root():
    """The oracle's Newton ends with corner 0's slip within rounding of zero, on the jump: the
    vertical equation, which has no friction in it, is left at 1.3e-7 m/s, a million times its
    round-off. That is no root, so the step is undecided (not judged), not a root whose
    friction the jump's size excuses."""
    scene = sign_box.scene()
    eq = Equations.from_scene(scene)
    z0 = np.array([sign_box.STATE])
    z1, _, solved = one_step(eq, z0, scene.dt, "implicit_euler")
    g, _ = implicit_residual(eq, z0, z1[:, 3:], scene.dt)
    assert abs(g[0, 1]) > VERTICAL_ROOT
    assert not solved[0]
    assert undecided(eq, solved)[0]


def test_a_solved_row_solves_its_friction_free_equation():
    """Over states of a box on its two bottom corners with slips from 1e-12 to 1e-3 m/s (the
    sign's jump among them), every row the oracle calls solved has G_y, the vertical equation
    that friction never enters, at round-off: a root is a root whichever side a sign takes."""
    scene = sign_box.scene()
    eq = Equations.from_scene(scene)
    rng = np.random.default_rng(7)
    n = 400
    z = np.tile(sign_box.STATE, (n, 1))
    z[:, 2] = rng.uniform(-1e-6, 1e-6, n)
    z[:, 5] = rng.uniform(-1e-2, 1e-2, n)
    slip = np.sign(rng.uniform(-1, 1, n)) * 10.0 ** rng.uniform(-12, -3, n)
    z[:, 3] = slip + z[:, 5] * (-0.05)         # vx = slip + omega r_y at the bottom corners
    z1, _, solved = one_step(eq, z, scene.dt, "implicit_euler")
    g, _ = implicit_residual(eq, z, z1[:, 3:], scene.dt)
    assert solved.any() and not solved.all()
    assert np.all(np.abs(g[solved, 1]) <= VERTICAL_ROOT)


def test_the_bound_still_allows_the_jump_where_a_sign_is_undecided():
    """The two-code bound keeps the jump: at a slip within rounding of zero, either side is a
    correct evaluation, so a step's bound on vx spans 2 h mu Fn / m."""
    scene = sign_box.scene()
    eq = Equations.from_scene(scene)
    # flat, turning at 0.01 rad/s about the bottom face: slip vx - omega r_y = 0 from inputs that round
    z = np.array([[0.0, 0.0489, 0.0, -5e-4, 0.0, 0.01]])
    _, scale = accelerations(eq, z)
    _, smooth = accelerations(eq, z, jumps=False)
    fn = 2.0 * eq.k * (0.05 - 0.0489)                    # both bottom corners' load, N (their dampers cancel)
    jump = 2.0 * eq.mu * fn / eq.mass                    # m/s^2
    assert EPS * (scale[0, 0] - smooth[0, 0]) == pytest.approx(jump, rel=1e-9)
    assert EPS * smooth[0, 0] < 1e-9 * jump
