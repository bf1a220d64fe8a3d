"""Built-in scenes: the TOML files in scenarios/ (stress cases in scenarios/stress/)."""
from __future__ import annotations

from pathlib import Path

from scene_types import Scene, SceneError, load_scene

SCENARIO_DIR = Path(__file__).resolve().parent.parent / "scenarios"
GROUPS = {"builtin": SCENARIO_DIR, "stress": SCENARIO_DIR / "stress"}


def builtin_paths(group: str = "builtin") -> list[Path]:
    return sorted(GROUPS[group].glob("*.toml"))


def builtin_names(group: str = "builtin") -> list[str]:
    return [p.stem for p in builtin_paths(group)]


def resolve(spec: str) -> Path:
    """A built-in name (either group) or a path to a scene file."""
    for folder in GROUPS.values():
        candidate = folder / f"{spec}.toml"
        if candidate.is_file():
            return candidate
    path = Path(spec)
    if path.suffix == ".toml" or path.exists() or "/" in spec:
        return path
    known = ", ".join(builtin_names() + builtin_names("stress"))
    raise SceneError(spec, "", f"unknown scenario (expected a built-in name: {known}; or a path to a .toml file)")


def load(spec: str) -> Scene:
    return load_scene(resolve(spec))


def load_all(specs: list[str] | None) -> list[Scene]:
    """The scenes a command runs: the given names or paths, or every built-in; names distinct
    (they name the report folders)."""
    scenes = [load(spec) for spec in (specs or [str(p) for p in builtin_paths()])]
    names = [s.name for s in scenes]
    for scene in scenes:
        if names.count(scene.name) > 1:
            raise SceneError(scene.source, "name", f"'{scene.name}' is used by two scenes "
                                                   "(expected distinct names: set `name` in one file)")
    return scenes


def load_builtins(group: str = "builtin") -> list[Scene]:
    return [load_scene(p) for p in builtin_paths(group)]
