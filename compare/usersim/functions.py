"""A user's Python functions as the simulator under test: a step function, or a whole run.

    --sim MODULE:FUNCTION           step(state, scene, dt) -> state          StepFunction
    --sim MODULE:FUNCTION --whole   simulate(scene) -> array (steps + 1, 6)   WholeFunction

MODULE is a dotted module name (importable from the current folder) or a path to a .py file.
A module-level INTEGRATOR (a string) names the integrator it implements (default: the scene's;
"other:NAME" for one the harness does not know). A module-level SHAPES (a tuple of point, box,
compound, circle) names the bodies it does: a scene of another shape is skipped without calling
it; a step (or whole run) that raises NotImplementedError("reason") skips its scene too.

The protocol, as the harness keeps it:
1. every run starts from a fresh copy of the module (its top level executed again), so no
   state is carried from one scene, or one run, to the next;
2. the step is called once per step, in order, from the t = 0 state, each time with a fresh
   float64 array holding the state it returned last (never an object it can keep);
3. it must return 6 real numbers (a sequence or a (6,) array); anything else is bad input
   naming the step and what came back;
4. an exception, a NaN or a state that blows up is that scene's fault: its row says the step
   and the state, and the other scenes are judged;
5. NotImplementedError is the code saying it does not do the scene: the scene is skipped
   (SceneSkipped) with the exception's message as the reason, never judged.
"""
from __future__ import annotations

import importlib
import importlib.util
import inspect
import keyword
import sys
import time
import warnings
from numbers import Real
from pathlib import Path

import numpy as np

from custom_sim import Scene
from custom_sim.model import initial_state
from scene_types.schema import SHAPES as SHAPE_NAMES

from ..executor import steps as progress
from .base import STATE, UserRun, _check_initial, _first_bad_row, _Simulator, _state_text, declared_integrator
from .errors import UserCodeError, UserFault, not_implemented, raised
from .guard import user_code
from .scene_dict import scene_dict

_SIX = (6,)
_F64 = np.dtype(np.float64)
# What a step's return is checked against on the fast path (anything else takes as_state's):
_SEQUENCES = {list, tuple}
_REALS = {float, int, np.float64}
# Steps between two progress reports are chosen so that a report comes about this often (s):
# often enough for a user to see a slow step move, rare enough to cost nothing per step.
REPORT_EVERY = 0.25


def _module_path(module: str) -> Path | None:
    return Path(module) if module.endswith(".py") or "/" in module or "\\" in module else None


def _execute(name: str, spec, where: str):
    """A new module object for spec, its top level run as user code."""
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod
    try:
        with user_code(where):
            spec.loader.exec_module(mod)
    except UserCodeError:
        raise
    except Exception as exc:  # noqa: BLE001 - any fault of the user's module
        sys.modules.pop(name, None)
        raise raised(where, exc) from None
    return mod


def _file_module_name(path: Path) -> str:
    """The module name a .py file is imported under: its own stem, as `import stem` names it in
    the user's own code (numba's cache=True stores the module's name, so that the user's imports
    and the harness's share it), unless that name is another module's (the harness's, the
    standard library's, another file's) or no identifier; then a name of the harness's own."""
    stem = path.stem
    if stem.isidentifier() and not keyword.iskeyword(stem):
        loaded = sys.modules.get(stem)
        if loaded is not None:
            mine = getattr(loaded, "__file__", None)
            if mine is not None and Path(mine).resolve() == path:
                return stem
        else:
            try:
                found = importlib.util.find_spec(stem)
            except (ImportError, ValueError):
                found = None
            if found is None or (found.origin and Path(found.origin).resolve() == path):
                return stem
    return "usersim_" + "".join(ch if ch.isalnum() else "_" for ch in str(path))


def _import(module: str):
    """A fresh copy of a dotted module or of a .py file; its own import errors are the user's.

    A file's folder goes first on sys.path while it imports (its siblings import as they would
    when run there) and stays at the end afterwards, so a step that imports a sibling later
    still finds it without the folder shadowing the harness's own modules."""
    where = f"--sim {module}"
    path = _module_path(module)
    if path is not None:
        if not path.is_file():
            raise UserCodeError(f"{where}: no such file (expected a path to a .py file or a dotted module name)")
        path = path.resolve()
        name = _file_module_name(path)
        spec = importlib.util.spec_from_file_location(name, path)
        folder = str(path.parent)
        sys.path.insert(0, folder)
        try:
            return _execute(name, spec, f"{where}: importing {path}")
        finally:
            sys.path.remove(folder)
            if folder not in sys.path:
                sys.path.append(folder)
    if "." not in sys.path and "" not in sys.path:
        sys.path.append(".")
    try:
        with user_code(f"{where}: importing {module}"):
            spec = importlib.util.find_spec(module)
    except ModuleNotFoundError as exc:
        spec, missing = None, exc.name
    except UserCodeError:
        raise
    except Exception as exc:  # noqa: BLE001 - a parent package that fails to import
        raise raised(f"{where}: importing {module}", exc) from None
    else:
        missing = module
    if spec is None:
        raise UserCodeError(f"{where}: no module named {missing!r} (expected a dotted module importable "
                            "from the current folder, or a path to a .py file)")
    return _execute(module, spec, f"{where}: importing {module}")


def load_function(spec: str, signature: str):
    """The callable named by MODULE:FUNCTION, and its module (freshly imported)."""
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


def _describe(value) -> str:
    """What came back, in a few words: `a float 0.3`, `an array of shape (1, 6)`, `None`."""
    if value is None:
        return "None (did the function forget to return the state?)"
    if isinstance(value, np.ndarray):
        return f"an array of shape {value.shape} and dtype {value.dtype}"
    if isinstance(value, (list, tuple)):
        return f"a {type(value).__name__} of {len(value)} items"
    text = repr(value)
    return f"a {type(value).__name__} {text[:40]}"


def as_state(value, where: str) -> tuple[np.ndarray, bool]:
    """A returned value as a state (6,) float64, and whether it came as float32. Anything but 6
    real numbers is bad input naming `where` and what came back (never broadcast, never cut)."""
    if isinstance(value, np.ndarray):
        ok = value.shape == _SIX and value.dtype.kind in "fiu"
        if ok:
            return value.astype(float), value.dtype == np.float32
    elif isinstance(value, (list, tuple)) and len(value) == 6:
        bad = [j for j, v in enumerate(value) if isinstance(v, (bool, np.bool_)) or not isinstance(v, Real)]
        if not bad:
            return np.array(value, dtype=float), any(isinstance(v, np.float32) for v in value)
        j = bad[0]
        raise UserCodeError(f"{where} returned a {type(value).__name__} whose item {j} is "
                            f"{_describe(value[j])} (expected 6 real numbers {STATE})")
    raise UserCodeError(f"{where} returned {_describe(value)} (expected 6 real numbers {STATE}: "
                        "a list, a tuple or an array of shape (6,))")


class _Function(_Simulator):
    """A user's function named by MODULE:FUNCTION: imported now (its faults are bad input before
    anything runs) and again at the start of every run (fresh)."""

    signature = ""
    arguments = 0      # the positional arguments the harness calls it with
    other_flag = ""    # what to say when the function takes the other kind's arguments

    def __init__(self, spec: str):
        self.spec = spec
        self.label = spec
        self.fresh()
        self._check_arguments()

    def _check_arguments(self) -> None:
        """Bad input before any call: a function that cannot take the arguments it will be given
        (a step function given --whole, a whole run without it)."""
        try:
            parameters = inspect.signature(self.function)
        except (TypeError, ValueError):   # no signature to read (a builtin, a C extension)
            return
        try:
            parameters.bind(*[None] * self.arguments)
        except TypeError as exc:
            raise UserCodeError(f"--sim {self.spec}: {self.function.__name__}{parameters} cannot be called "
                                f"with {self.arguments} argument{'s' if self.arguments > 1 else ''} ({exc}); "
                                f"expected {self.signature}{self.other_flag}") from None

    def __reduce__(self):  # another process imports it by name
        return (type(self), (self.spec,))

    def integrator_for(self, scene: Scene) -> str:
        return declared_integrator(getattr(self.module, "INTEGRATOR", None), f"{self.spec}: INTEGRATOR", scene.integrator)

    def fresh(self) -> None:
        """Import the module again: a new module state, as at the start of a run."""
        self.function, self.module = load_function(self.spec, self.signature)
        self.shapes = declared_shapes(getattr(self.module, "SHAPES", None), f"{self.spec}: SHAPES")

    def skip_reason(self, scene: Scene) -> str | None:
        if self.shapes is None or scene.body.shape in self.shapes:
            return None
        return f"a {scene.body.shape} body, not in the module's SHAPES = {self.shapes!r}"


def declared_shapes(value, where: str) -> tuple[str, ...] | None:
    """The shapes a module says it does (`where` names the field): None when it does not say;
    a tuple or list of names of point, box, compound, circle. Anything else is bad input."""
    if value is None:
        return None
    expected = f"expected a tuple of shape names, some of {', '.join(SHAPE_NAMES)}, e.g. (\"box\",)"
    if isinstance(value, str):
        raise UserCodeError(f"{where} = {value!r}: a string, not a tuple ({expected}; a one-item tuple "
                            "needs its comma)")
    if not isinstance(value, (tuple, list, set, frozenset)) or not value:
        raise UserCodeError(f"{where} = {value!r}: {expected}")
    bad = [v for v in value if v not in SHAPE_NAMES]
    if bad:
        raise UserCodeError(f"{where} = {value!r}: {bad[0]!r} is not a shape the harness knows ({expected})")
    return tuple(v for v in SHAPE_NAMES if v in value)


class StepFunction(_Function):
    """`step(state, scene, dt) -> state`, called in a plain Python loop (see the module's protocol)."""

    kind = "step"
    signature = "step(state, scene, dt) -> state"
    arguments = 3
    other_flag = " (a whole run, simulate(scene)? add --whole)"
    float32 = False   # set once a step has returned float32 (warned once)

    def call(self, state, scene_d: dict, dt: float, step: int = 1) -> np.ndarray:
        """One checked call from a copy of `state` (the diagnosis's probe)."""
        where = f"{self.spec} at step {step}"
        try:
            with user_code(where):
                out = self.function(np.array(state, dtype=float), scene_d, dt)
        except (UserCodeError, UserFault):   # a process's fault is one line already (process.py)
            raise
        except Exception as exc:  # noqa: BLE001
            raise UserFault(raised(where, exc)) from None
        return as_state(out, where)[0]

    def _run(self, scene: Scene) -> UserRun:
        self.fresh()
        fn, n, dt = self.function, scene.steps, scene.dt
        sd = scene_dict(scene)
        out = np.empty((n + 1, 6))
        out[0] = initial_state(scene)
        i, chunk, start = 1, 1, time.perf_counter()
        progress.started(n)
        where = f"{self.spec} at step"
        try:
            with user_code(lambda: f"{where} {i}"):
                while i <= n:
                    first, end, t0 = i, min(n, i + chunk - 1), time.perf_counter()
                    for i in range(first, end + 1):
                        z = fn(out[i - 1].copy(), sd, dt)
                        if z.__class__ is np.ndarray:
                            if z.shape != _SIX or z.dtype is not _F64:
                                z = self._accept(z, f"{where} {i}")
                        elif z.__class__ not in _SEQUENCES or len(z) != 6 or not _REALS.issuperset(map(type, z)):
                            z = self._accept(z, f"{where} {i}")
                        out[i] = z
                    progress.reached(end)
                    per_step = (time.perf_counter() - t0) / (end - first + 1)
                    chunk = int(min(4 * chunk, max(1.0, REPORT_EVERY / max(per_step, 1e-9))))
                    i = end + 1
        except (UserCodeError, UserFault):   # a process's fault is one line already (process.py)
            raise
        except NotImplementedError as exc:   # the code does not do this scene: skipped
            raise not_implemented(exc, i) from None
        except Exception as exc:  # noqa: BLE001 - the scene's fault: its row names the step
            bad = _first_bad_row(out[:i])
            if bad >= 0:  # it failed on a non-finite state it returned before: name that one
                raise _non_finite(self.spec, out, bad, dt) from None
            raise UserFault(raised(f"{self.spec} at step {i} (t = {i * dt:.6g} s, from state "
                                   f"{_state_text(out[i - 1])})", exc)) from None
        wall = time.perf_counter() - start
        bad = _first_bad_row(out)
        if bad >= 0:
            raise _non_finite(self.spec, out, bad, dt)
        return UserRun(out, None, wall, self.integrator_for(scene))

    def _accept(self, z, where: str) -> np.ndarray:
        state, single = as_state(z, where)
        if single and not self.float32:
            self.float32 = True
            warnings.warn(f"{self.spec} returns float32 numbers: about 7 significant digits, so `identical` "
                          "(round-off of double precision) cannot pass; return float64", UserWarning, stacklevel=2)
        return state


def _shape_hint(shape: tuple, n: int) -> str:
    """What a wrong shape most likely is, for the first common slips of a whole run."""
    if len(shape) == 2 and shape[1] in (6, 7) and shape[0] in (n, n + 2):
        return (", one row short: the t = 0 row (the initial state) missing?" if shape[0] == n
                else ", one row too many: a step past the duration?")
    if len(shape) == 2 and shape[0] in (6, 7) and shape[1] == n + 1:
        return ", its transpose: a row per component instead of a row per step"
    return ""


def _non_finite(spec: str, out: np.ndarray, row: int, dt: float) -> UserFault:
    return UserFault(f"{spec} returned a non-finite state {_state_text(out[row])} at step {row} "
                     f"(t = {row * dt:.6g} s) from {_state_text(out[row - 1])} (expected 6 finite numbers {STATE})")


class WholeFunction(_Function):
    """`simulate(scene) -> array (steps + 1, 6)` (or 7 columns, the 7th the energy in J)."""

    kind = "whole"
    signature = "simulate(scene) -> array (steps + 1, 6)"
    arguments = 1
    other_flag = " (a step function? drop --whole)"

    def __init__(self, spec: str):
        super().__init__(spec)
        self.label = spec + " (whole)"

    def _run(self, scene: Scene) -> UserRun:
        self.fresh()
        n = scene.steps
        where = f"{self.spec} on scene {scene.name}"
        start = time.perf_counter()
        try:
            with user_code(where):
                value = self.function(scene_dict(scene))
        except UserCodeError:
            raise
        except NotImplementedError as exc:   # the code does not do this scene: skipped
            raise not_implemented(exc) from None
        except Exception as exc:  # noqa: BLE001
            raise UserFault(raised(where, exc)) from None
        wall = time.perf_counter() - start
        if isinstance(value, np.ndarray) and value.dtype.kind not in "fiu" or value is None:
            raise UserCodeError(f"{where} returned {_describe(value)} "
                                f"(expected an array ({n + 1}, 6) of real rows {STATE})")
        try:
            data = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise UserCodeError(f"{where} returned {_describe(value)} "
                                f"(expected an array ({n + 1}, 6) of real rows {STATE})") from None
        if data.ndim != 2 or data.shape[0] != n + 1 or data.shape[1] not in (6, 7):
            raise UserCodeError(f"{where} returned shape {data.shape}{_shape_hint(data.shape, n)} "
                                f"(expected ({n + 1}, 6): the t = 0 row, then one row per step of {STATE}; "
                                "a 7th column may hold the energy)")
        bad = _first_bad_row(data)
        if bad >= 0:
            raise UserFault(f"{where} returned a non-finite row {bad} (t = {bad * scene.dt:.6g} s): "
                            f"{_state_text(data[bad])} (expected finite numbers)")
        _check_initial(data[0, :6], scene, f"{where}: row 0")
        energy = data[:, 6].copy() if data.shape[1] == 7 else None
        return UserRun(np.ascontiguousarray(data[:, :6]), energy, wall, self.integrator_for(scene))
