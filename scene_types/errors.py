"""Bad input, named where it was found: a scene file's field, a CSV's row, an option's value; and
Diverged, the one base of every run that could not go on."""
from __future__ import annotations

from pathlib import Path


class SceneError(ValueError):
    """Bad scene input: `file: field: message`."""

    def __init__(self, file: str, field: str, message: str):
        self.file, self.field, self.message = file, field, message
        where = f"{file}: {field}: " if field else f"{file}: "
        super().__init__(where + message)


class CsvError(ValueError):
    """A trajectory CSV that cannot be read: `file: where: what was expected`."""

    def __init__(self, path: str | Path, where: str, message: str):
        self.path, self.where = str(path), where
        super().__init__(f"{path}: {where}: {message}")


class BadInput(ValueError):
    """Bad input that is not a scene file's (an option's value, a user's module): `what: message`."""


class Diverged(RuntimeError):
    """A run that left the healthy range, or a solver that could not follow the motion: the base
    of custom_sim's SimulationDiverged, mujoco_models' MujocoDiverged, the contact check's
    NativeDiverged, a user's UserDiverged and the reference's ReferenceFailed, so that one
    `except Diverged` catches each of them (each keeps its own name and fields)."""
