"""Keeps numba's disk cache of the passive callback in step with the sources it compiles from.

numba checks a cached function against the file it is defined in; the callback (passive.py)
also compiles in the force law (contact_law.py), so an edit there alone would load stale
machine code. A SHA-256 of those sources is stored beside the cache; when it differs, the
cache files of this package are removed before anything loads.
"""
from __future__ import annotations

import hashlib
from pathlib import Path

HERE = Path(__file__).resolve().parent
SOURCES = ("contact_law.py", "passive.py")
STAMP = "passive_sources.sha256"


def sources_digest() -> str:
    h = hashlib.sha256()
    for name in SOURCES:
        h.update((HERE / name).read_bytes())
    return h.hexdigest()


def clear_if_sources_changed() -> None:
    """Remove this package's numba cache files if the callback's sources changed."""
    cache = HERE / "__pycache__"
    digest = sources_digest()
    stamp = cache / STAMP
    if stamp.is_file() and stamp.read_text() == digest:
        return
    try:
        cache.mkdir(exist_ok=True)
        for pattern in ("*.nbi", "*.nbc"):
            for old in cache.glob(pattern):
                old.unlink(missing_ok=True)
        stamp.write_text(digest)
    except OSError:   # a read-only install: numba compiles in memory instead
        pass
