"""Finished results kept on disk: a run interrupted and started again skips them."""
from __future__ import annotations

import json
from pathlib import Path


class Store:
    """A folder of finished results, one `<key>.json` each, written atomically."""

    def __init__(self, folder: str | Path):
        self.folder = Path(folder)

    def path(self, key: str) -> Path:
        return self.folder / f"{key}.json"

    def load(self, key: str):
        try:
            return json.loads(self.path(key).read_text())
        except (OSError, ValueError):
            return None   # absent, or cut short by an interruption: computed again

    def save(self, key: str, result) -> None:
        from ..files import finite_json, write_text_atomically

        self.folder.mkdir(parents=True, exist_ok=True)
        write_text_atomically(self.path(key), finite_json(result))

    def keys(self) -> set[str]:
        return {p.stem for p in self.folder.glob("*.json")} if self.folder.is_dir() else set()
