"""Remake the game's demo recording (compare/tools/game/demo_goal.json) by a scripted search.

    python -m compare tools game-demo

Round 1 (seed 1): the teammate's pass comes in bouncing; the script presses D (and W for lift)
once, at times and for durations taken from a small grid, and keeps the shot that scores with
the ball volleyed in the air from at least 3 m and crossing the line highest under the bar.
Round 2: D pushes the ball from far out and a second tap 0.6 m from the goal line sends it in:
the last kick decides, so the referee shows "too close". Then Q. Rewrites demo_goal.json (what
`python -m compare play --replay demo` plays) and prints its events, steps and result.
"""
from __future__ import annotations


def add_arguments(parser) -> None:
    pass


def main(args) -> int:
    from ...tools.game.demo import remake_demo

    return remake_demo()
