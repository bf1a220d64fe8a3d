"""Keeps numba's on-disk cache honest across edits.

numba checks a cached function against its own file only; `integrate` inlines the force law
from forces.py, so an edit there would silently run stale machine code. A digest of all the
package's sources, kept beside the cache, clears the cache whenever any source changes.
"""
from __future__ import annotations

import hashlib
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent


def clear_if_sources_changed() -> None:
    cache = PACKAGE / "__pycache__"
    digest = hashlib.sha256(b"".join(p.read_bytes() for p in sorted(PACKAGE.glob("*.py")))).hexdigest()
    stamp = cache / "numba_sources.sha256"
    try:
        if stamp.read_text() == digest:
            return
    except OSError:
        pass
    try:
        cache.mkdir(exist_ok=True)
        for stale in [*cache.glob("*.nbi"), *cache.glob("*.nbc")]:
            stale.unlink(missing_ok=True)
        stamp.write_text(digest)
    except OSError:
        pass  # a read-only install: numba then compiles in memory
