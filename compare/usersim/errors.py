"""Faults of a user's simulator, reported as bad input with their own traceback, shortened.

A user's function that raises is shown once: the frames of the user's own files only (not
the harness's, not the standard library's or installed packages'), then the one error line.
"""
from __future__ import annotations

import sysconfig
import traceback
from pathlib import Path

from scene_types import BadInput, Diverged

_HARNESS = [str(Path(__file__).resolve().parents[2] / pkg) for pkg in ("compare", "custom_sim", "mujoco_models")]
_LIBRARIES = sorted({str(Path(p).resolve()) for key in ("stdlib", "platstdlib", "purelib", "platlib")
                     if (p := sysconfig.get_paths().get(key))})


class UserCodeError(BadInput):
    """Bad input from a user's simulator: one line (str) and, where their code raised,
    `details`: the traceback of their own frames."""

    def __init__(self, message: str, details: str = ""):
        super().__init__(message)
        self.details = details


class UserFault(Exception):
    """A fault of the user's code in one scene (it raised, returned NaN, blew up): that scene's
    error row, the others still judged. `details`: the user's own traceback, if any."""

    def __init__(self, message, details: str = ""):
        if isinstance(message, UserCodeError):
            message, details = str(message), message.details
        super().__init__(message)
        self.details = details


class SceneSkipped(Exception):
    """A scene the user's code says it does not do: its module's SHAPES leaves the body's shape
    out, its step or whole run raised NotImplementedError, or a process answered `skip REASON`.
    The scene is listed as skipped with `reason`, never judged, and fails nothing."""

    def __init__(self, reason: str):
        super().__init__(reason)
        self.reason = reason


def not_implemented(exc: NotImplementedError, step: int | None = None) -> SceneSkipped:
    """The skip a NotImplementedError says: its message (or that it was raised), and the step
    where it came when that was not the first (the scene was then partly run)."""
    reason = str(exc).strip().splitlines()[0] if str(exc).strip() else "the code raised NotImplementedError"
    return SceneSkipped(reason if step is None or step <= 1 else f"{reason} (raised at step {step})")


class UserDiverged(UserFault, Diverged):
    """The user's run left the healthy range (custom_sim's blow-up test): the scene is unstable."""


def _own_frame(filename: str) -> bool:
    try:
        path = str(Path(filename).resolve())
    except (OSError, ValueError):
        return False
    if filename.startswith("<"):
        return False
    return not any(path.startswith(p) for p in _HARNESS + _LIBRARIES)


def user_traceback(exc: BaseException) -> str:
    """The traceback of exc cut to the user's frames (all frames if none is theirs)."""
    frames = traceback.extract_tb(exc.__traceback__)
    own = [f for f in frames if _own_frame(f.filename)]
    lines = ["Traceback (your code, most recent call last):\n"]
    lines += traceback.format_list(own or frames)
    lines += traceback.format_exception_only(type(exc), exc)
    return "".join(lines).rstrip()


def one_line(exc: BaseException) -> str:
    """`Type: first line of the message` (`Type` alone without a message)."""
    text = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {text[0]}" if text else type(exc).__name__


def raised(where: str, exc: BaseException) -> UserCodeError:
    """`where` raised exc: one line naming it and the exception, the shortened traceback (no
    "expected ...": the code raised, it returned nothing wrong)."""
    return UserCodeError(f"{where} raised {one_line(exc)}", user_traceback(exc))


