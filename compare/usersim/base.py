"""What every way in gives the harness: a UserRun of states, and the simulator's common face."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from custom_sim import Scene
from custom_sim.model import initial_state

from .errors import UserCodeError

STATE = "[x, y, theta, vx, vy, omega]"
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


def _first_bad_row(states: np.ndarray) -> int:
    bad = np.flatnonzero(~np.all(np.isfinite(states), axis=1))
    return int(bad[0]) if bad.size else -1


def _state_text(z) -> str:
    return "[" + ", ".join(f"{v:.6g}" for v in z) + "]"


def _check_initial(z0: np.ndarray, scene: Scene, where: str) -> None:
    want = initial_state(scene)
    if not np.allclose(z0, want, rtol=INITIAL_STATE_RTOL, atol=INITIAL_STATE_ATOL):
        raise UserCodeError(f"{where} is {_state_text(z0)}, not the scene's initial state "
                            f"{_state_text(want)} (expected the t = 0 row to be the initial state)")


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


