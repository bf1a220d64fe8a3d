"""A user's module compiled with numba's cache=True (issue 32, item 9): the harness imports a .py
file under its own stem, the name the user's `import` gives it, so that numba's on-disk cache
(which stores the module's name) serves both, in either order."""
from __future__ import annotations

import subprocess
import sys
import textwrap

import numpy as np
import pytest

from compare.usersim import load_simulator

pytest.importorskip("numba")

NUMBA_SIM = textwrap.dedent('''
    import numpy as np
    from numba import njit


    @njit(cache=True)
    def _fall(z, g, dt):
        out = z.copy()
        out[4] = z[4] - g * dt
        out[0] = z[0] + dt * z[3]
        out[1] = z[1] + dt * out[4]
        return out


    def step(state, scene, dt):
        return _fall(np.asarray(state, dtype=np.float64), scene["g"], dt)
''')

# the user's own script, importing the same file by its name
USER_SCRIPT = "import numpy as np, nb_fall; print(nb_fall.step(np.zeros(6), {'g': 10.0}, 0.5)[4])"


def _user_import(folder) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", USER_SCRIPT], cwd=folder, capture_output=True, text=True,
                          timeout=120)


def _harness_step(folder) -> float:
    sim = load_simulator(f"{folder / 'nb_fall.py'}:step")
    return float(sim.call(np.zeros(6), {"g": 10.0}, 0.5)[4])


def test_the_users_import_works_after_the_harness_cached_the_module(tmp_path):
    """Before: ModuleNotFoundError: No module named 'usersim__..._nb_fall_py' in the user's
    own import, which loaded numba's cache written under the harness's name."""
    (tmp_path / "nb_fall.py").write_text(NUMBA_SIM)
    assert _harness_step(tmp_path) == -5.0          # v = -g dt
    assert any((tmp_path / "__pycache__").glob("nb_fall._fall-*.nbi")), "numba wrote no cache"
    done = _user_import(tmp_path)
    assert done.returncode == 0, done.stderr[-400:]
    assert float(done.stdout) == -5.0


@pytest.mark.slow
def test_the_harness_works_after_the_users_import_cached_the_module(tmp_path):
    (tmp_path / "nb_fall.py").write_text(NUMBA_SIM)
    done = _user_import(tmp_path)
    assert done.returncode == 0, done.stderr[-400:]
    assert _harness_step(tmp_path) == -5.0


def test_a_file_named_like_a_module_of_the_harness_keeps_a_name_of_its_own(tmp_path):
    """A user's numpy.py must not take numpy's place in the harness's process."""
    (tmp_path / "numpy.py").write_text("def step(state, scene, dt):\n    return list(state)\n")
    sim = load_simulator(f"{tmp_path / 'numpy.py'}:step")
    assert sim.module.__name__ != "numpy" and sys.modules["numpy"] is np
