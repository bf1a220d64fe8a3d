"""The simulator under test from what a Python caller names: "MODULE:FUNCTION", a function
object, or a simulator object already made (compare.Process("COMMAND"), compare.usersim's)."""
from __future__ import annotations

import sys

from ..usersim import UserCodeError
from ..usersim.functions import StepFunction, WholeFunction, declared_shapes


def _name(fn) -> str:
    """How a function object is named in the harness's messages: module.qualname."""
    module = getattr(fn, "__module__", None) or "?"
    return f"{module}.{getattr(fn, '__qualname__', None) or getattr(fn, '__name__', None) or type(fn).__name__}"


class _Callable:
    """A function object given directly: called as it is (its module is not imported again, so
    state a closure keeps is the caller's to reset; every scene still runs in a process of its
    own). A module-level INTEGRATOR and SHAPES of the function's module are read as --sim reads them."""

    def __init__(self, fn):
        self.fn = fn
        self.spec = _name(fn)
        self.label = self.spec
        self.fresh()
        self._check_arguments()

    def fresh(self) -> None:
        self.function = self.fn
        self.module = sys.modules.get(getattr(self.fn, "__module__", None) or "") or _NoModule()
        self.shapes = declared_shapes(getattr(self.module, "SHAPES", None), f"{self.spec}: SHAPES")

    def __reduce__(self):   # `run` forks its scene processes (nothing pickled); a spawned pool cannot take it
        raise TypeError(f"{self.spec}: a function object cannot be sent to another process; "
                        "give it as \"MODULE:FUNCTION\" instead")


class _NoModule:
    """The module of a function that has none (built in a notebook's cell, a lambda): no INTEGRATOR, no SHAPES."""


class CallableStep(_Callable, StepFunction):
    """step(state, scene, dt) -> state, a function object."""


class CallableWhole(_Callable, WholeFunction):
    """simulate(scene) -> array (steps + 1, 6), a function object."""

    def __init__(self, fn):
        super().__init__(fn)
        self.label = self.spec + " (whole)"


def simulator_of(sim, whole: bool = False):
    """The simulator under test `sim` names (None: custom_sim). Bad input (a module that does not
    load, a function that cannot take the arguments) raises UserCodeError, before anything runs."""
    if sim is None:
        if whole:
            raise UserCodeError("whole=True: expected it with sim (a simulate(scene) function)")
        return None
    if isinstance(sim, str):
        return WholeFunction(sim) if whole else StepFunction(sim)
    if hasattr(sim, "kind") and hasattr(sim, "run") and hasattr(sim, "integrator_for"):
        if whole:
            raise UserCodeError(f"whole=True: {type(sim).__name__} is a simulator already (expected whole only "
                                "with a simulate function)")
        return sim
    if callable(sim):
        return CallableWhole(sim) if whole else CallableStep(sim)
    raise UserCodeError(f"sim = {sim!r}: expected \"MODULE:FUNCTION\", a function (step(state, scene, dt), or "
                        "with whole=True simulate(scene)), or compare.Process(\"COMMAND\")")
