"""The cache of scene-only work (compare/store.py): a second run takes every scene-only result
from it and judges to the bit as the first; another law, or the cache off, computes again."""
from __future__ import annotations

import dataclasses
import json
import re

import numpy as np
import pytest

from compare import store
from compare.cli import main
from compare.scenarios import load
from compare.checks.result import metrics_json
from compare.run.scenario import run_scenario


@pytest.fixture
def cache_on(tmp_path, monkeypatch):
    """A cache of its own, in use for the test's work (and the user's setting, for `run`'s)."""
    monkeypatch.setenv(store.CACHE_ENV, str(tmp_path / "cache"))
    with store.using(store.Cache(tmp_path / "cache")) as cache:
        yield cache


def judged(scene) -> str:
    """The scenario's metrics without its timings (which a cached run carries from its first)."""
    data = metrics_json(run_scenario(scene))
    for key in [k for k in data if k.startswith("wall_time")]:
        data.pop(key)
    return json.dumps(data, default=lambda a: np.asarray(a).tolist(), sort_keys=True)


def test_a_second_run_takes_the_scene_only_work_from_the_cache(cache_on):
    scene = dataclasses.replace(load("point_drop"), duration=0.4)
    first = judged(scene)
    computed = cache_on.counts()
    assert computed["misses"] > 0 and computed["hits"] == 0, computed
    second = judged(scene)
    after = cache_on.counts()
    assert after["misses"] == computed["misses"], "the second run computed scene-only work again"
    assert after["hits"] >= computed["misses"]
    assert second == first


def test_another_law_is_another_key(cache_on):
    scene = dataclasses.replace(load("point_drop"), duration=0.2)
    judged(scene)
    before = cache_on.misses
    judged(dataclasses.replace(scene, contact=dataclasses.replace(scene.contact, mu=0.4)))
    assert cache_on.misses > before


def test_run_says_where_the_scene_only_work_came_from(cache_on, tmp_path, capsys):
    short = tmp_path / "short_drop.toml"
    text = (load("point_drop").source and open(load("point_drop").source).read())
    short.write_text(re.sub(r"(?m)^duration = .*$", "duration = 0.3", text))
    said = []
    for flags in ([], [], ["--no-cache"]):
        assert main(["run", str(short), "--out", str(tmp_path / "out"), *flags]) == 0
        said.append([line for line in capsys.readouterr().err.splitlines() if line.startswith("cache:")])
    assert said[0][0].startswith("cache: 0 of ") and "0 of 1 scenarios wholly" in said[0][0], said
    assert "1 of 1 scenarios wholly" in said[1][0], said
    assert said[2] == ["cache: off (scene-only work computed)"], said


def test_a_mutated_copy_of_custom_sim_is_another_code(tmp_path):
    """The key covers the sources where they are imported from: a copy of custom_sim with one
    mistake put in (the mutation test's) never reads the original's results."""
    import shutil
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    shutil.copytree(root / "custom_sim", tmp_path / "custom_sim", ignore=shutil.ignore_patterns("__pycache__"))
    forces = tmp_path / "custom_sim" / "forces.py"
    forces.write_text(forces.read_text() + "\n# a mistake put in\n")
    probe = "from compare.store import code_version; import custom_sim; print(code_version(), custom_sim.__file__)"

    def version(cwd):
        out = subprocess.run([sys.executable, "-c", probe], cwd=cwd, capture_output=True, text=True, check=True,
                             env={**__import__("os").environ, "PYTHONPATH": str(root)})
        return out.stdout.split()

    original, mutated = version(root), version(tmp_path)
    assert mutated[1].startswith(str(tmp_path)), mutated   # the copy is what runs
    assert original[0] != mutated[0]


def test_the_cache_is_trimmed_to_its_limit(cache_on, monkeypatch):
    scene = dataclasses.replace(load("point_drop"), duration=0.2)
    judged(scene)
    size = sum(p.stat().st_size for p in cache_on.where.rglob("*") if p.is_file())
    assert size > 100_000
    monkeypatch.setattr(store, "CACHE_BYTES", size // 4)
    store.trim(cache_on.where)
    assert sum(p.stat().st_size for p in cache_on.where.rglob("*") if p.is_file()) <= size // 4


def test_a_users_rerun_computes_only_what_depends_on_their_simulator(cache_on, tmp_path, monkeypatch):
    """A second run of a user's simulator takes every scene-only result from the cache: custom_sim's
    and MuJoCo's runs and the reference, their CSV files and energy balances; the files written
    are the first run's, byte for byte, the user's own CSV (computed again) included."""
    import functools
    from pathlib import Path

    from compare.run import scenario
    from compare.run.config import RunConfig
    from compare.run.outcome import run_one
    from compare.report import pages
    from compare.usersim import load_simulator

    root = Path(__file__).resolve().parents[2]
    scene = dataclasses.replace(load("point_drop"), duration=0.3)
    simulator = load_simulator(f"{root}/examples/seed_sim.py:step")
    config = RunConfig(tmp_path / "out", jobs=1, cache=cache_on.where)
    scene_only = {(pages, "run_csv"), (scenario, "custom_balance"), (scenario, "mujoco_balance"),
                  (scenario, "reference_balance")}
    calls = []
    for module, name in scene_only:
        original = getattr(module, name)

        @functools.wraps(original)   # the store keys a call by the function's module and name
        def call(*args, _original=original, **kwargs):
            calls.append(_original.__name__)
            return _original(*args, **kwargs)
        monkeypatch.setattr(module, name, call)
    files = []
    for run in ("first", "second"):
        calls.clear()
        (tmp_path / run).mkdir()
        outcome = run_one(scene, str(tmp_path / run), simulator, config)
        assert outcome.row is not None, outcome
        files.append({p.name: p.read_bytes() for p in (tmp_path / run / scene.name).glob("*.csv")})
        if run == "first":
            assert sorted(calls) == sorted(["run_csv", "run_csv", "custom_balance", "mujoco_balance",
                                            "reference_balance"]), calls
            assert outcome.row["cache"]["misses"] > 0, outcome.row["cache"]
    assert calls == [], f"the second run computed scene-only work again: {calls}"
    assert outcome.row["cache"]["misses"] == 0, "the second run computed scene-only work again"
    assert sorted(files[0]) == ["trajectory_custom.csv", "trajectory_mujoco.csv", "trajectory_user.csv"]
    assert files[0] == files[1]
