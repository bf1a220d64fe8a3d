"""Whether a step answers designed probes as a function of its arguments: probes replayed out of order.

Designed identification reads a law from single calls made from states the step never visited
in that order. A step that keeps state between calls (the previous call's depth for a backward
difference, a stick/slip anchor, a counter for the time) answers each of them from whatever the
call before left behind: no law can be read from such answers. The test, as `validate` makes it
on a run (compare/usersim/purity.py): call the step again from a few probes already made, in
the reverse order, after other probes; a function of (state, scene, dt) returns exactly what it
returned the first time.
"""
from __future__ import annotations

import numpy as np

from ..usersim.base import _state_text

REPLAYED = 16   # probes called again: spread over flight and contact, in reverse order


def replayed_rows(n: int) -> list[int]:
    """Rows replayed out of n, last first (each then follows another probe than it did)."""
    if n <= 1:
        return list(range(n))
    return sorted({(k * (n - 1)) // (REPLAYED - 1) for k in range(REPLAYED)}, reverse=True)


def keeps_state(calls, Z0: np.ndarray, H: np.ndarray, Z1: np.ndarray, what: str) -> str | None:
    """None when the step returns, from every replayed probe (Z0, H) exactly its first answer
    Z1; otherwise the sentence the report shows (its start is validate's)."""
    for i in replayed_rows(len(Z0)):
        again = calls.one(Z0[i], float(H[i]), f"{what}, probe {i + 1} replayed out of order")
        if not np.array_equal(again, Z1[i]):
            return (f"your step keeps state between calls: called again from the designed state {_state_text(Z0[i])} "
                    f"(dt = {float(H[i]):.6g} s) after other probes, it returned {_state_text(again)} where it first "
                    f"returned {_state_text(Z1[i])}; no law is read from designed probes: identified from its own "
                    "sequential run from the scene's start")
    return None
