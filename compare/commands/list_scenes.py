"""List the built-in scenarios: name, shape, effects, description (stress cases apart)."""
from __future__ import annotations

from ..scenarios import builtin_paths, load


def add_arguments(parser) -> None:
    pass


def main(args) -> int:
    groups = {g: [load(str(p)) for p in builtin_paths(g)] for g in ("builtin", "stress")}
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
