"""numba's on-disk cache of the simulator: kept honest across edits, and filled once, up front.

numba checks a cached function against its own file only; `integrate` inlines the force law
from forces.py, so an edit there would silently run stale machine code. A digest of all the
package's sources, kept beside the cache, clears the cache whenever any source changes.

The first run on a machine (or after an edit) compiles the simulator: a few seconds on one
core. warm_up() does that once, in the calling process, before worker processes start, so
that they inherit the compiled code (fork) or load it from the cache instead of each
compiling it again at the same time; warm_up_in_parallel() splits it over two processes.
"""
from __future__ import annotations

import functools
import hashlib
import sys
import time
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent
COMPILING_MESSAGE = "compiling the simulator (first run only) ..."


def cache_folder() -> Path:
    """Where numba keeps this package's cache: custom_sim/__pycache__, or a folder under
    NUMBA_CACHE_DIR when that is set."""
    try:
        from .forces import tanh
        return Path(tanh._cache._cache_path)  # type: ignore[attr-defined]  # numba types no _cache
    except Exception:  # another numba layout: its default, in-tree
        return PACKAGE / "__pycache__"


@functools.cache
def fresh_cache() -> None:
    """Clear numba's cache of this package when any of its sources changed since the cache was
    written: once per process, before the first compiled call (model.build_model, which every
    run starts from, calls it; importing the package writes nothing)."""
    clear_stale(cache_folder(), sorted(PACKAGE.glob("*.py")), "numba_sources.sha256", "*")


def clear_stale(cache: Path, sources: list[Path], stamp_name: str, stem: str) -> None:
    """Remove the numba cache files `stem`.nbi/.nbc in `cache` unless the digest of `sources`
    stored there as `stamp_name` still matches (a read-only install: numba then compiles in
    memory)."""
    digest = hashlib.sha256(b"".join(p.read_bytes() for p in sources)).hexdigest()
    stamp = cache / stamp_name
    try:
        if stamp.read_text() == digest:
            return
    except OSError:
        pass
    try:
        cache.mkdir(parents=True, exist_ok=True)
        for stale in [*cache.glob(f"{stem}.nbi"), *cache.glob(f"{stem}.nbc")]:
            stale.unlink(missing_ok=True)
        stamp.write_text(digest)
    except OSError:
        pass


def is_cached(dispatcher) -> bool:
    """True when numba's cache holds an index for this compiled function (nothing to compile
    for the signatures it lists)."""
    try:
        return Path(dispatcher._cache._cache_file._index_path).is_file()
    except AttributeError:
        return False


def needs_compiling() -> bool:
    """True when a run would compile: a compiled loop or the blow-up check is not in the cache."""
    from .integrators import first_unhealthy, integrate_explicit, integrate_implicit
    return not all(is_cached(f) for f in (integrate_explicit, integrate_implicit, first_unhealthy))


def warm_up(stream=None, part=None) -> float:
    """Compile (or load from the cache) everything a run executes: the stepping loops of the
    integrators named in `part` (default: all four), through a 2-step run of a small scene with
    each, and the blow-up check of a recorded trajectory (unless `part` is implicit only).
    Prints COMPILING_MESSAGE to `stream` (stderr) when it has to compile. Returns the seconds
    it took."""
    import dataclasses

    from .integrators import INTEGRATORS, first_unhealthy
    from scene_types.schema import parse_scene
    from .runner import blowup_guard, simulate

    start = time.perf_counter()
    fresh_cache()
    if needs_compiling():
        print(COMPILING_MESSAGE, file=stream or sys.stderr, flush=True)
    scene = parse_scene({"name": "warm_up", "duration": 2e-4, "dt": 1e-4,
                         "body": {"shape": "box", "mass": 1.0, "size": [0.2, 0.1]},
                         "initial": {"position": [0.0, 0.04]}}, file="<warm_up>")
    part = part or list(INTEGRATORS)
    for integrator in part:
        traj = simulate(dataclasses.replace(scene, integrator=integrator))
    if not all(INTEGRATORS[name].implicit for name in part):   # the implicit half leaves it to the other
        states = traj.states()
        first_unhealthy(states, blowup_guard(scene, _props(scene), states[0], applied_input=False))
    return time.perf_counter() - start


def warm_up_in_parallel(stream=None, meanwhile=None) -> float:
    """warm_up(), with the implicit integrators' loop compiled in a forked process while this
    one compiles the explicit ones' (on a first run the two are about as long; no compiled
    function of one loop calls the other), then meanwhile(), if given. Returns the seconds it
    took."""
    import io
    import multiprocessing

    from .integrators import INTEGRATORS

    start = time.perf_counter()
    fresh_cache()
    other = None
    if needs_compiling():
        print(COMPILING_MESSAGE, file=stream or sys.stderr, flush=True)
        implicit = [name for name, method in INTEGRATORS.items() if method.implicit]
        other = multiprocessing.get_context("fork").Process(target=_warm_up_child, args=(implicit,), daemon=True)
        other.start()
        warm_up(io.StringIO(), [name for name in INTEGRATORS if name not in implicit])
    if meanwhile is not None:
        meanwhile()
    if other is not None:
        other.join()
    warm_up(stream)   # loads what is cached (compiles what the other process did not leave there)
    return time.perf_counter() - start


def _warm_up_child(names) -> None:
    """The forked half of the warm-up: Ctrl-C is the parent's to answer (a daemon, it ends with it)."""
    import io
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    warm_up(io.StringIO(), names)


def _props(scene):
    from .bodies import mass_properties
    return mass_properties(scene.body)
