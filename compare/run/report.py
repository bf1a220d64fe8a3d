"""`run`'s report, written whole: every scenario judged into a hidden folder beside DIR, then
index.md, then moved into place (compare/report/publish.py); bad input from the user's code, or
Ctrl-C, leaves DIR as it was. What the run is asked to do: a RunConfig (config.py)."""
from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path

from ..report import write_index
from ..report.publish import report_aside
from ..usersim import UserCodeError
from .config import RunConfig
from .outcome import run_one
from .processes import expected_cost, run_scenes


@dataclass
class Written:
    """What the report holds, in the order of the scenes."""

    rows: list[dict]       # metrics.json of each scenario that reached a verdict
    failed: list[tuple]    # (name, status, why) of each that did not ("skipped": the user's code does not do it)
    details: list[tuple]   # (name, the user's own traceback) of each scene where their code raised
    index: Path            # DIR/index.md


def write_report(scenes, simulator, config: RunConfig) -> Written:
    """Runs every scene (at most config.jobs at once, each stopped after config.timeout s) and
    writes config.out/; raises UserCodeError for the first bad input a scenario's process sent
    back, and Interrupted on Ctrl-C."""
    out = config.out
    with report_aside(out) as work:
        outcomes = run_scenes(scenes, functools.partial(run_one, out=str(work), simulator=simulator, config=config),
                              config.jobs, config.timeout, expected_cost)
        bad = [o.bad_input for o in outcomes.values() if o.bad_input]
        if bad:
            raise UserCodeError(*bad[0])
        rows = [outcomes[s.name].row for s in scenes if outcomes[s.name].row is not None]
        failed = [(s.name, *outcomes[s.name].failure) for s in scenes if outcomes[s.name].failure]
        details = [(s.name, outcomes[s.name].details) for s in scenes if outcomes[s.name].details]
        index = write_index(work, rows, failed)
    return Written(rows, failed, details, out / index.name)
