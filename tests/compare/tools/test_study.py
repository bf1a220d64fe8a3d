"""`study`: the table equals single runs bit for bit, a killed worker loses no run, bad input exits 2.

One local Dask cluster (two worker processes of one thread) serves the whole module.
"""
from __future__ import annotations

import os
import signal
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from compare.cli import main
from scene_types import BadInput
from compare.executor import make_executor
from compare.tools.study import table
from compare.tools.study.fields import SceneSource, parse_values, parse_vary
from compare.tools.study.measure import twin_rows
from compare.tools.study.plan import (BATCHES_PER_WORKER, batches, estimated_cost, physics_scene, plan, sample_rows,
                                sample_times)
from compare.scenarios import resolve
from compare.tools.study.runner import run_study

# Under pytest-xdist the module stays on one worker: its tests share one local Dask cluster
# (as does test_workprecision's sweep, through the engine's cluster of the process).
pytestmark = pytest.mark.xdist_group("dask_cluster")

ROOT = Path(__file__).resolve().parents[3]

# A short tilted box drop: one corner impact, rocking, rest (box_drop's body and contact, 0.6 s).
SCENE = """
duration = 0.6
dt = 1e-4
[body]
shape = "box"
mass = 2.0
size = [0.2, 0.1]
[contact]
k = 1e4
c = 20.0
damping_law = "linear"
[initial]
position = [0.0, 0.3]
angle = 0.4
"""


@pytest.fixture(scope="module")
def engine():
    with make_executor("dask", workers=2) as eng:
        yield eng


@pytest.fixture(scope="module")
def source(tmp_path_factory) -> SceneSource:
    path = tmp_path_factory.mktemp("scene") / "short_drop.toml"
    path.write_text(SCENE)
    return SceneSource.read(path)


def test_ranges_and_lists():
    assert parse_values("contact.k", "1e3:1e6:4:log") == (1e3, 1e4, 1e5, 1e6)
    assert parse_values("dt", "1:2:3:lin") == (1.0, 1.5, 2.0)
    assert parse_values("contact.damping_law", "linear,compression") == ("linear", "compression")
    assert parse_vary("initial.velocity[1]=-1,-2").path == ("initial", "velocity", 1)


@pytest.mark.parametrize("vary, field", [
    ("contact.kk=1,2", "contact.kk"),                 # unknown field, named by the loader
    ("contact.k=-1,1e4", "contact.k"),                # refused value, named by the loader
    ("contact.k=1e3:1e4:x:log", "contact.k"),         # COUNT not a number
    ("dt=0:1e-3:3:log", "dt"),                        # log range through 0
    ("initial.velocity[5]=1,2", "initial.velocity"),  # no such element
    ("initial.velocity=1,2", "initial.velocity"),     # a list, not one value
    ("integrator=rk4", "integrator"),                 # given by --integrators
    ("dt=5,1e-3", "dt"),                              # dt above the duration
])
def test_bad_vary_exits_2_naming_the_field_and_writes_nothing(tmp_path, capsys, vary, field):
    out = tmp_path / "out"
    status = main(["study", "box_drop", "--vary", vary, "--out", str(out)])
    err = capsys.readouterr().err
    assert status == 2, err
    assert field in err and err.count("\n") == 1, err
    assert not out.exists()


def test_bad_value_has_the_loaders_message(source):
    with pytest.raises(BadInput, match=r"contact\.c: expected a number >= 0"):
        plan(source, [parse_vary("contact.c=-5,5")], ["rk4"])


def _float(cell: str) -> float | None:
    return float(cell) if cell else None


def test_table_equals_single_runs_bit_for_bit(engine, source, tmp_path):
    """Each row of study.csv against custom_sim.simulate and mujoco_models.simulate_mujoco of the
    same scene, one run at a time, errors against the reference at the run's own sample times."""
    from compare.oracle.reference import cached_reference
    from custom_sim import SimulationDiverged, simulate
    from mujoco_models import simulate_mujoco

    varies = [parse_vary("contact.k=1e4,1e5"), parse_vary("dt=1e-4,1e-3")]
    integrators = ["explicit_euler", "semi_implicit_euler", "rk4"]
    study = run_study(source, varies, integrators, tmp_path, engine=engine, progress=False)
    table.write_csv(tmp_path / "study.csv", study.names, study.rows)
    rows = table.read_csv(tmp_path / "study.csv")
    assert list(rows[0])[:9] == ["contact.k", "dt", "integrator", "stable", "position_error_max",
                                 "twin_position_error_max", "wall_time", "force_evals", "status"]
    runs = [r for p in plan(source, varies, integrators) for r in p.runs]
    assert len(rows) == len(runs) == 12
    statuses = set()
    twins, references = {}, {}   # one per point (k, dt): shared by its integrators
    for row, run in zip(rows, runs):
        assert (float(row["contact.k"]), float(row["dt"]), row["integrator"]) == (*run.values, run.integrator)
        scene = run.scene
        statuses.add(row["status"])
        try:
            traj = simulate(scene)
        except SimulationDiverged:
            assert row["status"] == "unstable" and "diverged" in row["note"], row
            continue
        assert int(row["force_evals"]) == traj.force_evals
        keep = sample_rows(scene)
        ours = traj.states()[keep]
        if run.values not in references:
            references[run.values] = cached_reference(physics_scene(scene), sample_times(scene), None).states
            twins[run.values] = simulate_mujoco(scene).states()
        ref, twin = references[run.values], twins[run.values]
        error = float(np.max(np.hypot(*(ours[:, :2] - ref[:, :2]).T)))
        assert _float(row["position_error_max"]) == error, (row, error)
        mine, theirs = twin_rows(scene, scene.dt, keep)
        diff = float(np.max(np.hypot(*(ours[mine, :2] - twin[theirs, :2]).T)))
        assert _float(row["twin_position_error_max"]) == diff, (row, diff)
    assert statuses >= {"ok", "unstable"}, statuses   # the grid crosses a stability limit
    # run again over the same folder: everything comes from the kept batches
    again = run_study(source, varies, integrators, tmp_path, engine=engine, progress=False)
    assert again.reused == 12 and again.workers == 0 and again.rows == study.rows
    # another study over the same folder that shares runs: the kept rows carry its own values
    fewer = run_study(source, [parse_vary("dt=1e-4")], ["rk4"], tmp_path, engine=engine, progress=False)
    assert fewer.reused == 1 and fewer.rows[0]["values"] == [1e-4]


def test_a_killed_worker_loses_no_run_and_duplicates_none(engine, source, tmp_path):
    varies = [parse_vary("contact.k=1e4:1e5:6:log"), parse_vary("dt=1e-4,2e-4")]
    integrators = ["semi_implicit_euler", "rk4"]
    killed = []

    def kill_a_busy_worker():
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and not killed:
            busy = [w for w, keys in engine.client.processing().items()
                    if any(str(k).startswith("study-") for k in keys)]
            if busy:
                pid = engine.client.run(os.getpid, workers=[busy[0]])[busy[0]]
                os.kill(pid, signal.SIGKILL)
                killed.append(pid)
                return
            time.sleep(0.02)

    killer = threading.Thread(target=kill_a_busy_worker)
    killer.start()
    # small batches (about 20 ms each): the study is still running when the worker dies
    study = run_study(source, varies, integrators, tmp_path, engine=engine, twin=False, progress=False,
                      batch_seconds=0.02)
    killer.join()
    assert killed, "no worker was busy with a study batch"
    assert study.retried >= 1, "the killed worker's batch was not submitted again"
    keys = [r["key"] for r in study.rows]
    expected = [r.key for p in plan(source, varies, integrators) for r in p.runs]
    assert keys == expected and len(set(keys)) == len(keys) == 24
    assert all(r["status"] != "failed" for r in study.rows), [r["note"] for r in study.rows]
    kept = [row["key"] for f in (tmp_path / "batches").glob("*.json")
            for row in __import__("json").loads(f.read_text())]
    assert sorted(kept) == sorted(keys)      # each run written once
    # the cluster is whole again for the next test (the nanny restarts the worker)
    engine.client.wait_for_workers(2, timeout=120)


def test_batches_give_every_worker_several_and_start_with_the_costliest():
    """A small study is cut so that each worker gets BATCHES_PER_WORKER batches or more (one
    point each at least), submitted costliest first so that the last to finish are short."""
    source = SceneSource.read(resolve("box_drop"))
    points = plan(source, [parse_vary("contact.k=3e3:3e4:4:log"), parse_vary("dt=2.5e-5:1e-4:6:log")],
                  ["semi_implicit_euler", "rk4"])
    for workers in (1, 2):
        cut = batches(points, twin=False, workers=workers)
        assert len(cut) >= min(len(points), BATCHES_PER_WORKER * workers)
        assert sorted(p.key for b in cut for p in b) == sorted(p.key for p in points), "every point once"
        costs = [sum(estimated_cost(p, False) for p in b) for b in cut]
        assert costs == sorted(costs, reverse=True)
