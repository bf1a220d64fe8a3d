"""Done once before the scenario processes fork, so that each inherits it instead of redoing it:
numba's compiled loops, the checks' and the report's modules, the report's figure frames, the
cache of scene-only work opened."""
from __future__ import annotations

import functools
from pathlib import Path

from custom_sim.compile_cache import warm_up_in_parallel


def prepare_workers(cache: Path | None = None) -> None:
    """What every worker needs before its first scenario, done once here so that the forked
    workers inherit it: the cache in the folder `cache` opened (None: off), the dynamics twin's
    compiled passive-force callback, and the modules of the checks and the report (matplotlib,
    scipy, mujoco: a second or more a process)."""
    import compare.report  # noqa: F401
    from ..store import prepare
    prepare(cache)   # joblib and the code's digest, once
    compare.report.prebuild_figures()   # each figure's axes and ticks, built once for every worker
    import compare.checks.attribution  # noqa: F401
    import compare.run.scenario  # noqa: F401
    import compare.checks.contact_check  # noqa: F401
    import compare.checks.dynamics_check  # noqa: F401
    import compare.checks.step_check  # noqa: F401
    import compare.oracle.reference  # noqa: F401
    from mujoco_models.passive import callback
    callback()


def compile_everything(cache: Path | None = None) -> None:
    """Compile once, before the workers start, so that they load numba's cache instead of each
    compiling the same code: custom_sim's two stepping loops at once, in this process and a
    forked one, and here, meanwhile, what prepare_workers(cache) does. Prints "compiling the
    simulator (first run only) ..." when it has to."""
    warm_up_in_parallel(meanwhile=functools.partial(prepare_workers, cache))
