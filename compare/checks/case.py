"""A scenario's case: the scene resolved once, and every run the checks share, computed once.

Every check of a scenario takes the case (as MuJoCo's stages take mjModel) instead of the
scene, and asks it for what it needs:

    case.props                       custom_sim's mass properties and contact points
    case.equations                   the independent oracle's right-hand side and geometry
    case.trajectory(integrator)      custom_sim's run of the scene (the scene's own: integrator None)
    case.states(scene, integrator, dt)   custom_sim's states of a variant (friction off, another
                                     law, another step), without the chatter watch
    case.reference()                 the converged reference at the scene's step
    case.mujoco(solref)              MuJoCo's native twin with that solref mapping
    case.envelope(integrator)        the round-off envelope of custom_sim's run (check identical)

A function of the case alone (a CSV file of its runs, their energy balance) is cached with the
case as its argument: the case is keyed by its scene. Each is computed on first use and kept;
a failure (a divergence) is kept too and raised again, so no run is repeated to get its exception back.
"""
from __future__ import annotations

import dataclasses
from functools import cached_property

import numpy as np

from custom_sim import Scene, SimulationDiverged, mass_properties, simulate

from ..store import cached


class Case:
    """One scene and the runs its checks share (module docstring)."""

    def __init__(self, scene: Scene):
        self.scene = scene
        self._memo: dict = {}

    def __getstate__(self) -> dict:
        """A case pickles as its scene alone, without its runs: so it is keyed in the cache of
        scene-only work (compare/store.py) by its scene, as a scene is."""
        return {"scene": self.scene, "_memo": {}}

    def _once(self, key, compute):
        """compute() the first time `key` is asked for; its result, or its exception, after."""
        if key not in self._memo:
            try:
                self._memo[key] = (True, compute())
            except (SimulationDiverged, _mujoco_diverged(), _no_reference()) as exc:
                self._memo[key] = (False, exc)
        ok, value = self._memo[key]
        if not ok:
            raise value
        return value

    @cached_property
    def props(self):
        return mass_properties(self.scene.body)

    @cached_property
    def equations(self):
        from ..oracle.reference import Equations
        return Equations.from_scene(self.scene)

    def variant(self, integrator: str | None = None) -> Scene:
        """The scene with another integrator (None: its own)."""
        if integrator is None or integrator == self.scene.integrator:
            return self.scene
        return dataclasses.replace(self.scene, integrator=integrator)

    def trajectory(self, integrator: str | None = None):
        """custom_sim's run (simulate) with this integrator at the scene's dt. Raises
        SimulationDiverged (or SimulationChattered)."""
        scene = self.variant(integrator)
        return self._once(("simulate", scene), lambda: cached(simulate)(scene))

    def states(self, scene: Scene, integrator: str, dt: float) -> np.ndarray:
        """custom_sim's states of `scene` (a variant of this case's) at (integrator, dt), as
        sensitivity.run_states computes them. The case's own scene at its own step is its run."""
        from .sensitivity import run_states

        if scene == self.scene and dt == scene.dt:
            try:
                return self.trajectory(integrator).states()
            except SimulationDiverged:
                pass   # simulate also stops on chatter; run_states does not
        return self._once(("states", scene, integrator, dt), lambda: cached(run_states)(scene, integrator, dt))

    def reference(self):
        """The converged reference (oracle.reference.solve_reference) at the scene's step.
        Raises its ReferenceFailed."""
        from ..oracle.reference import solve_reference
        scene = self.scene
        return self._once(("reference",), lambda: cached(solve_reference)(scene, np.arange(scene.steps + 1) * scene.dt))

    def mujoco(self, solref: str):
        """MuJoCo's native twin with this solref mapping. Raises MujocoDiverged."""
        from mujoco_models import simulate_mujoco
        return self._once(("mujoco", solref), lambda: cached(simulate_mujoco)(self.scene, solref=solref))

    def envelope(self, integrator: str | None = None):
        """The round-off envelope of custom_sim's run with this integrator (roundoff.py)."""
        from .roundoff import roundoff_envelope
        scene = self.variant(integrator)
        return self._once(("envelope", scene),
                          lambda: cached(roundoff_envelope)(scene, self.trajectory(integrator).states()))


def as_case(scene: Scene, case: Case | None = None) -> Case:
    """The caller's case, or one of the scene's own (a check called alone, as the tests do)."""
    return case if case is not None else Case(scene)


def _mujoco_diverged():
    from mujoco_models import MujocoDiverged
    return MujocoDiverged


def _no_reference():
    from ..oracle.reference import ReferenceFailed
    return ReferenceFailed
