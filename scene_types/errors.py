"""Bad input, named where it was found: a scene file's field, a CSV's row, an option's value."""
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
