"""A run's configuration is passed, not ambient: `--no-cache` reaches the cache as an argument
(the environment is left as it was), a scenario's forked process takes the cache its RunConfig
names, and the Namespace of the command line stops at compare/commands/."""
from __future__ import annotations

import ast
import os
from pathlib import Path

from compare import store
from compare.cli import main
from compare.scenarios import load
from short_scene import short_scene

ROOT = Path(__file__).resolve().parents[3]
DURATION = 0.1   # s of point_drop: a few checks' worth of scene-only work, quickly


def files_in(folder: Path) -> list[Path]:
    return [p for p in folder.rglob("*") if p.is_file()] if folder.exists() else []


def test_no_cache_reaches_the_cache_without_touching_the_environment(tmp_path, monkeypatch, capsys):
    cache = tmp_path / "cache"
    monkeypatch.setenv(store.CACHE_ENV, str(cache))   # the user's own setting: the cache on, here
    scene = short_scene(tmp_path, "point_drop", DURATION)
    before = dict(os.environ)
    assert main(["run", str(scene), "--out", str(tmp_path / "out"), "--jobs", "1", "--no-cache"]) == 0
    assert dict(os.environ) == before, {k for k in before.keys() | os.environ.keys()
                                        if before.get(k) != os.environ.get(k)}
    assert files_in(cache) == [], "the cache was consulted under --no-cache"
    assert "cache: off (scene-only work computed)" in capsys.readouterr().err.splitlines()


def test_a_scenarios_process_takes_the_cache_its_config_names(tmp_path, monkeypatch):
    """The forked process of each scene consults the folder of its RunConfig, not the one the
    environment names."""
    from compare.api.judge import collect
    from compare.run.config import RunConfig

    named, passed = tmp_path / "named", tmp_path / "passed"
    monkeypatch.setenv(store.CACHE_ENV, str(named))
    scene = load(str(short_scene(tmp_path, "point_drop", DURATION)))
    judgement = collect([scene], None, RunConfig(tmp_path / "out", jobs=1, cache=passed))
    (judged,) = judgement.scenes
    assert judged.metrics["cache"]["misses"] > 0 and judged.metrics["cache"]["hits"] == 0, judged.metrics["cache"]
    assert files_in(passed) and not files_in(named)


def test_run_config_from_the_flags(tmp_path, monkeypatch):
    from compare.commands.run import run_config
    from compare.cli import build_parser

    monkeypatch.setenv(store.CACHE_ENV, str(tmp_path / "cache"))
    argv = ["run", "box_drop", "--out", str(tmp_path / "out"), "--jobs", "3", "--timeout", "9", "--law", "x.toml"]
    config = run_config(build_parser(argv).parse_args(argv))
    assert (config.out, config.jobs, config.timeout, config.law, config.cache) == (
        (tmp_path / "out").resolve(), 3, 9.0, "x.toml", tmp_path / "cache")
    assert run_config(build_parser(argv).parse_args([*argv, "--no-cache"])).cache is None


def test_judge_builds_its_config_from_its_arguments(tmp_path, monkeypatch):
    import compare
    from compare.api import judge

    monkeypatch.setenv(store.CACHE_ENV, str(tmp_path / "cache"))
    seen = []
    monkeypatch.setattr(judge, "collect", lambda scenes, simulator, config: seen.append(config))
    scene = short_scene(tmp_path, "point_drop", DURATION)
    compare.judge(None, str(scene), out=tmp_path / "out", jobs=2, timeout=5.0, law="identified", cache=False)
    compare.judge(None, str(scene), out=tmp_path / "out")
    assert [(c.out, c.jobs, c.timeout, c.law, c.cache) for c in seen] == [
        ((tmp_path / "out").resolve(), 2, 5.0, "identified", None),
        ((tmp_path / "out").resolve(), os.cpu_count() or 1, None, None, tmp_path / "cache")]


def _namespace_reads(path: Path) -> list[str]:
    """`args.NAME` and getattr(args, ...) in a module: the parsed command line read."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id == "args":
            found.append(f"{path.relative_to(ROOT)}:{node.lineno}: args.{node.attr}")
        if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "getattr"
                and node.args and isinstance(node.args[0], ast.Name) and node.args[0].id == "args"):
            found.append(f"{path.relative_to(ROOT)}:{node.lineno}: getattr(args, ...)")
    return found


def test_the_namespace_stops_at_the_commands():
    """Only compare/cli.py and compare/commands/ read argparse's Namespace; below them a
    command passes what it read (a RunConfig, the simulator's spec)."""
    below = [p for p in (ROOT / "compare").rglob("*.py")
             if p.name != "cli.py" and "commands" not in p.relative_to(ROOT / "compare").parts]
    assert below, "no module found under compare/"
    assert [hit for p in below for hit in _namespace_reads(p)] == []
