"""The explicit loop's cost has no hidden per-step part: numba counts no reference to its arrays.

numba counts a reference to an array passed into a compiled function (an atomic increment and
decrement) unless its pruner removes the pair, which a `break` or `return` inside a loop
prevents (custom_sim/forces.py). Before the loop was written to avoid them it counted 16 a step
on box_drop, a third of the step's cost. Counted, not timed: with NUMBA_DEBUG_NRT numba prints
every count, and a run of 45000 steps must print as many as one of 5000.
"""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

ADVANCE = """
import dataclasses, sys
from compare.scenarios import load
from custom_sim import Stepper
Stepper(dataclasses.replace(load("box_drop"), integrator=sys.argv[1])).advance(int(sys.argv[2]))
"""


@pytest.mark.slow
@pytest.mark.parametrize("integrator", ["semi_implicit_euler", "explicit_euler", "rk4"])
def test_the_explicit_loop_counts_no_reference_per_step(integrator, tmp_path):
    """box_drop's flight, landing, rocking and rest: the counts are those of the call alone."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path), "NUMBA_DEBUG_NRT": "1"}

    def counts(steps: int) -> int:
        out = subprocess.run([sys.executable, "-c", ADVANCE, integrator, str(steps)], cwd=ROOT, env=env,
                             capture_output=True, text=True, check=True).stdout
        return out.count("NRT_Incref") + out.count("NRT_Decref")

    assert counts(5_000) == counts(45_000)
