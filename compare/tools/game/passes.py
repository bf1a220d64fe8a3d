"""The teammate's pass: each round the ball comes in from the left with a seeded speed and bounce.

Round i of seed s draws from `numpy.random.default_rng([s, i])`, so a round's pass depends
on the seed and its number only, never on what happened before (R, replays, skipped rounds).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .ball import RADIUS

TEAMMATE_X = 0.0          # m, where the pass starts (the teammate stands at the left edge)
SPEED = (3.0, 4.5)        # m/s, horizontal speed of the pass (uniform)
BOUNCE = (0.0, 4.0)       # m/s, upward speed: 0 rolls along the grass, 4 hops 0.8 m high
# Sliding on grass turns a pass at v0 into rolling at 2 v0 / 3 (disk); rolling resistance
# (0.89 m/s^2) then stops even the fastest (3 m/s rolling) about 7 m out: the ball stops short
# of the goal line (9 m) unless the player kicks it (tests/test_game_rules.py checks 100 passes).


@dataclass(frozen=True)
class Pass:
    """Initial ball state of a round: position (m), velocity (m/s), spin (rad/s, counter-clockwise)."""

    position: tuple[float, float]
    velocity: tuple[float, float]
    spin: float = 0.0

    def state(self) -> np.ndarray:
        """[x, y, theta, vx, vy, omega] for `Stepper.reset`."""
        return np.array([*self.position, 0.0, *self.velocity, self.spin], dtype=np.float64)


def teammate_pass(seed: int, round_index: int, height: float = RADIUS) -> Pass:
    """The pass of round `round_index` (0-based) for `seed`; the ball starts at `height` (m)."""
    rng = np.random.default_rng([seed, round_index])
    speed = float(rng.uniform(*SPEED))
    bounce = float(rng.uniform(*BOUNCE))
    return Pass(position=(TEAMMATE_X, height), velocity=(speed, bounce), spin=0.0)
