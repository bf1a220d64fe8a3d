"""mujoco_models takes nothing derived from custom_sim: it may read the scene (scene_types.schema)
and return the shared Trajectory type (scene_types.trajectory), nothing else. The one module
that runs custom_sim is the comparison table, which no twin imports."""
import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "mujoco_models"
ALLOWED = {"scene_types.schema", "scene_types.trajectory"}
COMPARISON_TOOLS = {"mapping_table.py"}   # prints custom_sim against the twins; imported by no twin
MODULES = sorted(p for p in PACKAGE.glob("*.py"))


def custom_sim_imports(path: Path) -> set[str]:
    """Every custom_sim module or name the file imports (at any depth of the file)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found |= {a.name for a in node.names if a.name.split(".")[0] == "custom_sim"}
        elif isinstance(node, ast.ImportFrom) and node.module and node.module.split(".")[0] == "custom_sim":
            found.add(node.module if node.module != "custom_sim" else
                      "custom_sim:" + ",".join(a.name for a in node.names))
    return found


@pytest.mark.parametrize("path", MODULES, ids=[p.name for p in MODULES])
def test_only_the_scene_model_and_the_trajectory_type(path):
    if path.name in COMPARISON_TOOLS:
        return
    extra = custom_sim_imports(path) - ALLOWED
    assert not extra, f"{path.name} imports {sorted(extra)} from custom_sim"


def test_no_twin_imports_the_comparison_tools():
    for path in MODULES:
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and path.name not in COMPARISON_TOOLS:
                names = {node.module or ""} | {a.name for a in node.names}
                assert not names & {t[:-3] for t in COMPARISON_TOOLS}, f"{path.name} imports a comparison tool"
