"""One cache of the work that depends only on the scene: MuJoCo's runs, custom_sim's runs and the
converged reference, their CSV files and energy balances, the theory's stable step, kept on disk
(joblib.Memory) and keyed by the function, its arguments (the scene, its law; a checks.Case
stands for its scene) and the version of the code (a digest of every source file of the four packages
and the numeric libraries' versions). A user's simulator is never cached: only what the scene
alone decides, so a rerun after editing one's own simulator recomputes only that.

    cached(fn)(*args)        fn(*args), from the cache when the same call ran before
    prepare()                open it and digest the code once, before worker processes fork
    trim()                   keep it within CACHE_BYTES, least recently used out first
    CACHE_ENV                the folder (default ~/.cache/contact-sim-harness); "off" disables it
"""
from __future__ import annotations

import functools
import hashlib
import importlib
import os
from pathlib import Path

CACHE_ENV = "CONTACT_HARNESS_CACHE"
# A run of the seven built-ins keeps about 260 MB (a trajectory of 40,000 steps is 3 MB); the
# least recently used entries go beyond this, so an edit of the harness does not pile up copies
CACHE_BYTES = 1_000_000_000
PACKAGES = ("scene_types", "custom_sim", "mujoco_models", "compare")
_counts = {"hits": 0, "misses": 0}


def folder() -> Path | None:
    """Where the cache lives, or None when CONTACT_HARNESS_CACHE=off."""
    value = os.environ.get(CACHE_ENV, "")
    if value.lower() in ("off", "0", "no", "none"):
        return None
    if value:
        return Path(value).expanduser()
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "contact-sim-harness"


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


@functools.lru_cache(maxsize=1)
def _memory():
    where = folder()
    if where is None:
        return None
    from joblib import Memory
    return Memory(location=str(where), verbose=0)


def _call(module: str, name: str, version: str, args: tuple, kwargs: dict):
    """The cached body: fn(*args, **kwargs); `version` is part of the key, not used here."""
    _counts["misses"] += 1
    return getattr(importlib.import_module(module), name)(*args, **kwargs)


@functools.lru_cache(maxsize=1)
def _cached_call():
    memory = _memory()
    return None if memory is None else memory.cache(_call)


def cached(fn):
    """fn with its results kept on disk across runs (a module-level function of scene-only
    work, whose arguments pickle: scenes, numbers, strings, arrays)."""
    @functools.wraps(fn)
    def call(*args, **kwargs):
        body = _cached_call()
        if body is None:
            return fn(*args, **kwargs)
        before = _counts["misses"]
        out = body(fn.__module__, fn.__qualname__, code_version(), args, kwargs)
        if _counts["misses"] == before:
            _counts["hits"] += 1
        return out
    return call


def prepare() -> None:
    """Open the cache and digest the code once, before worker processes fork: each then
    inherits both (joblib's import and the digest of every source: a fifth of a second each)."""
    if _cached_call() is not None:
        code_version()


def trim() -> None:
    """Keep the cache within CACHE_BYTES, the least recently used entries going first."""
    memory = _memory()
    if memory is not None:
        memory.reduce_size(bytes_limit=CACHE_BYTES)


def counts() -> dict:
    """Calls answered from the cache and calls computed, in this process so far."""
    return dict(_counts)
