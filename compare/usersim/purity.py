"""Whether a step function is a function of its arguments: the same state in, the same state out.

The harness calls a step function in order through a run, and again from chosen states (the
diagnosis) and on variants of the scene. A step that keeps state between calls (a counter for
the time, a cached previous state, a module-level accumulator) answers a call out of order with
another state than its run used. The test: from a fresh copy of the module, call the step
twice from each of a few states of its own run; a function of its arguments returns, both
times, exactly the next state of the run.
"""
from __future__ import annotations

import numpy as np

from custom_sim import Scene

from .base import _state_text
from .errors import UserCodeError, UserFault
from .guard import EndedProcess
from .scene_dict import scene_dict

PROBES = 8   # states of the run probed, each twice: spread over its phases (flight, contact, rest)


def probe_rows(states: np.ndarray) -> list[int]:
    """Rows probed: spread over the run, away from the start (a fresh module answers the first
    call as its run did, whatever state it keeps)."""
    n = len(states) - 1
    return sorted({max(1, (k * n) // (PROBES + 1)) for k in range(1, PROBES + 1)} - {n}) if n > 1 else []


def keeps_state(simulator, scene: Scene, states: np.ndarray) -> str | None:
    """None for a step that answers as a function of its arguments (or for a simulator that is
    not a step function); otherwise the sentence the report shows."""
    if getattr(simulator, "kind", "") != "step":
        return None
    simulator.fresh()
    sd = scene_dict(scene)
    for row in probe_rows(states):
        try:
            first = simulator.call(states[row], sd, scene.dt, row + 1)
            second = simulator.call(states[row], sd, scene.dt, row + 1)
        except EndedProcess:
            raise
        except (UserFault, UserCodeError) as exc:
            return (f"your step keeps state between calls: called again from the state of step {row} of its own "
                    f"run, it failed ({exc}) where the run went on; judged: the sequential run only")
        want = states[row + 1]
        if not (np.array_equal(first, want) and np.array_equal(second, want)):
            return (f"your step keeps state between calls: from the state of step {row} of its own run it "
                    f"returned {_state_text(first)}, then {_state_text(second)}, where the run had "
                    f"{_state_text(want)}; judged: the sequential run only (the diagnosis does not call it "
                    "from chosen states)")
    return None
