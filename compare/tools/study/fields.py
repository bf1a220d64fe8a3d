"""`--vary NAME=SPEC`: which scene field a study varies, over which values, and the varied scene.

NAME is a field of the scene file, dotted as in the TOML tables, with [i] for an element of a
list: `dt`, `contact.k`, `body.mass`, `initial.velocity[1]`, `body.parts[0].mass`.
SPEC is a list `1e3,1e4,1e5` (numbers, or words for a field that takes one:
`contact.damping_law=compression,linear`) or a range `START:STOP:COUNT:SPACING`, COUNT values
from START to STOP inclusive, SPACING `log` (geometric) or `lin` (evenly spaced):
`contact.k=1e3:1e6:7:log` is 1e3, 3.16e3, 1e4, ..., 1e6.

A varied scene is the scene file's table with the field set, validated by the scene loader
(custom_sim.parse_scene), so a value the loader refuses is refused with the loader's message.
"""
from __future__ import annotations

import copy
import dataclasses
import re
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from custom_sim import Scene, SceneError, parse_scene
from scene_types.law_file import without_untaken
from scene_types.laws import SEED_LAW

from scene_types import BadInput

_TOKEN = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)((?:\[\d+\])*)")
SPEC_HELP = ("expected NAME=SPEC, SPEC a list (1e3,1e4) or a range START:STOP:COUNT:log|lin "
             "(1e3:1e6:7:log)")
# Fields a study sets another way, or that are not a single value.
RESERVED = {"integrator": "give the integrators with --integrators",
            "name": "a study keeps the scene's name", "description": "not a physical parameter",
            "effects": "a list of words: study each effect set as its own scene file"}


@dataclass(frozen=True)
class Vary:
    """One varied field: name as given, its path (keys and list indices), the values in order."""

    name: str
    path: tuple
    values: tuple

    @property
    def numeric(self) -> bool:
        return all(isinstance(v, float) for v in self.values)


def parse_path(name: str) -> tuple:
    """'initial.velocity[1]' -> ('initial', 'velocity', 1)."""
    path: list = []
    for part in name.split("."):
        m = _TOKEN.fullmatch(part)
        if not m:
            raise BadInput(f"--vary {name}: '{part}' is not a field name (expected names like "
                           "contact.k, dt, initial.velocity[1])")
        path.append(m.group(1))
        path += [int(i) for i in re.findall(r"\[(\d+)\]", m.group(2))]
    if path[0] in RESERVED:
        raise BadInput(f"--vary {name}: cannot be varied ({RESERVED[path[0]]})")
    return tuple(path)


def _number(text: str):
    try:
        return float(text)
    except ValueError:
        return None


def parse_values(name: str, spec: str) -> tuple:
    """The values of SPEC (see the module docstring), in order, duplicates refused."""
    where = f"--vary {name}={spec}"
    if not spec:
        raise BadInput(f"{where}: no values ({SPEC_HELP})")
    if ":" in spec:
        parts = spec.split(":")
        if len(parts) != 4:
            raise BadInput(f"{where}: a range has four parts ({SPEC_HELP})")
        start, stop, count = _number(parts[0]), _number(parts[1]), _number(parts[2])
        spacing = parts[3]
        if start is None or stop is None:
            raise BadInput(f"{where}: START and STOP must be numbers ({SPEC_HELP})")
        if count is None or count != int(count) or count < 1:
            raise BadInput(f"{where}: COUNT must be a whole number >= 1, got '{parts[2]}'")
        if spacing not in ("log", "lin"):
            raise BadInput(f"{where}: SPACING must be log or lin, got '{spacing}'")
        if spacing == "log" and (start <= 0 or stop <= 0):
            raise BadInput(f"{where}: a log range needs START and STOP > 0")
        if not (np.isfinite(start) and np.isfinite(stop)):
            raise BadInput(f"{where}: START and STOP must be finite")
        n = int(count)
        grid = np.geomspace(start, stop, n) if spacing == "log" else np.linspace(start, stop, n)
        values = tuple(float(v) for v in grid)
    else:
        items = [s.strip() for s in spec.split(",")]
        if any(not s for s in items):
            raise BadInput(f"{where}: an empty item in the list ({SPEC_HELP})")
        numbers = [_number(s) for s in items]
        if all(x is not None for x in numbers):
            values = tuple(numbers)
        elif all(x is None for x in numbers):
            values = tuple(items)
        else:
            raise BadInput(f"{where}: mixes numbers and words (expected one kind)")
        if any(isinstance(v, float) and not np.isfinite(v) for v in values):
            raise BadInput(f"{where}: values must be finite")
    if len(set(values)) != len(values):
        raise BadInput(f"{where}: a value appears twice")
    return values


def parse_vary(text: str) -> Vary:
    if "=" not in text:
        raise BadInput(f"--vary {text}: {SPEC_HELP}")
    name, spec = (s.strip() for s in text.split("=", 1))
    return Vary(name, parse_path(name), parse_values(name, spec))


def _default(scene: Scene, path: tuple):
    """The loaded scene's value at path (None where it has none), as TOML would hold it."""
    node = scene
    for key in path:
        if isinstance(key, int):
            node = node[key] if isinstance(node, (list, tuple)) and key < len(node) else None
        elif dataclasses.is_dataclass(node):
            node = getattr(node, key, None)
        else:
            node = None
        if node is None:
            return None
    if dataclasses.is_dataclass(node):
        return {}
    if isinstance(node, tuple):
        return [({} if dataclasses.is_dataclass(e) else e) for e in node]
    return node


def set_field(data: dict, vary: Vary, value, scene: Scene) -> dict:
    """A copy of the scene table `data` with the field at vary.path set to value; tables and
    lists missing on the way are filled from the loaded scene's defaults."""
    out = copy.deepcopy(data)
    node = out
    for depth, key in enumerate(vary.path[:-1]):
        nxt = vary.path[depth + 1]
        if isinstance(key, int):
            child = node[key]
        else:
            child = node.get(key)
            if child is None:
                child = _default(scene, vary.path[:depth + 1])
                child = {} if child is None else child
                node[key] = child
        if isinstance(nxt, int) and not (isinstance(child, list) and nxt < len(child)):
            size = len(child) if isinstance(child, list) else 0
            raise BadInput(f"--vary {vary.name}: {'.'.join(map(str, vary.path[:depth + 1]))} "
                           f"has {size} element(s), no [{nxt}]")
        if not isinstance(nxt, int) and not isinstance(child, dict):
            raise BadInput(f"--vary {vary.name}: {key} is not a table")
        node = child
    leaf = vary.path[-1]
    current = node[leaf] if isinstance(leaf, int) else node.get(leaf, _default(scene, vary.path))
    if isinstance(current, (list, dict)):
        raise BadInput(f"--vary {vary.name}: is a {'list' if isinstance(current, list) else 'table'}, "
                       f"not one value (vary one element, e.g. {vary.name}[0])")
    node[leaf] = value
    return out


@dataclass(frozen=True)
class SceneSource:
    """A scene file read once: its table, its file name and the loaded (default-filled) scene;
    law_from: the law file laid over its [contact] (under_law), "" for the scene's own law."""

    data: dict
    file: str
    stem: str
    scene: Scene
    law_from: str = ""

    @classmethod
    def read(cls, path: Path) -> SceneSource:
        from custom_sim import load_scene

        scene = load_scene(path)   # raises SceneError for an unreadable or invalid file
        return cls(tomllib.loads(path.read_text(encoding="utf-8")), str(path), path.stem, scene)

    def under_law(self, law: str) -> SceneSource:
        """The scene under a law file (`--law FILE.toml`): its [contact] table laid over the
        file's, as `run --law` does; the fields a study varies are then set over that law."""
        from scene_types.law_file import load_law, with_law

        table = load_law(law)   # a SceneError naming the file and the field
        scene = with_law(self.scene, table, law)
        contact = {f.name: getattr(scene.contact, f.name) for f in dataclasses.fields(scene.contact)}
        contact = {k: list(v) if isinstance(v, tuple) else v for k, v in contact.items() if v is not None}
        data = {**self.data, "contact": without_untaken(contact)}
        return dataclasses.replace(self, data=data, scene=scene, law_from=law)

    def varied(self, varies: list[Vary], values: tuple) -> Scene:
        """The scene with each varied field set to its value, through the loader."""
        data = self.data
        for vary, value in zip(varies, values):
            data = set_field(data, vary, value, self.scene)
        if any(v.path[:1] == ("contact",) and v.path[-1] in SEED_LAW for v in varies) and "contact" in data:
            # another family: the file's parameters only the old one took fall away (not those varied)
            kept = {v.path[-1] for v in varies if v.path[:1] == ("contact",)}
            data = {**data, "contact": without_untaken(data["contact"], kept)}
        try:
            scene = parse_scene(data, file=self.file, default_name=self.stem)
            if self.law_from:
                scene = dataclasses.replace(scene, law_from=self.law_from, scene_contact=self.scene.scene_contact)
            return scene
        except SceneError as exc:
            given = ", ".join(f"{v.name}={x:g}" if isinstance(x, float) else f"{v.name}={x}"
                              for v, x in zip(varies, values))
            raise BadInput(f"--vary {given}: {exc.field or exc.file}: {exc.message}") from None
