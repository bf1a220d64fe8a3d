"""The vocabulary is said once: the state's components and their units in scene_types/state.py,
every other place taking them from there (no module spells them again); one base, Diverged, for
every run that could not go on; no name that shadows a Python builtin."""
from __future__ import annotations

import ast
import builtins
import functools
import importlib
import re
from pathlib import Path

import numpy as np
import pytest

from scene_types import Diverged, STATE_COMPONENTS, STATE_UNITS, UNIT_OF, Trajectory, csv_text

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("scene_types", "custom_sim", "mujoco_models", "compare")
DEFINED_IN = ROOT / "scene_types" / "state.py"
DIVERGED = [   # module, class: each run or solver that could not go on
    ("custom_sim", "SimulationDiverged"),
    ("custom_sim.runner", "SimulationChattered"),
    ("mujoco_models", "MujocoDiverged"),
    ("compare.checks.impedance", "NativeDiverged"),
    ("compare.usersim.errors", "UserDiverged"),
    ("compare.oracle.reference", "ReferenceFailed"),
]


def test_velocities_are_the_time_derivatives_of_the_positions():
    """Units checked against kinematics: vx = dx/dt, vy = dy/dt, omega = dtheta/dt."""
    assert len(STATE_COMPONENTS) == len(STATE_UNITS) == 6
    for position, velocity in (("x", "vx"), ("y", "vy"), ("theta", "omega")):
        assert UNIT_OF[velocity] == UNIT_OF[position] + "/s", (position, velocity, UNIT_OF)
    assert UNIT_OF["x"] == UNIT_OF["y"] == "m" and UNIT_OF["theta"] == "rad"


def test_the_csv_header_and_the_states_follow_the_components():
    n = 3
    values = {c: np.arange(n) + 10.0 * k for k, c in enumerate(STATE_COMPONENTS)}
    zero = np.zeros(n)
    traj = Trajectory(t=np.arange(n) * 0.1, **values, energy_kinetic=zero, energy_gravity=zero, energy_contact=zero)
    assert csv_text(traj).splitlines()[0].split(",") == ["t", *STATE_COMPONENTS, "energy"]
    for k, c in enumerate(STATE_COMPONENTS):
        assert np.array_equal(traj.states()[:, k], values[c]), c


def test_every_consumer_takes_the_components_from_scene_types():
    from compare.checks import metrics, step_check
    from compare.usersim import base, csv_files

    assert step_check.COMPONENTS is STATE_COMPONENTS and step_check.UNIT_OF is UNIT_OF
    assert metrics.STATE is STATE_COMPONENTS and csv_files.STATE_COLUMNS is STATE_COMPONENTS
    assert base.STATE == "[x, y, theta, vx, vy, omega]"


@functools.cache
def _nodes(path: Path) -> tuple:
    """Every node of a module's syntax tree (parsed once for the tests that read them)."""
    return tuple(ast.walk(ast.parse(path.read_text(encoding="utf-8"))))


def _spellings(path: Path) -> list[str]:
    """Lines of code (docstrings aside) that spell the state again: three or more of its
    components as strings, a unit of a velocity beside another component, or a text naming them."""
    docstrings = set()
    for node in _nodes(path):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                docstrings.add(id(first.value))
    lines: dict[int, set[str]] = {}
    for node in _nodes(path):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docstrings:
            seen = lines.setdefault(node.lineno, set())
            if node.value in STATE_COMPONENTS or node.value in ("m/s", "rad/s"):
                seen.add(node.value)
            elif re.search(r"theta, ?vx, ?vy|m, ?m, ?rad", node.value):
                seen.add("a text")
    return [f"{path.relative_to(ROOT)}:{line}" for line, seen in sorted(lines.items())
            if len(seen) >= 3 or "a text" in seen or (seen & {"m/s", "rad/s"} and len(seen) >= 2)]


def test_no_module_spells_the_components_again():
    files = [p for package in PACKAGES for p in sorted((ROOT / package).rglob("*.py")) if p != DEFINED_IN]
    assert len(files) > 100
    assert _spellings(DEFINED_IN), "the scan no longer finds the definition itself"
    assert [hit for p in files for hit in _spellings(p)] == []


@pytest.mark.parametrize("module, name", DIVERGED, ids=[name for _, name in DIVERGED])
def test_every_diverged_is_a_scene_types_diverged(module, name):
    cls = getattr(importlib.import_module(module), name)
    assert issubclass(cls, Diverged) and issubclass(cls, RuntimeError), cls.__mro__


def test_a_users_diverged_is_still_a_fault_of_their_scene():
    from compare.usersim.errors import UserDiverged, UserFault

    exc = UserDiverged("step 12: x = inf", details="Traceback ...")
    assert isinstance(exc, UserFault) and isinstance(exc, Diverged) and exc.details == "Traceback ..."


def test_the_reference_raises_a_diverged_and_shadows_no_builtin():
    reference = importlib.import_module("compare.oracle.reference")
    assert not hasattr(reference, "ReferenceError"), "compare.oracle.reference shadows the builtin ReferenceError"
    exc = reference.ReferenceFailed("two points stuck at once", t=0.25)
    assert isinstance(exc, Diverged) and exc.t == 0.25


def test_no_module_binds_the_name_of_a_builtin_at_its_top():
    """A module-level class, function or import named like a builtin (ReferenceError was one)."""
    names = set(dir(builtins))
    found = []
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            for node in _nodes(path):
                bound = []
                if isinstance(node, (ast.ClassDef, ast.FunctionDef)) and node.col_offset == 0:
                    bound = [node.name]
                elif isinstance(node, (ast.Import, ast.ImportFrom)):
                    bound = [a.asname or a.name.split(".")[0] for a in node.names]
                found += [f"{path.relative_to(ROOT)}:{node.lineno}: {b}" for b in bound if b in names]
    assert found == []
