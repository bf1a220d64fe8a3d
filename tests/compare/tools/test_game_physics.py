"""The game's keys move the ball as Newton's laws predict (computed here, not by the game)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from compare.tools.game.ball import ball_scene


from compare.tools.game.ball import ALPHA, MASS, MU, MU_ROLL, RADIUS
from compare.tools.game.engines import make_engine
from compare.tools.game.game import KEY_FORCE, Game, KeyEvent
from compare.tools.game.passes import Pass

G = 9.81
INERTIA = 0.5 * MASS * RADIUS ** 2   # solid disk

# Round-off of summing N velocity increments of size ~h a (m/s): far below any physics here.
ROUNDOFF = 1e-9


def still_ball(x: float, y: float | None = None, v=(0.0, 0.0)):
    """A pass maker that puts the ball at (x, y) with velocity v (y None: resting on the ground)."""
    def make(seed, round_index, rest_height):
        return Pass((x, rest_height if y is None else y), v)
    return make


def engine_or_skip(name: str):
    if name == "mujoco":
        pytest.importorskip("mujoco_models")
    return make_engine(name)


@pytest.mark.parametrize("engine", ["custom", "mujoco"])
def test_a_key_acts_from_its_step_in_free_flight(engine):
    """In the air only gravity and the key act: semi-implicit Euler (ours, and MuJoCo's Euler)
    adds h (F/m - g) to vy on every step from the event's step on, and nothing before it
    (exact up to round-off)."""
    game = Game(pass_maker=still_ball(3.0, 3.0), fast=False, engine=engine_or_skip(engine))
    h = game.dt
    before = [game.state[4]]
    for _ in range(10):
        game.advance_to(game.step + 1)
        before.append(game.state[4])
    assert np.allclose(np.diff(before), -G * h, rtol=0, atol=ROUNDOFF), "vy per step before the key"
    vy0 = game.state[4]
    game.apply(KeyEvent(game.step, "w"))
    n = 200
    game.advance_to(game.step + n)
    assert game.state[1] > 2.0, "still in the air"
    expected = vy0 + n * h * (KEY_FORCE / MASS - G)
    assert game.state[4] == pytest.approx(expected, abs=ROUNDOFF), "vy after holding W"
    assert game.state[3] == 0.0, "no horizontal force"


@pytest.mark.parametrize("engine", ["custom", "mujoco"])
@pytest.mark.parametrize("key, direction", [("d", (1, 0)), ("a", (-1, 0)), ("s", (0, -1))])
def test_each_key_pushes_its_way_in_the_air(key, direction, engine):
    game = Game(pass_maker=still_ball(3.0, 3.0), fast=False, engine=engine_or_skip(engine))
    n = 100
    game.press(key)
    game.advance_to(n)
    h = game.dt
    dvx = direction[0] * KEY_FORCE / MASS * n * h
    dvy = (direction[1] * KEY_FORCE / MASS - G) * n * h
    assert game.state[3] == pytest.approx(dvx, abs=ROUNDOFF), "vx"
    assert game.state[4] == pytest.approx(dvy, abs=ROUNDOFF), "vy"


def test_holding_d_slides_the_ball_with_impulse_minus_friction():
    """F = 12 N > 3 mu m g = 6.3 N: the contact point slips, friction saturates at mu m g, so
    m dvx = (F - mu m g) t and I dw = (-R mu m g + mu_roll m g) t: friction spins the ball
    forward, rolling resistance (mu_roll Fn against the spin) holds it back.

    The tanh law reaches mu m g only once the slip s is well above 1/alpha. The slip grows at
    ds/dt = F/m - 3 f/m >= F/m - 3 mu g, so it passes S = 3/alpha within t_s = S / (F/m - 3 mu g);
    until then friction may be short by up to mu m g, afterwards by (1 - tanh 3) mu m g."""
    game = Game(pass_maker=still_ball(2.0), fast=False)
    t = 0.3
    n = int(round(t / game.dt))
    game.press("d")
    game.advance_to(n)
    s_sat = 3.0 / ALPHA
    t_s = s_sat / (KEY_FORCE / MASS - 3 * MU * G)
    shortfall = MU * G * (t_s + (1 - math.tanh(3.0)) * t)  # m/s: the most friction can miss
    x, y, th, vx, vy, om = game.state
    assert vx + om * RADIUS > s_sat, "the ball slides"
    assert vx == pytest.approx((KEY_FORCE - MU * MASS * G) * t / MASS, abs=shortfall), "vx"
    assert om == pytest.approx((-RADIUS * MU + MU_ROLL) * MASS * G * t / INERTIA,
                               abs=shortfall * MASS * RADIUS / INERTIA), "omega"


def test_a_gentle_push_rolls_the_ball():
    """F = 3 N < 3 mu m g: the ball rolls. Momentum and angular momentum about the centre give,
    with the friction force eliminated (disk, I = m R^2 / 2, rolling resistance mu_roll m g
    against the spin),
        m vx - (I / R) w = F t - (mu_roll m g / R) t_roll
    and with the slip s = vx + w R:  vx = (F t - mu_roll m g t_roll / R) / (1.5 m) + s / 3.
    custom_sim regularises the resistance's sign(w) as tanh(S w) (custom_sim.forces), so it
    acts in full once |w| > 3 / S; w grows at a / R from the second step (the first starts
    with no slip, so no friction and no spin): t_roll = t up to the ramp
    2 h + (3 / S) / (a / R), and (1 - tanh 3) t after it.
    The slip settles where tanh(alpha s) = |f| / (mu m g), f = I a / R^2 + mu_roll m g / R."""
    force = 3.0
    game = Game(key_force=force, pass_maker=still_ball(2.0), fast=False)
    h = game.dt
    t = 0.4
    n = int(round(t / h))
    game.press("d")
    game.advance_to(n)
    x, y, th, vx, vy, om = game.state
    resistance = MU_ROLL * MASS * G / RADIUS   # N, the rolling resistance as a force at the centre
    a = (force - resistance) / (1.5 * MASS)
    f = INERTIA * a / RADIUS ** 2 + resistance
    slip = math.atanh(f / (MU * MASS * G)) / ALPHA
    # The discrete slip update has the continuous steady state as its fixed point and relaxes
    # towards it by a factor 1 - h 3 mu g alpha (1 - tanh^2) = 0.58 a step: settled to round-off.
    assert vx + om * RADIUS == pytest.approx(slip, rel=1e-9), "slip settled at the tanh law's value"
    ramp = 2 * h + (3.0 / ball_scene().contact.roll_sharpness) / (a / RADIUS)
    missing = resistance * (ramp + (1.0 - math.tanh(3.0)) * t) / (1.5 * MASS)  # m/s, at most
    rolled = vx - (vx + om * RADIUS) / 3     # = (F t - resistance t_roll) / (1.5 m)
    assert a * t - ROUNDOFF <= rolled <= a * t + missing, "rolling identity"
    assert abs(vx - a * t) < 0.01 * a * t, "within 1 % of pure rolling, a = (F - mu_roll m g / R) / (1.5 m)"
