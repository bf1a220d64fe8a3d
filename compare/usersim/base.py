"""What every way in gives the harness: a UserRun of states, and the simulator's common face."""
from __future__ import annotations

import difflib
from dataclasses import dataclass

import numpy as np

from custom_sim import INTEGRATORS, Scene
from custom_sim.model import initial_state
from scene_types.state import STATE_TEXT

from ..oracle.one_step import Rounding
from .errors import SceneSkipped, UserCodeError

STATE = STATE_TEXT   # "[x, y, theta, vx, vy, omega]", in messages
# The CSV's t = 0 row must be the scene's initial state to this relative precision (or
# absolute, m and m/s, near zero): six significant digits, the least any writer keeps.
INITIAL_STATE_RTOL = 1e-6
INITIAL_STATE_ATOL = 1e-9


@dataclass(frozen=True)
class UserRun:
    """One scene run by the user's simulator.

    states (steps + 1, 6); energy (steps + 1,) J or None when not supplied; wall_time s
    (None: not known, a CSV); integrator: the one the simulator names; rounding: how the
    states were written (a CSV: compare.oracle.one_step.Rounding, fixed decimals or
    significant digits, found from the file's text), None for full double precision."""

    states: np.ndarray
    energy: np.ndarray | None
    wall_time: float | None
    integrator: str
    rounding: Rounding | None = None


OTHER = "other:"   # INTEGRATOR = "other:ode23": an integrator the harness does not know, on purpose


def declared_integrator(value, where: str, default: str) -> str:
    """The integrator a simulator declares (`where` names the field): one the harness knows,
    "other:NAME" on purpose, or None for the scene's. Anything else is bad input naming the
    closest known name: a misspelling must not turn the integrator's checks off. default: the
    scene's integrator, for a simulator that declares none."""
    if value is None:
        return default
    if not isinstance(value, str):
        raise UserCodeError(f"{where}: expected a string naming an integrator, got {value!r}")
    if value in INTEGRATORS or (value.startswith(OTHER) and value[len(OTHER):].strip()):
        return value
    spelled = value.strip().lower().replace("-", "_").replace(" ", "_")
    close = difflib.get_close_matches(spelled, list(INTEGRATORS), n=1, cutoff=0.5)
    hint = f"; the closest is {close[0]!r}" if close else ""
    raise UserCodeError(f"{where} = {value!r}: not an integrator the harness knows (expected one of "
                        f"{', '.join(INTEGRATORS)}, or \"{OTHER}NAME\" for one it does not know, e.g. "
                        f"\"{OTHER}ode23\"{hint})")


def known_integrator(integrator: str | None) -> bool:
    """Whether the harness can step this integrator itself (step, identical, dynamics)."""
    return integrator in INTEGRATORS


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
    """What every way in answers: run(scene) -> UserRun, integrator_for(scene), skip_reason(scene),
    close(), and for the report: name, integrator (of the scene last run).

    reruns: whether it can run a scene it was not given files for (a variant the harness
    derives, e.g. friction switched off): True for functions, False for a folder of CSVs."""

    kind = ""
    label = ""
    reruns = True
    _scene = None

    @property
    def name(self) -> str:
        return self.label

    def integrator_for(self, scene: Scene) -> str:
        """The integrator the simulator runs `scene` with: the one it declares, else the scene's."""
        raise NotImplementedError

    def _run(self, scene: Scene) -> UserRun:
        """One run of `scene` by the user's code (each way in has its own)."""
        raise NotImplementedError

    @property
    def integrator(self) -> str | None:
        """The integrator of the scene last run (declared, or that scene's)."""
        return None if self._scene is None else self.integrator_for(self._scene)

    def skip_reason(self, scene: Scene) -> str | None:
        """Why this simulator says it does not do `scene` before running it (a module's SHAPES),
        or None."""
        return None

    def run(self, scene: Scene) -> UserRun:
        """The scene's run; SceneSkipped (before any call of the user's code) for a scene the
        simulator says it does not do."""
        reason = self.skip_reason(scene)
        if reason:
            raise SceneSkipped(reason)
        self._scene = scene
        return self._run(scene)

    def close(self) -> None:
        """End whatever the simulator keeps running between calls (a process); a function keeps
        nothing."""


