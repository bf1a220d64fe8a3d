"""A user's Python functions as the simulator under test: a step function, or a whole run.

    --sim MODULE:FUNCTION           step(state, scene, dt) -> state          StepFunction
    --sim MODULE:FUNCTION --whole   simulate(scene) -> array (steps + 1, 6)   WholeFunction

MODULE is a dotted module name (importable from the current folder) or a path to a .py file.
A module-level INTEGRATOR (a string) names the integrator it implements (default: the scene's).
"""
from __future__ import annotations

import importlib
import importlib.util
import sys
import time
from pathlib import Path

import numpy as np

from custom_sim import Scene
from custom_sim.model import initial_state

from .base import STATE, UserRun, _check_initial, _first_bad_row, _Simulator, _state_text
from .errors import UserCodeError, raised
from .scene_dict import scene_dict


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


