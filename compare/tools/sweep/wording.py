"""How the sweep writes a run: integrator names, times (s or ms), lengths (mm or um), numbers."""
from __future__ import annotations

import math

from ...table import number

LABELS = {"explicit_euler": "explicit Euler", "semi_implicit_euler": "semi-implicit Euler",
          "implicit_euler": "implicit Euler", "rk4": "RK4"}


def ms(seconds: float) -> str:
    return f"{seconds:.3g} s" if seconds >= 1.0 else f"{seconds * 1e3:.3g} ms"


def mm(metres: float) -> str:
    if metres < 1e-4:
        return f"{metres * 1e6:.2g} um"
    return f"{metres * 1e3:.3g} mm"


def name(run) -> str:
    if run.simulator == "yours":
        return f"yours: {LABELS.get(run.integrator, run.integrator)}"
    return LABELS.get(run.integrator, run.integrator) if run.simulator == "custom" else f"MuJoCo {run.integrator}"


SIMULATOR = {"custom": "ours", "mujoco": "MuJoCo", "yours": "yours"}   # how the tables name each


def timing(run) -> str:
    """CPU time with its measured spread: '0.11 ms (+- 0.01 ms)'."""
    spread = run.cpu_time_spread
    return ms(run.cpu_time) + (f" (+- {ms(spread)})" if math.isfinite(spread) else "")


def cost(run) -> str:
    if run.force_evals is None:   # the user's code counts none
        return f"{run.steps} steps"
    return f"{run.force_evals} force evaluations ({run.steps} steps)"


def num(x, **options) -> str:
    """The sweep's number: 3 significant digits, "-" for a value that is missing or not finite."""
    return number(x, none="-", nonfinite="-", **options)
