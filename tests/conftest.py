"""Shared helpers for the tests: scenes built in code from the schema of docs/scene-format.md."""
from __future__ import annotations

import copy
import os

import pytest

# The tests compute everything: the cache of scene-only work (compare/store.py) stays off unless a
# test turns it on for itself (tests/test_store.py), so no test reads what another run left.
os.environ["CONTACT_HARNESS_CACHE"] = "off"

from custom_sim import parse_scene


# Compiles the batched loop (custom_sim.batch, the study's; ~13 s on a fresh checkout) into
# numba's cache, in a process of its own beside the controller's warm-up.
WARM_BATCH = """
import dataclasses
from compare.scenarios import load
from custom_sim.batch import simulate_batch
simulate_batch([dataclasses.replace(load("box_drop"), duration=0.01)], threads=1)
"""


def pytest_configure(config):
    """Under pytest-xdist, compile the simulator into numba's cache once, in the controller,
    before the workers start: otherwise on a fresh checkout every worker (and every Dask worker
    of test_study) compiles the same loops at the same time. Quick when the cache is warm; a
    warm-up that fails leaves the compiling to the tests."""
    workers = getattr(config.option, "numprocesses", None)
    if hasattr(config, "workerinput") or not workers or getattr(config.option, "collectonly", False):
        return
    import subprocess
    import sys
    from pathlib import Path

    try:
        from custom_sim import batch
        from custom_sim.compile_cache import is_cached, needs_compiling, warm_up_in_parallel

        other = None
        if not is_cached(getattr(batch, "_run_batch", None)):
            other = subprocess.Popen([sys.executable, "-c", WARM_BATCH], cwd=Path(__file__).resolve().parents[1],
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        if needs_compiling():
            warm_up_in_parallel()
        if other is not None:
            other.wait()
    except Exception:   # noqa: BLE001 - an optimisation only
        pass


def make_scene(body: dict, initial: dict, **top):
    """A scene from dicts, with the given top-level overrides (contact={...} etc.)."""
    data = {"duration": 1.0, "dt": 1e-4, "body": body, "initial": initial}
    data.update(copy.deepcopy(top))
    return parse_scene(data, file="<test>")


@pytest.fixture
def scene_factory():
    return make_scene
