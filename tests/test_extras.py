"""The base install runs everything but `study` and `play --video`: Dask is the `study` extra and
imageio the `game` extra (pyproject.toml). Their paths stay free of both; without them `sweep`
runs on a process pool, and `study` and `play --video` say in one line what to install."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXTRAS = ("dask", "distributed", "imageio", "imageio_ffmpeg")   # top-level modules of the extras

# Hides the extras from a fresh interpreter, as if they were not installed: None in sys.modules
# makes `import` raise ImportError and importlib.util.find_spec return None.
HIDE = f"import sys\nfor _name in {EXTRAS!r}:\n    sys.modules[_name] = None\n"

IMPORTS = """
import json, sys
import compare, compare.cli
import compare.commands.run, compare.run.report, compare.run.lines, compare.executor
import compare.commands.sweep, compare.tools.accuracy.workprecision, compare.tools.sweep.report
compare.cli.build_parser(everything=True)   # imports every command and tool module
print(json.dumps(sorted(m for m in sys.modules if m.split(".")[0] in EXTRAS)))
"""

WITHOUT_EXTRAS = """
import contextlib, io, json
from compare import cli

def status_of(argv):
    try:
        return cli.main(argv)
    except SystemExit as exc:   # --help
        return exc.code

out = []
for argv in ARGVS:
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        status = status_of(argv)
    out.append([status, err.getvalue()])
print(json.dumps(out))
"""

SWEEP_WITHOUT_DASK = """
import dataclasses, json
from compare import executor
from compare.executor.base import Executor
from compare.tools.accuracy.workprecision import run_sweep
from compare.scenarios import load
assert not executor.dask_available()
seen = []
real = Executor.run
def run(self, *a, **k):
    seen.append(type(self).__name__)
    return real(self, *a, **k)
Executor.run = run
scene = dataclasses.replace(load("box_slide"), duration=DURATION)
(sweep,) = run_sweep([scene], cache_dir=None, jobs=2, mujoco=False, stability=False,
                     ladders={"custom": LADDER})
print(json.dumps({"engines": seen, "runs": [[r.integrator, r.dt, r.error_max, r.force_evals]
                                             for r in sweep.runs]}))
"""

# A short box_slide and a short ladder: the sweep on the pool takes a few seconds.
SWEEP_DURATION = 0.2   # s simulated
SWEEP_LADDER = (1, 2)  # dt = 2 ms, 1 ms


def python(code: str, timeout: float = 120) -> str:
    proc = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True,
                          timeout=timeout)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout.strip().splitlines()[-1]


def test_run_and_sweep_import_neither_dask_nor_imageio():
    """Importing the package, `run`, `sweep` and every command's parser pulls in no extra."""
    loaded = json.loads(python(f"EXTRAS = {EXTRAS!r}\n" + IMPORTS))
    assert loaded == [], f"imported on the run/sweep path: {loaded}"


def test_without_the_extras_study_and_video_say_in_one_line_what_to_install(tmp_path):
    argvs = [["--help"], ["list"],
             ["study", "box_slide", "--vary", "dt=1e-4:1e-3:2", "--out", f"{tmp_path}/study"],
             ["sweep", "box_slide", "--scheduler", "tcp://127.0.0.1:8786", "--out", f"{tmp_path}/sweep"],
             ["play", "--replay", "demo", "--video", f"{tmp_path}/demo.mp4"],
             ["play", "--replay", "demo", "--video", f"{tmp_path}/demo.gif"]]
    (help_, list_, study, sweep, mp4, gif) = json.loads(python(HIDE + f"ARGVS = {argvs!r}\n" + WITHOUT_EXTRAS))
    assert help_[0] == 0 and list_[0] == 0
    assert study == [2, "error: study needs Dask: pip install -e '.[study]'\n"]
    assert sweep == [2, "error: sweep --scheduler needs Dask: pip install -e '.[study]'\n"]
    assert mp4 == [2, "error: play --video needs imageio and imageio-ffmpeg: pip install -e '.[game]'\n"]
    assert gif == [2, "error: play --video needs imageio: pip install -e '.[game]'\n"]
    assert not any(tmp_path.iterdir()), "bad input writes nothing"


@pytest.mark.slow
def test_sweep_without_dask_runs_on_the_process_pool_with_the_same_errors():
    """The pool's results are the in-process ones: errors and force evaluations are counted and
    computed, not timed, so they match bit for bit."""
    import dataclasses

    from compare.tools.accuracy.workprecision import custom_ladder, reference_task
    from compare.scenarios import load
    from custom_sim import INTEGRATORS

    code = (HIDE + f"DURATION = {SWEEP_DURATION!r}\nLADDER = {SWEEP_LADDER!r}\n" + SWEEP_WITHOUT_DASK)
    got = json.loads(python(code))
    assert set(got["engines"]) == {"Pool"}
    scene = dataclasses.replace(load("box_slide"), duration=SWEEP_DURATION)
    ref = reference_task(scene, None)
    expected = [[r.integrator, r.dt, r.error_max, r.force_evals] for integ in INTEGRATORS
                for r in custom_ladder(scene, integ, ref["states"], ref["energy_scale"], SWEEP_LADDER)]
    assert got["runs"] == json.loads(json.dumps(expected))
