"""A new report written beside the old one, then moved into place whole, or not at all.

    with report_aside(out) as work:   # a hidden fresh folder in `out` (or beside it, before it exists)
        ... write index.md and the scenario folders into work ...
    # leaving the block without an exception: the old report's files leave `out`, the new
    # ones take their place; with an exception: work is removed and `out` is untouched

The old report is its index.md and every folder holding a metrics.json (a scenario page);
anything else in `out` (reports/calibration, reports/sweep, a user's own files) stays.
"""
from __future__ import annotations

import contextlib
import os
import shutil
from pathlib import Path

from ..files import temporary_folder


def _old_report(out: Path) -> list[Path]:
    if not out.is_dir():
        return []
    return [p for p in out.iterdir()
            if p.name == "index.md" or (p.is_dir() and not p.name.startswith(".") and (p / "metrics.json").is_file())]


@contextlib.contextmanager
def report_aside(out: Path):
    out = Path(out)
    # the temporaries go in DIR itself (hidden), or, where it does not exist yet, in its nearest
    # existing parent: nothing is created before the report is whole
    existing = out if out.is_dir() else next(p for p in out.parents if p.is_dir())
    work = temporary_folder(existing, f".{out.name}.new-")
    try:
        yield work
    except BaseException:
        shutil.rmtree(work, ignore_errors=True)
        raise
    out.mkdir(parents=True, exist_ok=True)
    old = temporary_folder(existing, f".{out.name}.old-")
    try:
        for path in _old_report(out):
            os.replace(path, old / path.name)
        for path in work.iterdir():
            target = out / path.name
            if target.is_dir() and not (target / "metrics.json").is_file():
                shutil.rmtree(target)   # a folder of that name that is no report page
            os.replace(path, target)
    finally:
        shutil.rmtree(old, ignore_errors=True)
        shutil.rmtree(work, ignore_errors=True)
