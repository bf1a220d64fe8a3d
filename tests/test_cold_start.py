"""The first run's compile: said once, done once, in the right cache folder; the cold-start
benchmark's table. (How long it takes is measured by `python -m compare bench --cold`, not here.)"""
from __future__ import annotations

import io
import os
import subprocess
import sys
from pathlib import Path

from compare.accuracy import cold_start
from custom_sim import compile_cache
from custom_sim.compile_cache import COMPILING_MESSAGE, is_cached, warm_up
from custom_sim.integrators import first_unhealthy, integrate

ROOT = Path(__file__).resolve().parents[1]


def test_warm_up_compiles_what_a_run_needs_and_is_quiet_once_cached():
    warm_up(io.StringIO())   # compiles if this process has not yet
    assert is_cached(integrate) and is_cached(first_unhealthy)
    assert integrate.signatures, "the stepping loop is compiled"
    quiet = io.StringIO()
    warm_up(quiet)
    assert quiet.getvalue() == ""


def test_warm_up_says_so_when_it_must_compile(monkeypatch):
    monkeypatch.setattr(compile_cache, "is_cached", lambda dispatcher: False)
    said = io.StringIO()
    warm_up(said)
    assert said.getvalue() == COMPILING_MESSAGE + "\n"


def test_the_cache_stamp_follows_numba_cache_dir(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    out = subprocess.run([sys.executable, "-c", "from custom_sim.compile_cache import cache_folder; print(cache_folder())"],
                         cwd=ROOT, env=env, capture_output=True, text=True, check=True).stdout.strip()
    assert Path(out).is_relative_to(tmp_path), out
    assert (Path(out) / "numba_sources.sha256").is_file(), "the source digest is kept beside numba's cache"


def test_cold_start_table_shows_every_stage_for_each_tree():
    t = cold_start.Timed(1.5, 1.25, 0)
    r = cold_start.ColdStart("x", t, t, t, t)
    text = cold_start.table([("today", r), ("before", r)])
    assert "today" in text and "before" in text
    for stage in ("compile (empty cache)", "run, cache warm", "first run (empty cache)", "second run"):
        assert stage in text
    assert text.count("1.5") == 8 and text.count("1.2") == 8
