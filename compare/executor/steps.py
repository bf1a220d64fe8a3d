"""How far a task's run has got, shared with the process that shows it.

The worker process running a task publishes (steps reached, steps in the run, time stepping
began) in its slot of a shared array (a user's step function does, compare/usersim/functions.py);
the executor reads it to show steps per second, to name the step reached when the user presses
Ctrl-C, and to say where a task was when it timed out. Outside such a process (a test,
`validate`) publishing does nothing.
"""
from __future__ import annotations

import time

FIELDS = 3            # steps reached, steps in the run, time.time() when stepping began
_slot = None          # (shared array, offset) of this process's scene, or None


def attach(shared, index: int) -> None:
    """This process runs scene `index`: publish into its slot of `shared`."""
    global _slot
    _slot = (shared, index * FIELDS)


def started(steps: int) -> None:
    if _slot is not None:
        shared, k = _slot
        shared[k], shared[k + 1], shared[k + 2] = 0.0, float(steps), time.time()


def reached(step: int) -> None:
    if _slot is not None:
        shared, k = _slot
        shared[k] = float(step)


def read(shared, index: int) -> tuple[int, int, float]:
    """(steps reached, steps in the run, time stepping began; 0 before it began)."""
    k = index * FIELDS
    return int(shared[k]), int(shared[k + 1]), float(shared[k + 2])
