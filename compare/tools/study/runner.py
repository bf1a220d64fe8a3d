"""A study from start to finish: plan, references, batches on the executor, the rows in plan order.

    run_study(source, varies, integrators, out, scheduler=None, workers=None, twin=True, yours=None) -> Study

With `yours` (plan.Yours) each point also runs the user's code, shipped to the workers as
source text with every task (compare/usersim/bundle.py): a worker needs no copy of the user's
files.

Finished batches are kept in DIR/batches/ (one JSON file each, rows keyed by run) and the
references in DIR/references/; a study started again over the same folder runs only what is
missing.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ...executor import Executor, Failure, Store, Task, make_executor
from .fields import SceneSource, Vary
from .measure import failed_rows, measure_batch, reference_states
from .plan import BATCH_SECONDS, Point, Yours, _hash, batches, physics_scene, plan, sample_times


@dataclass
class Study:
    source: SceneSource
    varies: list[Vary]
    integrators: list[str]
    points: list[Point]
    rows: list[dict]        # plan order, one per run
    reused: int             # runs found in DIR/batches
    wall_time: float        # s, the whole study
    workers: int            # 0 when nothing had to run
    threads_per_task: int
    scheduler: str | None
    twin: bool
    retried: int = 0        # tasks submitted again after a failure (a worker died, an error)
    yours: Yours | None = None
    dashboard: str | None = None   # the local cluster's dashboard, when opened

    @property
    def names(self) -> list[str]:
        return [v.name for v in self.varies]

    @property
    def panels(self) -> list[tuple[str, str]]:
        """(simulator, integrator) of every map panel: custom_sim's integrators, then yours."""
        yours = self.yours.integrators if self.yours else ()
        return [("custom_sim", i) for i in self.integrators] + [("yours", i) for i in yours]


def load_done(store: Store) -> dict[str, dict]:
    """Rows already computed, by run key."""
    done = {}
    for key in sorted(store.keys()):
        rows = store.load(key)
        for row in rows or []:
            if row.get("status") != "failed":   # a failed run is tried again next time
                done[row["key"]] = row
    return done


def _batch_task(points: list[Point], refs: list, threads: int, twin: bool, bundle=None) -> Task:
    return Task(key=_hash(tuple(p.key for p in points)), args=(points, refs, threads, twin, bundle),
                runs=sum(len(p.runs) for p in points))


def _split(task: Task) -> list[Task]:
    """One task per run of the batch (run after the batch failed)."""
    points, refs, threads, twin, bundle = task.args
    return [_batch_task([replace(p, runs=(run,))], [ref], threads, twin, bundle)
            for p, ref in zip(points, refs) for run in p.runs]


def _failed(task: Task, failure: Failure) -> list[dict]:
    return failed_rows(task.args[0], failure.reason)


def run_study(source: SceneSource, varies: list[Vary], integrators: list[str], out: Path,
              scheduler: str | None = None, workers: int | None = None, twin: bool = True,
              progress: bool = True, engine: Executor | None = None,
              batch_seconds: float = BATCH_SECONDS, yours: Yours | None = None,
              dashboard: str | None = None) -> Study:
    """Run (or finish) the study whose kept results live in `out`; engine: the executor to use
    (default: a Dask one started for the study, on `scheduler` or a local cluster of `workers`,
    its dashboard at `dashboard` when given); yours: the user's code, run beside custom_sim."""
    start = time.perf_counter()
    points = plan(source, varies, integrators, yours)
    bundle = yours.bundle if yours else None
    store = Store(out / "batches")
    done = load_done(store)
    todo = [p for p in points if any(r.key not in done for r in p.runs)]
    todo = [replace(p, runs=tuple(r for r in p.runs if r.key not in done)) for p in todo]
    reused = sum(len(p.runs) for p in points) - sum(len(p.runs) for p in todo)
    n_workers, threads, retried, link = 0, 1, 0, None
    if todo:
        own = engine is None
        engine = engine or make_executor("dask", scheduler=scheduler, workers=workers, dashboard=dashboard)
        try:
            n_workers, threads = engine.workers, engine.threads_per_task
            link = getattr(engine, "dashboard_link", None)
            if link and progress:
                print(f"dashboard: {link}", flush=True)
            before = engine.retried
            refs = _references(engine, todo, out / "references", progress)
            tasks = [_batch_task(b, [refs[p.key] for p in b], threads, twin, bundle)
                     for b in batches(todo, twin, batch_seconds, n_workers)]
            results = engine.run(measure_batch, tasks, desc="study", store=store, split=_split,
                                 failed=_failed, progress=progress)
            retried = engine.retried - before
        finally:
            if own:
                engine.close()
        for rows in results.values():
            for row in rows:
                done[row["key"]] = row
    # a kept row may come from another study over the same folder (other fields varied, the
    # same scene): its values are this study's
    rows = [dict(done[r.key], values=list(r.values)) for p in points for r in p.runs]
    return Study(source, varies, integrators, points, rows, reused, time.perf_counter() - start,
                 n_workers, threads, scheduler, twin, retried, yours, link)


def _references(engine: Executor, points: list[Point], cache: Path, progress: bool) -> dict:
    """(states at the point's sample times, note) for every point, one solve per physics key at
    the union of its points' sample times."""
    groups: dict[str, list[Point]] = {}
    for p in points:
        groups.setdefault(p.physics, []).append(p)
    tasks, unions = [], {}
    for key, members in groups.items():
        unions[key] = np.unique(np.concatenate([sample_times(p.scene) for p in members]))
        tasks.append(Task(key=key, args=(physics_scene(members[0].scene), unions[key], str(cache))))
    solved = engine.run(reference_states, tasks, desc="references", progress=progress)
    out = {}
    for key, members in groups.items():
        states, note = solved[key]
        for p in members:
            if states is None:
                out[p.key] = (None, note)
            else:
                idx = np.searchsorted(unions[key], sample_times(p.scene))
                out[p.key] = (states[idx], "")
    return out
