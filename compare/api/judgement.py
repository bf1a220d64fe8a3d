"""A whole judgement: every scene's, whether the code under test passed, the lines `run` prints
and its exit status. `run` prints from this object, so the command and the API cannot differ."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from .scene import SceneJudgement
from .status import Status, exit_status


@dataclass(frozen=True)
class Judgement:
    """The judgement of a simulator on some scenes (compare.judge), in the order `run` prints."""

    scenes: tuple[SceneJudgement, ...]
    details: tuple[tuple[str, str], ...] = ()   # (scene, the user's own traceback) where their code raised
    report: Path | None = None        # index.md of the report written (judge(out=...)), else None

    @property
    def passed(self) -> bool:
        """Every scene not skipped passed, and at least one was not skipped."""
        return self.exit_status == 0

    @property
    def exit_status(self) -> int:
        """What `run` exits with: 0 passed, 1 otherwise."""
        return exit_status([s.status for s in self.scenes])

    @property
    def lines(self) -> tuple[str, ...]:
        """The verdict lines `run` prints on stdout (without its `report:` line)."""
        return tuple(line for s in self.scenes for line in s.lines)

    @property
    def diagnosis(self) -> str:
        """Each scene's diagnosis that is not a pass, `NAME  diagnosis: VERDICT` (law sentences
        below), one a line; "" when every scene passed or none has one."""
        from ..run.lines import law_line

        out = []
        for s in self.scenes:
            if s.diagnosis is not None and not s.passed:
                out.append(f"{s.name:<20} diagnosis: {s.diagnosis.verdict}")
                out.extend(law_line(law) for law in s.diagnosis.laws)
        return "\n".join(out)

    def __getitem__(self, name: str) -> SceneJudgement:
        """The judgement of the scene named `name`."""
        for s in self.scenes:
            if s.name == name:
                return s
        raise KeyError(f"{name}: no such scene in this judgement (it has {', '.join(self.names) or 'none'})")

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.scenes)

    @property
    def statuses(self) -> dict[str, Status]:
        return {s.name: s.status for s in self.scenes}

    @classmethod
    def of_report(cls, rows: list[dict], failed: list[tuple], details=(), report: Path | None = None) -> Judgement:
        """From what `run` collected (compare/run/report.py Written): the rows of the scenes that
        reached a verdict (metrics.json), then (name, status, why) of those that did not."""
        scenes = [SceneJudgement.from_row(r) for r in rows]
        scenes += [SceneJudgement.no_verdict(name, status, why) for name, status, why in failed]
        return cls(tuple(scenes), tuple(details), report)
