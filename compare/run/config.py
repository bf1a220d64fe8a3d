"""What a run is asked to do beside its scenes and its simulator: one frozen RunConfig, built by
`run` from its flags and by compare.judge from its arguments, and passed down to every scenario's
process (an argument of the forked function: nothing travels through the environment)."""
from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

from ..store import folder


@dataclass(frozen=True)
class RunConfig:
    """out: the report's folder (written whole, or left as it was); jobs: scenarios at once;
    timeout: s a scenario may run (None: no limit); law: "identified", a law file's path, or None
    (each scene's own); cache: the folder of the cache of scene-only work (compare/store.py),
    None when off (--no-cache, or CONTACT_HARNESS_CACHE=off)."""

    out: Path
    jobs: int = field(default_factory=lambda: os.cpu_count() or 1)
    timeout: float | None = None
    law: str | None = None
    cache: Path | None = field(default_factory=folder)

    @classmethod
    def of(cls, out: Path, jobs: int, timeout: float | None = None, law: str | None = None,
           cache: bool = True) -> RunConfig:
        """The configuration from a run's choices; cache=False (--no-cache) is off."""
        return cls(Path(out), jobs, timeout, law or None, folder(cache))
