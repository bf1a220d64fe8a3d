"""List the built-in scenarios: name, shape, effects, description (stress cases apart)."""
from __future__ import annotations

import sys

from custom_sim import SceneError

from ..scenarios import builtin_paths, load


def add_arguments(parser) -> None:
    pass


def main(args) -> int:
    try:
        groups = {g: [load(str(p)) for p in builtin_paths(g)] for g in ("builtin", "stress")}
    except SceneError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    titles = {"builtin": "Built-in scenarios (`python -m compare run` runs these)",
              "stress": "Stress scenarios (hard cases: run them by name)"}
    for group, scenes in groups.items():
        if not scenes:
            continue
        print(titles[group])
        width = max(len(s.name) for s in scenes)
        effects = max(len(",".join(s.effects)) for s in scenes)
        for s in scenes:
            print(f"  {s.name:<{width}}  {s.body.shape:<8}  {','.join(s.effects):<{effects}}  {s.description}")
        print()
    return 0
