"""compare.judge: every check of `run` on a simulator, as a Judgement, writing nothing unless
asked to; and the pipeline `run` itself goes through (collect)."""
from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

from .judgement import Judgement


def scene_specs(scenes) -> list[str] | None:
    """The scenes argument as `run`'s SCENE words: None (every built-in), one name or path, or
    several (a list or tuple of names or paths)."""
    if scenes is None:
        return None
    if isinstance(scenes, (str, os.PathLike)):
        return [os.fspath(scenes)]
    specs = [os.fspath(s) if isinstance(s, os.PathLike) else s for s in scenes]
    bad = [s for s in specs if not isinstance(s, str)]
    if bad or not specs:
        from scene_types import BadInput
        raise BadInput(f"scenes = {scenes!r}: expected a built-in scene's name or a path to a .toml, or a list of "
                       "them (None: every built-in)")
    return specs


def collect(scenes, simulator, config) -> Judgement:
    """`run`'s pipeline once its input is read: the scenes under config.law, every scene judged in
    a process of its own (config: compare/run/config.py), the report written whole into
    config.out. Raises bad input (nothing written) and Interrupted (Ctrl-C) as `run` reports them."""
    from ..run.report import write_report
    from ..run.warm_up import compile_everything
    from ..store import Cache, trim, using

    with using(Cache(config.cache)):   # this process's scene-only work too (identify's, under --law)
        if config.law:
            from ..run.law import under_law
            scenes = under_law(scenes, config.law, simulator)
        compile_everything(config.cache)
        written = write_report(scenes, simulator, config)
    if written.failed or any(r.get("cache", {}).get("misses") for r in written.rows):   # the cache may have grown
        trim(config.cache)
    return Judgement.of_report(written.rows, written.failed, written.details, written.index)


def judge(sim=None, scenes=None, *, law: str | None = None, whole: bool = False, out=None,
          jobs: int | None = None, timeout: float | None = None, cache: bool = True) -> Judgement:
    """Judge a simulator as `python -m compare run --sim SIM` does, and return the Judgement.

    sim: "MODULE:FUNCTION", a function (step(state, scene, dt) -> state; with whole=True
    simulate(scene) -> array (steps + 1, 6)), compare.Process("COMMAND"), or None (custom_sim).
    scenes: a built-in name or a .toml path, or a list of them (None: every built-in).
    law: "identified" or a law file's path (run --law). out: a folder for the report `run --out`
    writes (None: nothing is written; the work goes into a temporary folder, removed after).
    jobs: scenes at once (default every core); timeout: s per scene; cache=False recomputes the
    scene-only work (run --no-cache; CONTACT_HARNESS_CACHE=off does too). Bad input raises
    compare.BadInput (or SceneError) naming what was wrong, before anything is written."""
    from ..files import output_folder
    from ..run.config import RunConfig
    from ..scenarios import load_all
    from ..usersim import preflight
    from .subject import simulator_of

    if timeout is not None and not timeout > 0:
        from scene_types import BadInput
        raise BadInput(f"timeout = {timeout!r}: expected a positive number of seconds")
    folder = None if out is None else output_folder(os.fspath(out)).resolve()
    scene_list = load_all(scene_specs(scenes))
    simulator = simulator_of(sim, whole)
    if simulator is not None:
        preflight(simulator, scene_list)
    jobs = jobs or os.cpu_count() or 1
    if folder is not None:
        return collect(scene_list, simulator, RunConfig.of(folder, jobs, timeout, law, cache))
    work = Path(tempfile.mkdtemp(prefix="contact-judge-"))
    try:
        judgement = collect(scene_list, simulator, RunConfig.of(work / "report", jobs, timeout, law, cache))
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return Judgement(judgement.scenes, judgement.details, None)
