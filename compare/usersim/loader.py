"""The simulator under test, brought in one of three ways, each giving states (steps + 1, 6).

    --sim MODULE:FUNCTION           step(state, scene, dt) -> state          StepFunction
    --sim MODULE:FUNCTION --whole   simulate(scene) -> array (steps + 1, 6)   WholeFunction
    --trajectories DIR              DIR/<scene name>.csv                      TrajectoryFiles

state = [x, y, theta, vx, vy, omega] (m, m, rad, m/s, m/s, rad/s) of the centre of mass; scene
= scene_dict(scene), the resolved scene as plain dicts and floats. MODULE is a dotted module
name (importable from the current folder) or a path to a .py file. A simulator may name the
integrator it implements in a module-level INTEGRATOR (a string; default: the scene's), and a
--whole function may return a 7th column, the energy (J). A folder of trajectories may hold a
simulator.toml with `integrator = "..."`.

Every fault is a UserCodeError (bad input, exit 2) naming the function or the file (row,
column), what was wrong and what was expected.
"""
from __future__ import annotations

import importlib
import importlib.util
import sys
import time
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from custom_sim import Scene
from custom_sim.model import initial_state

from .errors import UserCodeError, raised
from .scene_dict import scene_dict

STATE = "[x, y, theta, vx, vy, omega]"
# A CSV's t column must equal i dt to within this fraction of dt: a row off by one step is
# off by a whole dt, and a time written with too few digits to tell steps apart is refused.
TIME_GRID_TOLERANCE = 0.01
# The CSV's t = 0 row must be the scene's initial state to this relative precision (or
# absolute, m and m/s, near zero): six significant digits, the least any writer keeps.
INITIAL_STATE_RTOL = 1e-6
INITIAL_STATE_ATOL = 1e-9


@dataclass(frozen=True)
class UserRun:
    """One scene run by the user's simulator.

    states (steps + 1, 6); energy (steps + 1,) J or None when not supplied; wall_time s
    (None: not known, a CSV); written_digits: significant digits the states were stored with
    (a CSV) or None (full double precision); integrator: the one the simulator names."""

    states: np.ndarray
    energy: np.ndarray | None
    wall_time: float | None
    integrator: str
    written_digits: int | None = None


def _import(module: str):
    """A dotted module or a path to a .py file; its own import errors are the user's."""
    where = f"--sim {module}"
    if module.endswith(".py") or "/" in module or "\\" in module:
        path = Path(module)
        if not path.is_file():
            raise UserCodeError(f"{where}: no such file (expected a path to a .py file or a dotted module name)")
        name = "usersim_" + "".join(ch if ch.isalnum() else "_" for ch in str(path.resolve()))
        if name in sys.modules:
            return sys.modules[name]
        spec = importlib.util.spec_from_file_location(name, path)
        mod = importlib.util.module_from_spec(spec)
        folder = str(path.resolve().parent)
        sys.path.insert(0, folder)  # its sibling modules import as they would when run there
        try:
            sys.modules[name] = mod
            spec.loader.exec_module(mod)
        except Exception as exc:  # noqa: BLE001 - any fault of the user's module
            sys.modules.pop(name, None)
            raise raised(f"{where}: importing {path}", exc, "a module that imports") from None
        finally:
            sys.path.remove(folder)
        return mod
    if "." not in sys.path and "" not in sys.path:
        sys.path.append(".")
    try:
        return importlib.import_module(module)
    except ModuleNotFoundError as exc:
        if exc.name and module.startswith(exc.name):
            raise UserCodeError(f"{where}: no module named {exc.name!r} (expected a dotted module importable "
                                "from the current folder, or a path to a .py file)") from None
        raise raised(f"{where}: importing {module}", exc, "a module that imports") from None
    except Exception as exc:  # noqa: BLE001
        raise raised(f"{where}: importing {module}", exc, "a module that imports") from None


def load_function(spec: str, signature: str):
    """The callable named by MODULE:FUNCTION, and its module."""
    module, sep, func = spec.rpartition(":")
    if not sep or not module or not func:
        raise UserCodeError(f"--sim {spec}: expected MODULE:FUNCTION naming {signature}")
    mod = _import(module)
    fn = getattr(mod, func, None)
    if fn is None:
        names = sorted(n for n in dir(mod) if callable(getattr(mod, n)) and not n.startswith("_"))
        raise UserCodeError(f"--sim {spec}: {module} has no function {func!r} (expected {signature}; "
                            f"it defines: {', '.join(names) or 'no functions'})")
    if not callable(fn):
        raise UserCodeError(f"--sim {spec}: {func} is a {type(fn).__name__}, not a function (expected {signature})")
    return fn, mod


def _declared_integrator(mod, scene: Scene) -> str:
    value = getattr(mod, "INTEGRATOR", None)
    if value is None:
        return scene.integrator
    if not isinstance(value, str):
        raise UserCodeError(f"{mod.__name__}.INTEGRATOR: expected a string naming an integrator, got {value!r}")
    return value


def _as_state(value, where: str, step: int) -> np.ndarray:
    """A returned state checked: 6 finite floats."""
    try:
        z = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise UserCodeError(f"{where} returned {type(value).__name__} at step {step} "
                            f"(expected 6 numbers {STATE})") from None
    if z.shape != (6,):
        raise UserCodeError(f"{where} returned shape {z.shape} at step {step} (expected shape (6,): {STATE})")
    if not np.all(np.isfinite(z)):
        raise UserCodeError(f"{where} returned a non-finite state {z.tolist()} at step {step} "
                            f"(expected 6 finite numbers {STATE})")
    return z


def _first_bad_row(states: np.ndarray) -> int:
    bad = np.flatnonzero(~np.all(np.isfinite(states), axis=1))
    return int(bad[0]) if bad.size else -1


def _state_text(z) -> str:
    return "[" + ", ".join(f"{v:.6g}" for v in z) + "]"


class _Simulator:
    """What every way in answers: run(scene) -> UserRun, integrator_for(scene), and for the
    report: name, integrator (of the scene last run), diagnose(scene, trajectory).

    reruns: whether it can run a scene it was not given files for (a variant the harness
    derives, e.g. friction switched off): True for functions, False for a folder of CSVs."""

    kind = ""
    label = ""
    reruns = True
    _scene = None

    @property
    def name(self) -> str:
        return self.label

    @property
    def integrator(self) -> str | None:
        """The integrator of the scene last run (declared, or that scene's)."""
        return None if self._scene is None else self.integrator_for(self._scene)

    def run(self, scene: Scene) -> UserRun:
        self._scene = scene
        return self._run(scene)

    def diagnose(self, scene: Scene, trajectory) -> dict:
        """diagnosis(self, scene, trajectory.states()): see compare/usersim/diagnosis.py."""
        from .diagnosis import diagnosis
        return diagnosis(self, scene, trajectory.states())


class StepFunction(_Simulator):
    """`step(state, scene, dt) -> state`, called in a plain Python loop.

    The first call gets a numpy array (float, length 6); each later call gets what the previous
    one returned (a numpy array or a list of 6 numbers), so the harness adds only a call and a
    copy per step (python -m compare.usersim.overhead measures it)."""

    kind = "step"

    def __init__(self, spec: str):
        self.spec = spec
        self.function, self.module = load_function(spec, "step(state, scene, dt) -> state")
        self.label = spec

    def __reduce__(self):  # a process pool re-imports it by name
        return (StepFunction, (self.spec,))

    def integrator_for(self, scene: Scene) -> str:
        return _declared_integrator(self.module, scene)

    def call(self, state, scene_d: dict, dt: float, step: int = 1) -> np.ndarray:
        """One checked call from `state` (the diagnosis's probe)."""
        try:
            out = self.function(np.array(state, dtype=float), scene_d, dt)
        except Exception as exc:  # noqa: BLE001
            raise raised(f"{self.spec} at step {step}", exc, f"a state {STATE}") from None
        self._first_returned = out
        return _as_state(out, self.spec, step)

    def _run(self, scene: Scene) -> UserRun:
        n, dt, step = scene.steps, scene.dt, self.function
        sd = scene_dict(scene)
        out = np.empty((n + 1, 6))
        out[0] = initial_state(scene)
        out[1] = self.call(out[0], sd, dt, 1)  # the first call checked in full
        as_list = isinstance(self._first_returned, (list, tuple))
        z = list(out[1]) if as_list else out[1].copy()
        i = 1
        start = time.perf_counter()
        try:
            if as_list:
                # a step returning a list: its numbers appended flat (a list copies floats,
                # so a list changed in place later cannot corrupt the rows), one array at the end
                flat = []
                append = flat.extend
                for i in range(2, n + 1):
                    z = step(z, sd, dt)
                    append(z)
            else:
                # the harness's whole cost per step: one call and one row copied
                for i in range(2, n + 1):
                    z = step(z, sd, dt)
                    out[i] = z
        except Exception as exc:  # noqa: BLE001
            if exc.__traceback__.tb_next is None:  # raised by our own line: not a state
                _as_state(z, self.spec, i)
                raise UserCodeError(f"{self.spec} returned {type(z).__name__} at step {i} "
                                    f"(expected 6 numbers {STATE})") from None
            raise raised(f"{self.spec} at step {i} (t = {i * dt:.6g} s, from state "
                         f"{_state_text(out[i - 1] if not as_list else z)})", exc, f"a state {STATE}") from None
        if as_list and n > 1:
            if len(flat) != 6 * (n - 1):
                raise UserCodeError(f"{self.spec} returned a list of 6 numbers at step 1 but of another length at a "
                                    f"later step ({len(flat)} numbers over {n - 1} steps; expected 6 numbers {STATE} "
                                    "every step; note that from step 2 on it is given back the list it returned)")
            try:
                out[2:] = np.fromiter(flat, dtype=float, count=len(flat)).reshape(n - 1, 6)
            except (TypeError, ValueError):
                raise UserCodeError(f"{self.spec} returned a list holding something other than numbers after "
                                    f"step 1 (expected 6 numbers {STATE} every step)") from None
        wall = time.perf_counter() - start
        bad = _first_bad_row(out)
        if bad >= 0:
            raise UserCodeError(f"{self.spec} returned a non-finite state {_state_text(out[bad])} at step {bad} "
                                f"(t = {bad * dt:.6g} s) from {_state_text(out[bad - 1])} "
                                f"(expected 6 finite numbers {STATE})")
        return UserRun(out, None, wall, self.integrator_for(scene))


class WholeFunction(_Simulator):
    """`simulate(scene) -> array (steps + 1, 6)` (or 7 columns, the 7th the energy in J)."""

    kind = "whole"

    def __init__(self, spec: str):
        self.spec = spec
        self.function, self.module = load_function(spec, "simulate(scene) -> array (steps + 1, 6)")
        self.label = spec + " (whole)"

    def __reduce__(self):
        return (WholeFunction, (self.spec,))

    def integrator_for(self, scene: Scene) -> str:
        return _declared_integrator(self.module, scene)

    def _run(self, scene: Scene) -> UserRun:
        n = scene.steps
        start = time.perf_counter()
        try:
            value = self.function(scene_dict(scene))
        except Exception as exc:  # noqa: BLE001
            raise raised(f"{self.spec} on scene {scene.name}", exc, f"an array ({n + 1}, 6)") from None
        wall = time.perf_counter() - start
        try:
            data = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise UserCodeError(f"{self.spec} returned {type(value).__name__} on scene {scene.name} "
                                f"(expected an array ({n + 1}, 6) of rows {STATE})") from None
        if data.ndim != 2 or data.shape[0] != n + 1 or data.shape[1] not in (6, 7):
            raise UserCodeError(f"{self.spec} returned shape {data.shape} on scene {scene.name} "
                                f"(expected ({n + 1}, 6): the t = 0 row, then one row per step of {STATE}; "
                                "a 7th column may hold the energy)")
        bad = _first_bad_row(data)
        if bad >= 0:
            raise UserCodeError(f"{self.spec} returned a non-finite row {bad} (t = {bad * scene.dt:.6g} s) "
                                f"on scene {scene.name}: {_state_text(data[bad])} (expected finite numbers)")
        _check_initial(data[0, :6], scene, f"{self.spec} on scene {scene.name}: row 0")
        energy = data[:, 6].copy() if data.shape[1] == 7 else None
        return UserRun(np.ascontiguousarray(data[:, :6]), energy, wall, self.integrator_for(scene))


def _check_initial(z0: np.ndarray, scene: Scene, where: str) -> None:
    want = initial_state(scene)
    if not np.allclose(z0, want, rtol=INITIAL_STATE_RTOL, atol=INITIAL_STATE_ATOL):
        raise UserCodeError(f"{where} is {_state_text(z0)}, not the scene's initial state "
                            f"{_state_text(want)} (expected the t = 0 row to be the initial state)")


def written_digits(values: np.ndarray, sample: int = 200) -> int | None:
    """Significant digits a CSV's numbers were written with: the fewest that reproduce every
    sampled value exactly (None: 17, full double precision)."""
    rows = values if len(values) <= 2 * sample else np.vstack([values[:sample], values[-sample:]])
    most = 0
    for v in rows.ravel():
        v = float(v)
        if v == 0.0:
            continue
        for p in range(1, 18):
            if float(f"{v:.{p}g}") == v:
                break
        most = max(most, p)
        if most >= 16:
            return None
    return most or None


class TrajectoryFiles(_Simulator):
    """Precomputed runs: DIR/<scene name>.csv, columns by header name (t,x,y,theta,vx,vy,omega
    required; energy optional), first row t = 0, then one row per step of dt."""

    kind = "trajectories"
    reruns = False

    def __init__(self, folder: str):
        self.folder = Path(folder)
        self.label = f"{folder}/<scene>.csv"
        if not self.folder.is_dir():
            raise UserCodeError(f"--trajectories {folder}: no such folder (expected a folder of <scene name>.csv files)")
        self._declared = None
        meta = self.folder / "simulator.toml"
        if meta.is_file():
            try:
                data = tomllib.loads(meta.read_text(encoding="utf-8"))
            except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
                raise UserCodeError(f"{meta}: is not valid TOML ({exc})") from None
            value = data.get("integrator")
            if value is not None and not isinstance(value, str):
                raise UserCodeError(f"{meta}: integrator: expected a string, got {value!r}")
            self._declared = value

    def __reduce__(self):
        return (TrajectoryFiles, (str(self.folder),))

    def integrator_for(self, scene: Scene) -> str:
        return self._declared or scene.integrator

    def path(self, scene: Scene) -> Path:
        return self.folder / f"{scene.name}.csv"

    def _run(self, scene: Scene) -> UserRun:
        from custom_sim import read_csv

        path = self.path(scene)
        if not path.is_file():
            raise UserCodeError(f"{path}: no such file (expected one CSV per scene run, named <scene name>.csv)")
        try:
            cols = read_csv(path)
        except ValueError as exc:  # CsvError: file, row or column, what was expected
            raise UserCodeError(str(exc)) from None
        missing = [c for c in ("t", "x", "y", "theta", "vx", "vy", "omega") if c not in cols]
        if missing:
            raise UserCodeError(f"{path}: header: missing column {', '.join(missing)} "
                                "(expected t,x,y,theta,vx,vy,omega; energy optional)")
        t = cols["t"]
        n, dt = scene.steps, scene.dt
        slack = TIME_GRID_TOLERANCE * dt
        if abs(t[0]) > slack:
            hint = " (the t = 0 row, the initial state, is missing)" if abs(t[0] - dt) <= slack else ""
            raise UserCodeError(f"{path}: row 2 (first data row): t = {t[0]:.10g} s{hint} "
                                "(expected the first row at t = 0, the initial state)")
        grid = np.arange(len(t)) * dt
        off = np.flatnonzero(np.abs(t - grid) > slack)
        if off.size:
            i = int(off[0])
            raise UserCodeError(f"{path}: row {i + 2}, column t: {t[i]:.10g} s is not on the scene's time grid "
                                f"(expected t = {i} x dt = {grid[i]:.10g} s within {slack:.2g} s, dt = {dt:g} s)")
        if len(t) != n + 1:
            raise UserCodeError(f"{path}: {len(t)} data rows, t up to {t[-1]:.10g} s (expected {n + 1} rows: "
                                f"t = 0 to {n * dt:.10g} s = duration {scene.duration:g} s in steps of {dt:g} s)")
        states = np.column_stack([cols[c] for c in ("x", "y", "theta", "vx", "vy", "omega")])
        _check_initial(states[0], scene, f"{path}: row 2 (t = 0)")
        energy = cols.get("energy")
        return UserRun(states, None if energy is None else np.array(energy), None, self.integrator_for(scene),
                       written_digits(states))


def preflight(simulator, scenes) -> None:
    """Find bad input before anything is written: every scene's CSV read and checked; a step
    function called once from each scene's initial state. (A fault later in a run is still
    raised by run_user; a whole-run function is only checked by running it.)"""
    for scene in scenes:
        if simulator.kind == "trajectories":
            simulator.run(scene)
        elif simulator.kind == "step":
            simulator.call(initial_state(scene), scene_dict(scene), scene.dt, 1)
        simulator.integrator_for(scene)


def for_run(args, scenes):
    """run's hook (args.load_simulator): the simulator its flags name, checked on every scene
    before anything is written (preflight); None for custom_sim."""
    simulator = from_args(args)
    if simulator is not None:
        preflight(simulator, scenes)
    return simulator


def load_simulator(spec: str | None = None, whole: bool = False, trajectories: str | None = None):
    """The simulator under test: --sim spec (a step function, or with whole=True a simulate
    function), or trajectories=DIR (a folder of CSVs). None when neither is given (custom_sim)."""
    if trajectories is not None:
        if spec is not None:
            raise UserCodeError("--sim and --trajectories: expected one simulator under test, got both")
        return TrajectoryFiles(trajectories)
    if spec is None:
        if whole:
            raise UserCodeError("--whole: expected it with --sim MODULE:FUNCTION")
        return None
    return WholeFunction(spec) if whole else StepFunction(spec)


def from_args(args):
    """load_simulator from run's parsed flags (--sim, --whole, --trajectories)."""
    return load_simulator(getattr(args, "sim", None), getattr(args, "whole", False),
                          getattr(args, "trajectories", None))
