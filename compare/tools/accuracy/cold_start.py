"""What a first run costs: numba compiling the simulator, apart from the run itself.

Each figure comes from a fresh Python process with NUMBA_CACHE_DIR pointing at a folder of its
own, and the cache of scene-only work (compare/store.py) beside it, so nothing compiled or
computed earlier on the machine is reused:

    compile      the simulator compiled into an empty cache in one process (10 steps of
                 box_drop with each integrator, and the blow-up check a MuJoCo trajectory goes
                 through: everything of custom_sim that `run` compiles; on an older revision
                 its own warm-up)
    run, warm    `python -m compare run SCENES` once that compile is cached (no scene-only work yet)
    first run    `python -m compare run SCENES` on other empty caches: what a new user waits
    second run   the same command again, both caches now full
    user's run   `python -m compare run SCENES --sim COPY:step`, COPY a copy of examples/seed_sim.py
    after edit   the same again after an edit of COPY: what a user waits between two edits
                 (nothing of a user's simulator is cached, so any edit costs the same)
    user's code  COPY's step alone, through the runs `run --sim` makes of it (the scene, and its
                 variant with friction off where that differs): the part of `after edit` that
                 is the user's code, measured in today's checkout for every tree. Over N cores,
                 `after edit` cannot take less wall time than its CPU time / N.

Wall time is what a user waits; CPU time (user + system, all the processes of the command)
is what the machine spent, and moves less with other load. The load average is printed with
them. With `tree`, an older checkout of the repository, the same commands also run there,
in alternation with today's, so both are measured under the same load.
"""
from __future__ import annotations

import os
import resource
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from ...table import text

ROOT = Path(__file__).resolve().parents[3]

# The compile probe: works on any revision of custom_sim (no warm_up needed); one process,
# every integrator, so it is the whole compile as one core does it.
COMPILE_PROBE = """
import dataclasses, numpy as np, custom_sim as cs
from custom_sim.integrators import first_unhealthy
from custom_sim.runner import blowup_guard
scene = cs.load_scene('scenarios/box_drop.toml')
for name in cs.INTEGRATORS:
    traj = cs.simulate(dataclasses.replace(scene, duration=10 * scene.dt, integrator=name))
states = np.ascontiguousarray(traj.states())
first_unhealthy(states, blowup_guard(scene, cs.mass_properties(scene.body), states[0], applied_input=False))
"""
# On a revision whose modules the probe above does not find: its own warm-up, which compiles
# what its run executes.
WARM_UP_PROBE = "from custom_sim.compile_cache import warm_up; warm_up()"

# The user's code alone: the runs of their step that `run --sim` cannot do without, through the
# harness's own loop (compare/usersim), timed inside the process (imports left out).
USER_CODE_PROBE = """
import sys, time
from compare.checks.contact_check import contact_scene
from compare.scenarios import load_all
from compare.usersim import load_simulator, run_user
sim = load_simulator(sys.argv[1])
scenes = load_all(sys.argv[2:])
wall, cpu = time.perf_counter(), time.process_time()
for scene in scenes:
    variant = contact_scene(scene)
    for run in (scene, variant) if variant != scene else (scene,):
        run_user(sim, run)
print(time.perf_counter() - wall, time.process_time() - cpu)
"""


@dataclass(frozen=True)
class Timed:
    """One command: wall time and CPU time (s) of the process and its children; exit status."""

    wall: float
    cpu: float
    status: int


def timed(command: list[str], cwd: Path, cache: str, ok: tuple = (0, 1)) -> Timed:
    """Run command in cwd with NUMBA_CACHE_DIR = cache and the cache of scene-only work beside it
    (compare/store.py: a first run on a fresh machine has neither); its wall and CPU time. An
    exit status outside `ok` (a run's 0 or 1 by default) raises RuntimeError."""
    env = {**os.environ, "NUMBA_CACHE_DIR": cache, "PYTHONPATH": str(cwd),
           "CONTACT_HARNESS_CACHE": os.path.join(cache, "results")}
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    proc = subprocess.run(command, cwd=cwd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if proc.returncode not in ok:
        raise RuntimeError(f"{' '.join(command)} (in {cwd}) exited {proc.returncode}: {proc.stderr.strip()[-500:]}")
    return Timed(wall, cpu, proc.returncode)


def compile_time(tree: Path, cache: str) -> Timed:
    """The compile into the empty `cache`: COMPILE_PROBE, or WARM_UP_PROBE where that cannot run
    (an older revision). A probe that fails would leave the compile to the next stage's run and
    show a failure's time as the compile's, so no figure is better: RuntimeError."""
    errors = []
    for probe in (COMPILE_PROBE, WARM_UP_PROBE):
        try:
            return timed([sys.executable, "-c", probe], tree, cache, ok=(0,))
        except RuntimeError as err:
            errors.append(str(err).splitlines()[-1])
    raise RuntimeError(f"neither compile probe runs in {tree}: {'; '.join(errors)}")


def user_code(sim: Path, scenes: list[str]) -> Timed:
    """The wall and CPU time (s) of USER_CODE_PROBE: the step function in `sim` run as `run
    --sim` runs it on `scenes` (default: the built-ins), in today's checkout."""
    proc = subprocess.run([sys.executable, "-c", USER_CODE_PROBE, f"{sim}:step", *scenes], cwd=ROOT,
                          env={**os.environ, "PYTHONPATH": str(ROOT)}, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"timing the user's code alone failed: {proc.stderr.strip()[-500:]}")
    wall, cpu = map(float, proc.stdout.split()[-2:])
    return Timed(wall, cpu, 0)


@dataclass(frozen=True)
class ColdStart:
    """The figures of the module docstring for one checkout."""

    tree: str
    compile: Timed
    run_warm: Timed
    first_run: Timed
    second_run: Timed
    user_run: Timed
    after_edit: Timed
    user_code: Timed


def measure(trees: list[Path], scenes: list[str], jobs: int | None = None, rounds: int = 1) -> list[ColdStart]:
    """The cold-start figures of each checkout in `trees`, stage by stage in alternation;
    with rounds > 1 the whole sequence is repeated and each stage keeps its fastest round
    (a shared machine's speed drifts by a third within minutes)."""
    run = [sys.executable, "-m", "compare", "run", *scenes]
    if jobs:
        run += ["--jobs", str(jobs)]
    best: list[list[Timed]] = [[] for _ in trees]
    for _ in range(max(1, rounds)):
        with tempfile.TemporaryDirectory() as work:
            def folder():
                return tempfile.mkdtemp(dir=work)
            caches = [(folder(), folder()) for _ in trees]
            stages = [[] for _ in trees]
            sims = [Path(folder()) / "my_sim.py" for _ in trees]
            for step in range(6):
                for i, tree in enumerate(trees):
                    if step == 0:
                        stages[i].append(compile_time(tree, caches[i][0]))
                        continue
                    cache, extra = caches[i][0] if step == 1 else caches[i][1], []
                    if step == 4:
                        sims[i].write_text((tree / "examples" / "seed_sim.py").read_text())
                    if step == 5:
                        sims[i].write_text(sims[i].read_text() + "\n# an edit\n")
                    if step >= 4:
                        extra = ["--sim", f"{sims[i]}:step"]
                    stages[i].append(timed([*run, *extra, "--out", folder()], tree, cache))
                    if step == 5:
                        stages[i].append(user_code(sims[i], scenes))
        for i, st in enumerate(stages):
            best[i] = st if not best[i] else [min(a, b, key=lambda t: t.wall) for a, b in zip(best[i], st)]
    return [ColdStart(str(tree), *st) for tree, st in zip(trees, best)]


def checkout(revision: str, into: Path) -> Path:
    """The repository as of `revision` (git archive), extracted into `into`."""
    import io
    import tarfile

    proc = subprocess.run(["git", "archive", "--format=tar", revision], cwd=ROOT, capture_output=True)
    if proc.returncode != 0:
        raise ValueError(f"--against {revision}: git archive failed: {proc.stderr.decode().strip()}")
    with tarfile.open(fileobj=io.BytesIO(proc.stdout)) as tar:
        tar.extractall(into, filter="data")
    return into


def load_average() -> str:
    try:
        return " ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        return "unknown"


def table(results: list[tuple[str, ColdStart]]) -> str:
    """The figures as a text table, one column pair (wall, CPU) per checkout."""
    headers = ["stage", *(f"{label} {kind} s" for label, _ in results for kind in ("wall", "cpu"))]
    rows = [[words, *(f"{t:.1f}" for _, r in results for t in (getattr(r, key).wall, getattr(r, key).cpu))]
            for key, words in (("compile", "compile (empty cache)"), ("run_warm", "run, cache warm"),
                               ("first_run", "first run (empty cache)"), ("second_run", "second run"),
                               ("user_run", "run --sim (example copy)"), ("after_edit", "run --sim after an edit"),
                               ("user_code", "of which the copy's own code"))]
    return text(headers, rows, align=["left", *["right"] * (len(headers) - 1)])
