"""The game's frame rate, measured headless (matplotlib Agg with blitting).

    python -m compare tools game-fps

Plays 6 s of a game off-screen at 50 frames per second, three times: D held 20 % of the time,
D held all the time, and the texts re-rendered every frame. One line each: the frames per second
the physics and the drawing allow, the milliseconds of each per frame, and what reading the
pixels for a video adds.
"""
from __future__ import annotations


def add_arguments(parser) -> None:
    pass


def main(args) -> int:
    from ...tools.game.view import print_fps

    return print_fps()
