"""One cache of the work that depends only on the scene: MuJoCo's runs, custom_sim's runs and the
converged reference, their CSV files and energy balances, the theory's stable step, kept on disk
(joblib.Memory) and keyed by the function, its arguments (the scene, its law; a checks.Case
stands for its scene) and the version of the code (a digest of every source file of the four packages
and the numeric libraries' versions). A user's simulator is never cached: only what the scene
alone decides, so a rerun after editing one's own simulator recomputes only that.

    folder(enabled)          where it lives: None when off (run --no-cache, or CONTACT_HARNESS_CACHE=off)
    Cache(where)             one run's use of it, with the calls it answered (hits) and computed (misses)
    using(cache)             the cache the enclosed work consults (run's scenario processes)
    cached(fn)(*args)        fn(*args), from the cache in use when the same call ran before
    prepare(where)           open it and digest the code once, before worker processes fork
    trim(where)              keep it within CACHE_BYTES, least recently used out first
    CACHE_ENV                the user's own setting: the folder (default ~/.cache/contact-sim-harness),
                             or "off"; read, never written (--no-cache is passed as an argument)
"""
from __future__ import annotations

import contextlib
import functools
import hashlib
import importlib
import os
from contextvars import ContextVar
from dataclasses import dataclass
from pathlib import Path

CACHE_ENV = "CONTACT_HARNESS_CACHE"
# A run of the seven built-ins keeps about 260 MB (a trajectory of 40,000 steps is 3 MB); the
# least recently used entries go beyond this, so an edit of the harness does not pile up copies
CACHE_BYTES = 1_000_000_000
PACKAGES = ("scene_types", "custom_sim", "mujoco_models", "compare")


def folder(enabled: bool = True) -> Path | None:
    """Where the cache lives: None when enabled is False (run --no-cache) or the user's
    CONTACT_HARNESS_CACHE says off; else CONTACT_HARNESS_CACHE, or ~/.cache/contact-sim-harness."""
    value = os.environ.get(CACHE_ENV, "")
    if not enabled or value.lower() in ("off", "0", "no", "none"):
        return None
    if value:
        return Path(value).expanduser()
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "contact-sim-harness"


@dataclass(eq=False)
class Cache:
    """One run's use of the cache: its folder (None: off, everything is computed), and the calls
    it answered from the folder (hits) and computed (misses), in this process."""

    where: Path | None
    hits: int = 0
    misses: int = 0

    def counts(self) -> dict:
        return {"hits": self.hits, "misses": self.misses}


# The cache the work in progress consults: set by `using` (a scenario's process sets its run's),
# else one made from the environment for each call outside a run (a test, `validate`)
_in_use: ContextVar[Cache | None] = ContextVar("compare_store_cache", default=None)


@contextlib.contextmanager
def using(cache: Cache):
    """The enclosed work consults `cache` (and counts into it); the one before is back after."""
    token = _in_use.set(cache)
    try:
        yield cache
    finally:
        _in_use.reset(token)


def in_use() -> Cache:
    """The cache `using` set, else the one the environment names (counted nowhere else)."""
    return _in_use.get() or Cache(folder())


@functools.lru_cache(maxsize=1)
def code_version() -> str:
    """A digest of the sources of the four packages, read where they are imported from, and the
    versions of the libraries that compute (an edit anywhere in the harness, a copy of custom_sim
    with a mistake put in, or a new MuJoCo starts a new cache)."""
    import mujoco
    import numba
    import numpy
    import scipy

    digest = hashlib.sha256(repr((mujoco.__version__, numpy.__version__, scipy.__version__,
                                  numba.__version__)).encode())
    for package in PACKAGES:   # where each package is imported from: a mutated copy is another code
        for base in importlib.import_module(package).__path__:
            for path in sorted(Path(base).rglob("*.py")):
                digest.update(f"{package}/{path.relative_to(base)}".encode())
                digest.update(path.read_bytes())
    return digest.hexdigest()[:16]


@functools.lru_cache(maxsize=4)
def _memory(where: Path):
    from joblib import Memory
    return Memory(location=str(where), verbose=0)


def _call(module: str, name: str, version: str, args: tuple, kwargs: dict, tally: Cache):
    """The cached body: fn(*args, **kwargs), run on a miss only, counted in `tally`; `version`
    is part of the key, not used here; `tally` is not part of it (joblib ignores it)."""
    tally.misses += 1
    return getattr(importlib.import_module(module), name)(*args, **kwargs)


@functools.lru_cache(maxsize=4)
def _cached_call(where: Path):
    return _memory(where).cache(_call, ignore=["tally"])


def cached(fn):
    """fn with its results kept on disk across runs, in the cache in use (`using`): a
    module-level function of scene-only work, whose arguments pickle (scenes, numbers, strings,
    arrays)."""
    @functools.wraps(fn)
    def call(*args, **kwargs):
        cache = in_use()
        if cache.where is None:
            return fn(*args, **kwargs)
        before = cache.misses
        out = _cached_call(cache.where)(fn.__module__, fn.__qualname__, code_version(), args, kwargs, cache)
        if cache.misses == before:
            cache.hits += 1
        return out
    return call


def prepare(where: Path | None) -> None:
    """Open the cache in `where` (None: off, nothing to do) and digest the code once, before
    worker processes fork: each then inherits both (joblib's import and the digest of every
    source: a fifth of a second each)."""
    if where is not None:
        _cached_call(where)
        code_version()


def trim(where: Path | None) -> None:
    """Keep the cache in `where` within CACHE_BYTES, the least recently used entries going first."""
    if where is not None:
        _memory(where).reduce_size(bytes_limit=CACHE_BYTES)
