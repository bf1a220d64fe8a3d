"""The three sides are independent: custom_sim, the MuJoCo twins (mujoco_models) and the
harness's oracle (compare/oracle) each import the shared types (scene_types) and none of each
other, so no check can share the quantity it checks. No exceptions."""
import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SIDES = {                      # folder: the top-level packages it must never import
    "custom_sim": {"mujoco_models", "compare"},
    "mujoco_models": {"custom_sim", "compare"},
    "compare/oracle": {"custom_sim", "mujoco_models"},
}
FILES = [(side, path) for side in SIDES for path in sorted((ROOT / side).glob("*.py"))]


def imported_packages(path: Path) -> set[str]:
    """The top-level packages a file imports, at any depth of the file (relative imports within
    compare/ count as compare, which the oracle may use only through compare.oracle)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found |= {a.name.split(".")[0] for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            found.add(node.module.split(".")[0])
        elif isinstance(node, ast.ImportFrom) and node.level >= 2:   # from ..x: outside the package
            found.add("compare" if path.parent.parent.name == "compare" else path.parent.parent.name)
    return found


@pytest.mark.parametrize("side, path", FILES, ids=[f"{s}/{p.name}" for s, p in FILES])
def test_each_side_imports_only_the_shared_types(side, path):
    extra = imported_packages(path) & SIDES[side]
    assert not extra, f"{side}/{path.name} imports {sorted(extra)}"


def test_the_shared_types_import_no_side():
    for path in sorted((ROOT / "scene_types").glob("*.py")):
        extra = imported_packages(path) & {"custom_sim", "mujoco_models", "compare"}
        assert not extra, f"scene_types/{path.name} imports {sorted(extra)}"


# the command modules of the tools: the only files outside compare/tools that may import them
# (with compare/commands/tools/, the developer tools' commands)
TOOL_COMMANDS = {"bench.py", "calibrate.py", "play.py", "solref.py", "study.py", "sweep.py"}


def imported_modules(path: Path) -> set[str]:
    """The absolute names of the modules a file imports (relative imports resolved)."""
    package = ".".join(path.relative_to(ROOT).parent.parts)
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            base = package.split(".")[: len(package.split(".")) - node.level + 1] if node.level else []
            found.add(".".join(base + ([node.module] if node.module else [])))
    return found


def test_the_checks_and_the_run_never_import_the_tools():
    """compare/tools (sweep, bench, study, calibration, mutation, game) is off the run path."""
    for path in sorted((ROOT / "compare").rglob("*.py")):
        inside = path.relative_to(ROOT / "compare").parts
        if inside[0] == "tools" or inside[:2] == ("commands", "tools") or (
                inside[0] == "commands" and inside[-1] in TOOL_COMMANDS):
            continue
        tools = {m for m in imported_modules(path) if m == "compare.tools" or m.startswith("compare.tools.")}
        assert not tools, f"{path.relative_to(ROOT)} imports {sorted(tools)}"
