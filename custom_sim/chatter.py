"""Chatter: the instability that stays bounded. The one definition the whole harness uses.

A run is *stable* when it neither blows up (integrators.is_healthy) nor chatters. It
*chatters* at step i when one contact point, touching the ground at every step or every other
step of the last CHATTER_STEPS, has its slip velocity vc_x = vx - omega r_y or its normal
velocity vc_y = vy + omega r_x (m/s)

  1. change sign at every one of those steps, each value above FLIP_FLOOR in size, and
  2. not decay over them, |v_i| >= NO_DECAY |v_(i - CHATTER_STEPS)|, or (the slip only) stay
     where the friction law is saturated, alpha |v| >= 1 at both ends.

    chattering_point(model, points, z, watch)   the compiled tracker, after every step
    idle(watch), clear_height(points)           when a step leaves the tracker as it is
    unstable_law(scene, integrator)             why no step is stable under a bare sign law
    unsolved_stick(scene, integrator)           why implicit Euler may chatter there all the same

Why a flip at every step is numerical, never physical, and what sets the constants:
docs/stability.md#definition.
"""
from __future__ import annotations

import math

from numba import njit

from .forces import rotation
from .model import SIGN

# consecutive flips that make chatter (even: the window compares like signs); short enough to
# catch the friction chatter of the briefest impact at its scene's step (stiff_contact's
# contact lasts pi / wn = 0.1 ms, 10 steps of 1e-5 s)
CHATTER_STEPS = 8
FLIP_FLOOR = 1e-9      # m/s: 1e8 above a resting body's round-off, 1e3 below the smallest
                       # chatter of any scene (h mu g = 2.5e-6 m/s for sharp_friction's 5e-7 s)
NO_DECAY = 1.0 - 1e-3  # over CHATTER_STEPS: a stable mode |lambda| < 1 - 1.3e-4 decays by more,
                       # a limit cycle (constant amplitude) by round-off only

# columns of the tracker `watch` (one row per contact point)
PREV_SLIP, PREV_NORMAL, RUN_SLIP, RUN_NORMAL, START_SLIP, START_NORMAL, FLAG, TOUCHED = range(8)
WATCH_COLUMNS = 8
CLEARED = -1.0   # watch[p, TOUCHED]: in the air since the row was cleared (0.0: in the air, 1.0: touching)
SLIP, NORMAL = 1.0, 2.0    # watch[p, FLAG]: which velocity of point p chattered
QUANTITY = {SLIP: "slip velocity", NORMAL: "normal velocity"}


@njit(cache=True)
def chattering_point(model, points, z, watch):
    """Update the tracker watch (n, WATCH_COLUMNS) with state z after a step; returns the
    index of a contact point that chatters (its FLAG set to SLIP or NORMAL), or -1."""
    cs, sn = rotation(model, z[2])
    return chattering_point_at(model, points, z, cs, sn, watch)


@njit(cache=True, error_model="numpy", inline="always")
def chattering_point_at(model, points, z, cs, sn, watch):
    """chattering_point() with the contact points' turn (cs, sn) at z given (the explicit loop
    computes it once per state, for this and for the next step's forces). z: an array or a tuple.

    Per point and quantity q (0: slip, 1: normal): the previous value (column q), the run of
    flips (2 + q) and the size at the start of the current window (4 + q). One loop, no helper
    function per quantity (the cost: docs/stability.md#what-watching-costs)."""
    vx, vy, om = z[3], z[4], z[5]
    saturated = math.inf                 # the slip speed above which friction is saturated
    if model.friction:
        saturated = 0.0 if model.friction_law == SIGN else 1.0 / model.alpha
    flagged = -1
    for p in range(points.shape[0]):
        if flagged >= 0:
            continue  # the run stops at this step: the other points are left as they were
        lx, ly = points[p, 0], points[p, 1]
        rx, ry = cs * lx - sn * ly, sn * lx + cs * ly
        touching = z[1] + ry < 0.0
        if not touching and watch[p, TOUCHED] <= 0.0:
            # two steps in the air: no contact force, nothing flips; the row is cleared once
            if watch[p, TOUCHED] == 0.0:
                for c in (PREV_SLIP, PREV_NORMAL, RUN_SLIP, RUN_NORMAL):
                    watch[p, c] = 0.0
                watch[p, TOUCHED] = CLEARED
            continue
        watch[p, TOUCHED] = 1.0 if touching else 0.0
        for q in range(2):
            if flagged >= 0:
                continue
            v = vx - om * ry if q == 0 else vy + om * rx
            prev = watch[p, PREV_SLIP + q]
            watch[p, PREV_SLIP + q] = v
            # the floor first: at rest it is always below, in motion always above, so the
            # branch is predictable; signs compared, not multiplied: a resting body's
            # velocities decay to 1e-200 and below, and their product would be subnormal
            if abs(v) <= FLIP_FLOOR or abs(prev) <= FLIP_FLOOR or (v > 0.0) == (prev > 0.0):
                watch[p, RUN_SLIP + q] = 0.0
                continue
            run = watch[p, RUN_SLIP + q] + 1.0
            watch[p, RUN_SLIP + q] = run
            if run == 1.0:
                watch[p, START_SLIP + q] = abs(v)
                continue
            if int(run) % CHATTER_STEPS == 1:  # a window of CHATTER_STEPS flips since its start
                start = watch[p, START_SLIP + q]
                # condition 2: not decayed, or (the slip) saturated at both ends
                if abs(v) >= NO_DECAY * start or (q == 0 and min(abs(v), start) >= saturated):
                    watch[p, FLAG] = SLIP if q == 0 else NORMAL
                    flagged = p
                    continue
                watch[p, START_SLIP + q] = abs(v)   # decaying: a stable mode; watch the next window
    return flagged


@njit(cache=True)
def idle(watch):
    """True when every contact point has been in the air for two steps (its row cleared): then
    a step that leaves every point in the air changes nothing in the tracker and flags nothing
    (chattering_point_at skips such a row)."""
    cleared = 0
    for p in range(watch.shape[0]):
        cleared += watch[p, TOUCHED] == CLEARED
    return cleared == watch.shape[0]


@njit(cache=True)
def clear_height(points):
    """COM height (m) at and above which no contact point touches the ground, whatever the
    body's angle: a point's height below the COM, sin l_x + cos l_y rounded, is at most
    |l_x| + |l_y| rounded (rounding is monotone, and |sin|, |cos| <= 1)."""
    height = 0.0
    for p in range(points.shape[0]):
        height = max(height, abs(points[p, 0]) + abs(points[p, 1]))
    return height


def unstable_law(scene, integrator: str | None = None) -> str | None:
    """Why no step size is stable for the scene's law under an explicit integrator (default:
    the scene's): a bare sign friction or rolling law (docs/stability.md#definition). None when
    some step is, and for implicit Euler, which no step size limits (but see unsolved_stick)."""
    method = integrator or scene.integrator
    why = [f"{law} {kick}" for law, kick in _kicks(scene)]
    if not why or method == "implicit_euler":
        return None
    if method == "rk4":
        what = ("RK4's four stages straddle the jump: under a steady load they cancel, so the motion "
                "creeps on at a constant speed below half a kick instead of stopping, and under a changing "
                "one, as a point bounces, the slip can flip every step: chatter")
    else:
        what = "where it should stick the slip flips sign every step for ever: chatter"
    return (f"{'; '.join(why)}: no step size is stable for {method} ({what}); use a regularised "
            "law (tanh, ramp, smooth_coulomb) or implicit_euler")


def _kicks(scene) -> list[tuple[str, str]]:
    """The scene's bare sign laws: (the law, the kick it gives a point per explicit step)."""
    ct, out = scene.contact, []
    if scene.has("friction") and ct.friction_law == "sign":
        out.append(("friction_law 'sign'", "(bare Coulomb) kicks a contact point's slip by h mu Fn / m_t "
                                           "each step, never to zero"))
    if scene.has("rolling_friction") and ct.roll_law == "sign":
        out.append(("roll_law 'sign'", "kicks a disk's spin by h mu_roll Fn / I each step, never to zero"))
    return out


def unsolved_stick(scene, integrator: str | None = None) -> str | None:
    """Why implicit Euler (default: the scene's integrator) can chatter under a bare sign law
    though no step size limits it, or None (another integrator, or no bare sign): where a point
    should stick its equation has no root (the force jumps over the value that would hold it),
    and the Newton solve ends on the jump, on either side of it; it does not solve the
    set-valued law, so a body resting on two points can land on alternate sides step after step
    (integrators.implicit_euler_step; docs/contact-laws.md)."""
    laws = [law for law, _ in _kicks(scene)]
    if (integrator or scene.integrator) != "implicit_euler" or not laws:
        return None
    return (f"no step size limits implicit_euler, but under {' and '.join(laws)} its equation has no root "
            "where a point should stick (the force jumps over the value that would hold it), and custom_sim's "
            "Newton ends on the jump, on either side of it, not on the stick of the set-valued law: a body "
            "resting on two points can land on alternate sides step after step (chatter); use a regularised "
            "law (tanh, ramp, smooth_coulomb)")
