"""The house in layers: every import, at module level or inside a function, points down (or
sideways within a layer), and no two units import each other in a cycle.

Run as a script (`python tests/test_layers.py`) it prints the graph of units and their layers."""
from __future__ import annotations

import ast
import sys
from collections import defaultdict
from pathlib import Path


ROOT = Path(__file__).resolve().parents[1]

# Lowest first. A unit is a top-level package, or a package or module right under compare/.
LAYERS = [
    ("shared types", {"scene_types"}),
    ("the three sides", {"custom_sim", "mujoco_models", "compare.oracle"}),
    ("utilities and the executor", {"compare.scenarios", "compare.table", "compare.store", "compare.files",
                                    "compare.executor"}),
    ("the subject: the user's code", {"compare.usersim"}),
    ("checks", {"compare.energy", "compare.checks"}),
    ("identification", {"compare.identification"}),
    ("diagnosis", {"compare.diagnosis"}),
    ("report", {"compare.report"}),
    ("run", {"compare.run"}),
    ("the Python API", {"compare.api"}),
    ("tools", {"compare.tools"}),
    ("commands", {"compare.commands", "compare.cli", "compare.__main__", "compare.console",
                  "compare.pytest_plugin", "compare"}),
]
LAYER_OF = {unit: i for i, (_, units) in enumerate(LAYERS) for unit in units}
PACKAGES = ("scene_types", "custom_sim", "mujoco_models", "compare")


def unit_of(module: str) -> str | None:
    """The unit a dotted module name belongs to (None: outside the project)."""
    parts = module.split(".")
    if parts[0] not in PACKAGES:
        return None
    if parts[0] != "compare" or len(parts) == 1:
        return parts[0]
    return f"compare.{parts[1]}"


def module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imports(source: str, module: str, is_package: bool) -> list[tuple[str, int]]:
    """(imported module, line) for every import statement anywhere in the source, relative
    imports resolved against `module`."""
    package = module if is_package else module.rpartition(".")[0]
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            found += [(a.name, node.lineno) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            found.append((target, node.lineno))
            if node.module is None or node.level:   # `from . import x` may name submodules
                found += [(f"{target}.{a.name}", node.lineno) for a in node.names]
    return found


def edges() -> dict[tuple[str, str], list[str]]:
    """(importing unit, imported unit) -> the places ("file:line") that make the edge."""
    out: dict[tuple[str, str], list[str]] = defaultdict(list)
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            module = module_name(path)
            here = unit_of(module)
            for target, line in imports(path.read_text(), module, path.name == "__init__.py"):
                there = unit_of(target)
                if there is not None and there != here:
                    out[(here, there)].append(f"{path.relative_to(ROOT)}:{line}")
    return out


def upward(graph) -> list[str]:
    return [f"{a} (layer {LAYER_OF[a]}) imports {b} (layer {LAYER_OF[b]}): {', '.join(places)}"
            for (a, b), places in sorted(graph.items()) if LAYER_OF[b] > LAYER_OF[a]]


def cycles(graph) -> list[list[str]]:
    """Every cycle of units, each once (its smallest unit first)."""
    succ = defaultdict(set)
    for a, b in graph:
        succ[a].add(b)
    found = set()

    def walk(path):
        for nxt in succ[path[-1]]:
            if nxt == path[0]:
                i = path.index(min(path))
                found.add(tuple(path[i:] + path[:i]))
            elif nxt not in path and nxt > path[0]:
                walk(path + [nxt])
    for start in sorted(succ):
        walk([start])
    return [list(c) for c in sorted(found)]


def test_every_unit_has_a_layer():
    units = {unit for pair in edges() for unit in pair}
    units |= {unit_of(module_name(p)) for pkg in PACKAGES for p in (ROOT / pkg).rglob("*.py")}
    missing = sorted(u for u in units if u not in LAYER_OF)
    assert not missing, f"units with no layer in LAYERS: {missing}"


def test_no_import_points_up():
    found = upward(edges())
    assert not found, "imports that point up a layer:\n" + "\n".join(found)


def test_no_cycle_between_units():
    found = cycles(edges())
    assert not found, "units that import each other: " + "; ".join(" -> ".join(c + c[:1]) for c in found)


def test_the_layer_check_finds_an_upward_import_inside_a_function():
    """The check itself fails on a known mistake: a function-level import of the report from
    the subject, and a two-unit cycle."""
    source = "def f():\n    from ..report import pages\n"
    found = imports(source, "compare.usersim.base", False)
    assert ("compare.report", 2) in found
    graph = {("compare.usersim", "compare.report"): ["x:2"]}
    assert upward(graph) and cycles({**graph, ("compare.report", "compare.usersim"): ["y:1"]})
    assert not upward({("compare.report", "compare.usersim"): ["y:1"]})


if __name__ == "__main__":   # the graph, for a reader: each unit, its layer, what it imports
    graph = edges()
    for i, (name, units) in enumerate(LAYERS):
        for unit in sorted(units):
            below = sorted({b for (a, b) in graph if a == unit}, key=lambda u: (LAYER_OF.get(u, -1), u))
            print(f"{i:>2} {name:<30} {unit:<24} -> {', '.join(below) or '-'}")
    print(f"{len(upward(graph))} imports point up, {len(cycles(graph))} cycles")
    sys.exit(bool(upward(graph) or cycles(graph)))
