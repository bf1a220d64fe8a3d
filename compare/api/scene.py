"""One scene's judgement: its status, its check rows, the diagnosis and the lines `run` prints."""
from __future__ import annotations

from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any
from collections.abc import Mapping

from .check import Check
from .diagnosis import Diagnosis
from .status import Status


@dataclass(frozen=True)
class SceneJudgement:
    """What became of one scene. A scene with no verdict (error, unstable, timeout, skipped) has
    no checks and says why in `reason`."""

    name: str
    status: Status
    checks: tuple[Check, ...] = ()
    diagnosis: Diagnosis | None = None
    lines: tuple[str, ...] = ()           # what `run` prints for it on stdout
    reason: str = ""                      # no verdict: why, in one line
    warnings: tuple[str, ...] = ()        # what `run` prints on stderr (`warning: ...`)
    metrics: Mapping[str, Any] | None = field(default=None, compare=False, repr=False)   # its metrics.json

    @property
    def passed(self) -> bool:
        return self.status is Status.PASSED

    @property
    def failed_checks(self) -> tuple[Check, ...]:
        return tuple(c for c in self.checks if c.passed is False)

    @classmethod
    def from_row(cls, row: dict) -> SceneJudgement:
        """A scene that reached a verdict, from its metrics.json."""
        from ..checks.summary import read_summary
        from ..run.lines import law_line, verdict_line

        s = read_summary(row)
        diagnosis = Diagnosis.from_json(s.diagnosis)
        lines = (verdict_line(s), *(law_line(text) for text in (diagnosis.laws if diagnosis else ())))
        warnings = tuple(w if w.startswith(f"{s.name}:") else f"{s.name}: {w}" for w in s.warnings)
        return cls(s.name, s.status, tuple(Check.of(c) for c in s.checks), diagnosis, lines, "",
                   warnings, metrics=MappingProxyType(row))

    @classmethod
    def no_verdict(cls, name: str, status: str, why: str) -> SceneJudgement:
        """A scene whose process reached no verdict: (status, why) as `run` collects them."""
        from ..run.lines import no_verdict_line

        return cls(name, Status.of(status), lines=(no_verdict_line(name, status, why),), reason=why)
