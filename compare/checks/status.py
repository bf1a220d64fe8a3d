"""A scenario's status, as metrics.json and `run`'s lines name it; of_rows, the status of a
scenario's check rows; and exit_status, the one exit status of `run`, `validate` and the API."""
from __future__ import annotations

from enum import Enum


class Status(str, Enum):
    """What became of one scene; the value is the word metrics.json and the verdict line use."""

    PASSED = "pass"              # every judged check within its tolerance
    FAILED = "FAIL"              # a judged check outside it
    NOT_JUDGED = "not judged"    # it ran, but no check could be judged
    ERROR = "error"              # the code under test (or the harness) failed on it: no verdict
    UNSTABLE = "unstable"        # the run diverged or chattered: no verdict
    TIMEOUT = "timeout"          # stopped after --timeout s
    SKIPPED = "skipped"          # the code does not do this scene (SHAPES, NotImplementedError)

    @classmethod
    def of(cls, word: str) -> Status:
        """The status a row names; a word this version does not know is an error (never a pass)."""
        try:
            return cls(word)
        except ValueError:
            return cls.ERROR

    def __str__(self) -> str:
        return self.value


def of_rows(rows) -> Status:
    """The status of a scenario that ran, from its check rows (row.py CheckRow): FAIL when a
    judged check failed, pass when every judged one passed, not judged when none was judged."""
    judged = [r for r in rows if r.passed is not None]
    if not judged:
        return Status.NOT_JUDGED
    return Status.PASSED if all(r.passed for r in judged) else Status.FAILED


def exit_status(statuses) -> int:
    """The exit status of a judgement: 0 when every scene not skipped passed and at least one was
    not skipped; 1 otherwise (a failed check, no verdict, nothing judged, everything skipped)."""
    judged = [s for s in statuses if s is not Status.SKIPPED]
    return 0 if judged and all(s is Status.PASSED for s in judged) else 1
