"""A built-in scene written to a file with a shorter duration (s), named <builtin>_short."""
from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def short_scene(tmp_path, builtin="point_drop", duration=0.4):
    text = (ROOT / "scenarios" / f"{builtin}.toml").read_text()
    text = "\n".join(f"duration = {duration}" if line.startswith("duration") else line for line in text.splitlines())
    path = tmp_path / f"{builtin}_short.toml"
    path.write_text(text)
    return path
