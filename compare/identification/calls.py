"""The user's step called from designed states, inside usersim's guard: every fault is one line."""
from __future__ import annotations

import contextlib

import numpy as np

from ..usersim.base import STATE, _state_text
from ..usersim.errors import UserCodeError, UserFault, not_implemented, one_line
from ..usersim.functions import StepFunction, as_state
from ..usersim.guard import user_code
from ..usersim.scene_dict import scene_dict


class StepCalls:
    """A step function called from the states identification designs, from a fresh import of
    its module (as every scene's run starts). A step that raises, returns anything but 6 real
    numbers, or returns a non-finite state is bad input: UserCodeError naming the function, the
    probe, the state and the step (one line, no traceback); one that raises NotImplementedError
    does not do the scene: SceneSkipped.

    Each call runs inside usersim's guard; `session()` holds one guard around many calls (the
    guard puts numpy's error state, the working folder and matplotlib's settings back when it
    is left: with matplotlib loaded that costs 1.7 ms, more than the step)."""

    def __init__(self, simulator: StepFunction, scene):
        simulator.fresh()
        self.simulator = simulator
        self.scene_d = scene_dict(scene)
        self.count = 0
        self._where = ""
        self._inside = False

    @contextlib.contextmanager
    def session(self):
        """Calls inside share one guard (the error names the call that failed)."""
        if self._inside:
            yield
            return
        try:
            with user_code(lambda: self._where):
                self._inside = True
                yield
        except UserCodeError as exc:
            raise UserCodeError(str(exc)) from None
        finally:
            self._inside = False

    def one(self, z0, h: float, what: str) -> np.ndarray:
        """The step from z0 (6,) with step h (s)."""
        self.count += 1
        where = self._where = (f"{self.simulator.spec} called by identify ({what}) from state {_state_text(z0)} "
                               f"with dt = {h:.6g} s")
        with self.session():
            try:
                out = self.simulator.function(np.array(z0, dtype=float), self.scene_d, float(h))
            except NotImplementedError as exc:   # the step does not do this scene: skipped
                raise not_implemented(exc) from None
            except UserFault as exc:   # a process's fault (process.py): its one line, with the probe
                raise UserCodeError(f"{where}: {exc}") from None
            except Exception as exc:  # noqa: BLE001 - any fault of the user's step is bad input here
                raise UserCodeError(f"{where} raised {one_line(exc)}") from None
        z1, _ = as_state(out, where)
        if not np.all(np.isfinite(z1)):
            raise UserCodeError(f"{where} returned a non-finite state {_state_text(z1)} (expected 6 finite numbers "
                                f"{STATE})")
        return z1

    def many(self, Z0: np.ndarray, H, what: str) -> np.ndarray:
        """One step from every row of Z0 (n, 6); H a step per row or one for all."""
        Z0 = np.atleast_2d(Z0)
        H = np.broadcast_to(np.asarray(H, dtype=float), (len(Z0),))
        with self.session():
            return np.array([self.one(z, h, f"{what}, probe {i + 1} of {len(Z0)}")
                             for i, (z, h) in enumerate(zip(Z0, H))])
