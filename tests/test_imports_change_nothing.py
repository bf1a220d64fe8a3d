"""Importing a package writes nothing and changes no process-wide state: numba's cache is
checked against the sources when a run first needs it (custom_sim.compile_cache.fresh_cache),
and MuJoCo's warning handler is set when a twin is first built, only where the program has none."""
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

IMPORT_ALL = """
import mujoco
import scene_types, custom_sim, mujoco_models, compare, compare.cli, compare.checks.roundoff
print(mujoco.get_mju_user_warning() is None)
"""

BUILD_A_TWIN = """
import mujoco
from compare.scenarios import load
from mujoco_models import build_model
own = {own}
if own:
    mujoco.set_mju_user_warning(print)
build_model(load("box_slide"))
handler = mujoco.get_mju_user_warning()
print(handler is print if own else handler is not None)
"""


def _python(code: str, cwd: Path, cache: Path) -> str:
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache), "PYTHONPATH": str(ROOT)}
    return subprocess.run([sys.executable, "-c", code], cwd=cwd, env=env, capture_output=True, text=True,
                          check=True).stdout.strip()


def test_importing_every_package_writes_nothing_and_keeps_mujocos_handler(tmp_path):
    cache = tmp_path / "numba"
    cache.mkdir()
    assert _python(IMPORT_ALL, tmp_path, cache) == "True", "an import replaced MuJoCo's warning handler"
    # numba makes its (empty) cache folders when a cache=True function is defined: its own doing
    written = sorted(str(p.relative_to(tmp_path)) for p in tmp_path.rglob("*") if p.is_file())
    assert not written, f"importing wrote {written}"


def test_the_first_twin_counts_warnings_quietly_unless_the_program_has_its_own(tmp_path):
    for own in (False, True):
        assert _python(BUILD_A_TWIN.format(own=own), tmp_path, tmp_path / "numba") == "True", own


def test_the_first_run_still_clears_a_stale_cache(tmp_path):
    """The digest beside numba's cache is checked (and written) by the first model built."""
    code = ("from custom_sim.compile_cache import cache_folder\nfrom custom_sim.model import build_model\n"
            "from compare.scenarios import load\nbuild_model(load('box_slide'))\nprint(cache_folder())")
    folder = Path(_python(code, tmp_path, tmp_path / "numba"))
    assert (folder / "numba_sources.sha256").is_file(), "no source digest beside numba's cache after a run"
