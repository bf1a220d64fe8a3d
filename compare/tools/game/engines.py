"""The ball's simulator, by name: "custom" (custom_sim.Stepper) or "mujoco" (the MuJoCo twin).

An engine has `.state` [x, y, theta, vx, vy, omega], `.advance(n, force=(Fx, Fy, tau))` and
`.reset(state)`, the interface of custom_sim.Stepper; the game needs nothing else.
"""
from __future__ import annotations

from custom_sim import Stepper

from .ball import DT, ball_scene

ENGINES = ("custom", "mujoco")


class EngineUnavailable(RuntimeError):
    """The engine asked for cannot run here (says why)."""


def make_engine(name: str = "custom", dt: float = DT):
    """A fresh engine for the game's ball scene at step dt (s)."""
    scene = ball_scene(dt)
    if name == "custom":
        return Stepper(scene, watch_chatter=False)  # the ball chatters at bounces (docs/stability.md): play on
    if name == "mujoco":
        try:
            from .mujoco_ball import MujocoBall
        except ImportError as exc:
            raise EngineUnavailable(f"--engine mujoco: the MuJoCo twin cannot be loaded ({exc})") from None
        return MujocoBall(scene)
    raise EngineUnavailable(f"unknown engine {name!r} (expected one of: {', '.join(ENGINES)})")
