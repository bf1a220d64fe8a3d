"""The first run's compile: said once, done once, in the right cache folder; the cold-start
benchmark's table. (How long it takes is measured by `python -m compare bench --cold`, not here.)"""
from __future__ import annotations

import io
import os
import subprocess
import sys
from pathlib import Path

import pytest

from compare.tools.accuracy import cold_start
from short_scene import short_scene
from custom_sim import compile_cache
from custom_sim.compile_cache import COMPILING_MESSAGE, needs_compiling, warm_up
from custom_sim.integrators import integrate_explicit, integrate_implicit

ROOT = Path(__file__).resolve().parents[2]


def test_warm_up_compiles_what_a_run_needs_and_is_quiet_once_cached():
    warm_up(io.StringIO())   # compiles if this process has not yet
    assert not needs_compiling()
    assert integrate_explicit.signatures and integrate_implicit.signatures, "both stepping loops are compiled"
    quiet = io.StringIO()
    warm_up(quiet)
    assert quiet.getvalue() == ""


def test_warm_up_says_so_when_it_must_compile(monkeypatch):
    monkeypatch.setattr(compile_cache, "is_cached", lambda dispatcher: False)
    said = io.StringIO()
    warm_up(said)
    assert said.getvalue() == COMPILING_MESSAGE + "\n"


PARALLEL_WARM_UP = """
import sys
from custom_sim.compile_cache import needs_compiling, warm_up_in_parallel
from custom_sim.integrators import first_unhealthy, integrate_explicit, integrate_implicit
warm_up_in_parallel(sys.stdout, meanwhile=lambda: print("meanwhile"))
print(needs_compiling(), len(integrate_explicit.signatures), len(integrate_implicit.signatures))
# who compiled what: this process the explicit loop (a cache miss), the other the implicit one
# (here a cache hit: loaded from what the other process wrote); the blow-up check, this process
print(sum(integrate_explicit.stats.cache_misses.values()), sum(integrate_implicit.stats.cache_misses.values()),
      sum(integrate_implicit.stats.cache_hits.values()), sum(first_unhealthy.stats.cache_misses.values()))
"""


@pytest.mark.slow
def test_the_parallel_warm_up_compiles_both_loops_into_an_empty_cache_and_says_so_once(tmp_path):
    """Its two halves are compiled in two processes: this one compiles the explicit loop and
    loads the implicit one from what the other wrote; afterwards the cache is complete."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    out = subprocess.run([sys.executable, "-c", PARALLEL_WARM_UP], cwd=ROOT, env=env, capture_output=True,
                         text=True, check=True).stdout.splitlines()
    assert out == [COMPILING_MESSAGE, "meanwhile", "False 1 1", "1 0 1 1"], out


def test_the_cache_stamp_follows_numba_cache_dir(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    code = "from custom_sim.compile_cache import cache_folder, fresh_cache; fresh_cache(); print(cache_folder())"
    out = subprocess.run([sys.executable, "-c", code],
                         cwd=ROOT, env=env, capture_output=True, text=True, check=True).stdout.strip()
    assert Path(out).is_relative_to(tmp_path), out
    assert (Path(out) / "numba_sources.sha256").is_file(), "the source digest is kept beside numba's cache"


def test_cold_start_table_shows_every_stage_for_each_tree():
    t = cold_start.Timed(1.5, 1.25, 0)
    r = cold_start.ColdStart("x", t, t, t, t, t, t, t)
    text = cold_start.table([("today", r), ("before", r)])
    assert "today" in text and "before" in text
    for stage in ("compile (empty cache)", "run, cache warm", "first run (empty cache)", "second run",
                  "run --sim (example copy)", "run --sim after an edit", "of which the copy's own code"):
        assert stage in text
    assert text.count("1.5") == 14 and text.count("1.2") == 14


def test_cold_start_rounds_keep_each_stages_fastest_round(monkeypatch):
    """Round 1 is slow in the compile, the first run and the rerun after an edit, round 2 in
    the other runs: each stage keeps its own minimum, with the CPU time of that same round."""
    walls = iter([9.0, 2.0, 8.0, 2.0, 4.0, 7.0,   # round 1: compile, run warm, first, second, --sim, after edit
                  5.0, 3.0, 6.0, 3.0, 5.0, 4.0])  # round 2
    commands = []

    def timed(command, cwd, cache, ok=(0, 1)):
        commands.append(command)
        return (lambda w: cold_start.Timed(w, w + 0.5, 0))(next(walls))

    monkeypatch.setattr(cold_start, "timed", timed)
    own = iter([cold_start.Timed(1.0, 1.5, 0), cold_start.Timed(0.5, 1.0, 0)])
    monkeypatch.setattr(cold_start, "user_code", lambda sim, scenes: next(own))
    (r,) = cold_start.measure([ROOT], ["box_slide"], rounds=2)
    assert r.user_code == cold_start.Timed(0.5, 1.0, 0)
    assert [r.compile.wall, r.run_warm.wall, r.first_run.wall, r.second_run.wall, r.user_run.wall,
            r.after_edit.wall] == [5.0, 2.0, 6.0, 2.0, 4.0, 4.0]
    assert r.compile.cpu == 5.5 and r.run_warm.cpu == 2.5
    sims = [c[c.index("--sim") + 1] for c in commands if "--sim" in c]
    assert len(sims) == 4 and all(s.endswith("my_sim.py:step") for s in sims), "the last two stages run a copy"


def test_the_users_code_alone_is_timed_inside_its_process(tmp_path):
    """The probe runs the copy's step on the scene and, where it differs, the friction-off
    variant: elastic_bounce is its own variant (one run), box_slide is not (two)."""
    sim = tmp_path / "my_sim.py"
    sim.write_text((ROOT / "examples" / "seed_sim.py").read_text() + "\nCALLS = []\n"
                   "_step = step\n"
                   "def step(state, scene, dt):\n"
                   "    if not CALLS: open(__file__ + '.runs', 'a').write('run\\n')\n"
                   "    CALLS.append(1)\n"
                   "    return _step(state, scene, dt)\n")
    # cut to 0.1 s: the runs, not their length, are counted
    scenes = [str(short_scene(tmp_path, name, 0.1)) for name in ("elastic_bounce", "box_slide")]
    timed = cold_start.user_code(sim, scenes)
    assert 0 < timed.cpu and 0 < timed.wall
    assert (tmp_path / "my_sim.py.runs").read_text().count("run") == 3


def test_the_compile_stage_takes_the_probe_that_runs_on_the_revision_and_fails_without_one(monkeypatch):
    """A probe that exits 1 (an older revision lacks a module it imports) must not count as a
    compile: the next stage would then compile, and both figures would be wrong."""
    said = []

    def timed(command, cwd, cache, ok=(0, 1)):
        said.append((command[-1], ok))
        if command[-1] == cold_start.COMPILE_PROBE or fail_both:
            raise RuntimeError("exited 1: ImportError")
        return cold_start.Timed(3.0, 3.5, 0)

    monkeypatch.setattr(cold_start, "timed", timed)
    fail_both = False
    assert cold_start.compile_time(ROOT, "cache") == cold_start.Timed(3.0, 3.5, 0)
    assert said == [(cold_start.COMPILE_PROBE, (0,)), (cold_start.WARM_UP_PROBE, (0,))]
    fail_both = True
    with pytest.raises(RuntimeError, match="neither compile probe runs"):
        cold_start.compile_time(ROOT, "cache")


def test_bench_cold_says_which_command_failed_without_a_traceback(monkeypatch, capsys):
    from compare.cli import main

    def measure(trees, scenes, rounds=1):
        raise RuntimeError("neither compile probe runs in /old: exited 1: ImportError")

    monkeypatch.setattr(cold_start, "measure", measure)
    assert main(["bench", "--cold"]) == 1
    err = capsys.readouterr().err
    assert err.startswith("error: bench --cold: neither compile probe runs in /old") and "Traceback" not in err
