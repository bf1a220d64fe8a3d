"""A user's simulator shipped as source text: what travels, and that the copy runs alone."""
from __future__ import annotations

import dataclasses
import shutil
import sys

import numpy as np
import pytest

from compare.scenarios import load
from compare.usersim import StepFunction, UserCodeError
from compare.usersim.bundle import PREFIX, Bundle

# A step in two files and a package: the module imports a sibling at its top and another
# inside its step (at call time); `physics` is a package of its own folder.
MAIN = '''
import numpy as np
from helper import GRAVITY_SIGN

def step(state, scene, dt):
    import physics.drag as drag
    z = np.array(state, dtype=float)
    z[4] += GRAVITY_SIGN * scene["g"] * dt * drag.FACTOR
    z[:3] += z[3:] * dt
    return z
'''
HELPER = "GRAVITY_SIGN = -1.0\n"
SHORT = 0.05   # s of box_drop: a few hundred steps of a Python step
DRAG = "FACTOR = 1.0\n"


def _write(folder, helper=HELPER):
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "my_sim.py").write_text(MAIN)
    (folder / "helper.py").write_text(helper)
    (folder / "unrelated.py").write_text("raise SystemExit('never imported')\n")
    (folder / "physics").mkdir(exist_ok=True)
    (folder / "physics" / "__init__.py").write_text("")
    (folder / "physics" / "drag.py").write_text(DRAG)
    return folder / "my_sim.py"


@pytest.fixture
def clean_modules():
    """The test's `helper` and `physics` modules forgotten afterwards (other tests import theirs)."""
    before = set(sys.modules)
    path = list(sys.path)
    yield
    for name in set(sys.modules) - before:
        if name.split(".")[0] in ("helper", "physics") or name.startswith("usersim_"):
            del sys.modules[name]
    sys.path[:] = path


def test_the_module_and_the_files_it_imports_travel_and_nothing_else(tmp_path, clean_modules):
    path = _write(tmp_path / "user")
    bundle = Bundle.of(f"{path}:step")
    assert [rel for rel, _ in bundle.files] == ["helper.py", "my_sim.py", "physics/__init__.py",
                                                "physics/drag.py"]
    assert bundle.entry == "my_sim.py"


def test_the_shipped_copy_runs_where_the_users_folder_is_gone(tmp_path, clean_modules):
    """As on a worker that cannot see the user's files: the copy alone, bit for bit the same run."""
    path = _write(tmp_path / "user")
    scene = dataclasses.replace(load("box_drop"), duration=SHORT)
    want = StepFunction(f"{path}:step").run(scene).states
    bundle = Bundle.of(f"{path}:step")
    for name in ("helper", "physics", "physics.drag"):
        sys.modules.pop(name, None)
    shutil.rmtree(tmp_path / "user")
    simulator = bundle.simulator()
    got = simulator.run(scene).states
    assert np.array_equal(got, want)
    assert simulator.spec == f"{path}:step", "messages name the user's file, not the copy"
    assert PREFIX in simulator.module.__file__


def test_two_versions_of_a_sibling_stay_apart(tmp_path, clean_modules):
    """Two studies whose modules import their own helper.py: each run uses its own (the
    worker's sys.path and sys.modules hold one shipped folder at a time)."""
    first = Bundle.of(f"{_write(tmp_path / 'a')}:step")
    second = Bundle.of(f"{_write(tmp_path / 'b', helper='GRAVITY_SIGN = +1.0')}:step")
    assert first.digest != second.digest
    scene = dataclasses.replace(load("box_drop"), duration=SHORT)
    vy = []
    for bundle in (first, second, first):
        sim = bundle.simulator()
        z = sim.call(np.array([0.0, 1.0, 0.0, 0.0, 0.0, 0.0]), {"g": 9.81}, 0.01)
        vy.append(z[4])
        assert sim.run(scene).states.shape == (scene.steps + 1, 6)
    assert vy == [-9.81 * 0.01, 9.81 * 0.01, -9.81 * 0.01], vy


def test_a_module_that_is_no_py_file_is_bad_input_naming_it():
    """A compiled module cannot be sent as text: one line saying so, before anything runs."""
    with pytest.raises(UserCodeError, match="math is not a .py file the workers can be sent"):
        Bundle.of("math:sqrt")


def test_a_whole_run_travels_too(tmp_path, clean_modules):
    """--whole: simulate(scene) from the shipped copy, the same array as from the user's file."""
    folder = tmp_path / "user"
    folder.mkdir()
    (folder / "helper.py").write_text(HELPER)
    (folder / "whole_sim.py").write_text(
        "import numpy as np\nfrom helper import GRAVITY_SIGN\n\n"
        "def simulate(scene):\n"
        "    n = int(round(scene['duration'] / scene['dt']))\n"
        "    z = np.tile(np.array(scene['state0'], dtype=float), (n + 1, 1))\n"
        "    t = np.arange(n + 1) * scene['dt']\n"
        "    z[:, 1] += GRAVITY_SIGN * 0.5 * scene['g'] * t * t\n"
        "    z[:, 4] += GRAVITY_SIGN * scene['g'] * t\n"
        "    return z\n")
    scene = dataclasses.replace(load("box_drop"), duration=SHORT)
    from compare.usersim import WholeFunction
    want = WholeFunction(f"{folder / 'whole_sim.py'}:simulate").run(scene).states
    bundle = Bundle.of(f"{folder / 'whole_sim.py'}:simulate", whole=True)
    sys.modules.pop("helper", None)
    shutil.rmtree(folder)
    simulator = bundle.simulator()
    assert simulator.kind == "whole"
    assert np.array_equal(simulator.run(scene).states, want)


def test_the_shapes_a_shipped_module_declares_skip_the_other_scenes(tmp_path, clean_modules):
    """SHAPES travels with the code: a box scene is skipped, with the reason, before any call."""
    from compare.usersim import SceneSkipped

    path = _write(tmp_path / "user")
    path.write_text("SHAPES = ('circle',)\n" + MAIN)
    simulator = Bundle.of(f"{path}:step").simulator()
    with pytest.raises(SceneSkipped, match="a box body, not in the module's SHAPES"):
        simulator.run(dataclasses.replace(load("box_drop"), duration=SHORT))
