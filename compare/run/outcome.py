"""A scenario's process (run_one) and what it sends back (Outcome); an error row's cause is
one line (one_line)."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ..usersim.errors import one_line


@dataclass
class Outcome:
    """What one scenario's process sent back: exactly one field is set."""

    row: dict | None = None            # metrics.json of a scenario that reached a verdict
    failure: tuple | None = None       # (status, why): no verdict (error, unstable, timeout, skipped)
    bad_input: tuple | None = None     # (message, details): the user's code broke the protocol
    details: str = ""                  # with a failure: the user's own traceback, where their code raised


def run_one(scene, out: str, simulator=None, config=None):
    """A scenario's process: run, judge and write it into `out`, with the cache config.cache
    (a RunConfig, config.py; None: the environment's). Returns an Outcome: the metrics.json
    dict; or (status, cause) when no verdict could be reached; or the bad input the user's code
    gave (the whole run then writes nothing). Never raises."""
    from ..usersim import UserCodeError
    try:
        from mujoco_models import to_mjcf

        from ..report import write_scenario, write_skipped
        from .scenario import run_scenario

        from ..store import Cache, folder, using

        with using(Cache(folder() if config is None else config.cache)) as cache:
            result = run_scenario(scene, simulator)
            if result.skipped:   # its page says why; it fails nothing
                write_skipped(result, Path(out))
                return Outcome(failure=("skipped", result.skipped))
            if result.error:
                return Outcome(failure=(result.status.value, result.error), details=result.error_details)
            row = write_scenario(result, Path(out), to_mjcf(scene))
        return Outcome(row={**row, "cache": cache.counts()})
    except UserCodeError as exc:
        return Outcome(bad_input=(str(exc), exc.details))
    except Exception as exc:  # noqa: BLE001 - becomes the scenario's error row
        return Outcome(failure=("error", one_line(exc)))
