"""The equation implicit Euler solves each step, G(v1) = 0, in one place for both of its solvers.

    G(v1) = v1 - v0 - h a(q0 + h v1, v1)          (integrators.implicit_euler_step: Newton)
    G_lam(v1): the same with the load of one contact point scaled by lam
                                                  (filippov.jump_step: the touchdown's jump)

A step of implicit Euler is v1 = v0 + h a(q1, v1) with q1 = q0 + h v1; putting q1 in terms of
v1 leaves three equations in the velocities alone.
"""
from __future__ import annotations

from numba import njit

from .forces import accelerations, held_share


@njit(cache=True)
def residual(model, points, z0, zi, h, fx, fy, tau, held, share, g, counters):
    """G_lam(v1) into g (3,) for the velocities zi[3:], setting the positions zi[:3] = q0 + h v1;
    contact point `held` (-1: none) acts whatever its depth, its load scaled by share. Returns
    max |G_lam| (m/s, rad/s); counts one force evaluation.

    One compiled copy for Newton (held = -1) and the jump step, called directly by both: an
    inlined copy per caller was a third of implicit Euler's compile, and a wrapper inlined
    around it adds reference counting of its arrays at every call (a fifth of a step)."""
    for j in range(3):
        zi[j] = z0[j] + h * zi[3 + j]
    if held >= 0 and model.contact:
        fx, fy, tau = held_share(model, points, zi, held, share, fx, fy, tau)
    ax, ay, aw = accelerations(model, points, zi, fx, fy, tau)
    counters[0] += 1
    g[0] = zi[3] - z0[3] - h * ax
    g[1] = zi[4] - z0[4] - h * ay
    g[2] = zi[5] - z0[5] - h * aw
    return max(abs(g[0]), abs(g[1]), abs(g[2]))
