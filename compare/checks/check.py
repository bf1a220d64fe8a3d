"""What a check is: the Check protocol every check follows, and Runs, what the checks of one
scenario judge (collected and validated once, compare/run/scenario.py collect_runs).

A check (one per registry line, compare/checks/registry.py) keeps to four rules:

    1. `name` is the word of its metrics.json rows (`step`, `dynamics`, ...);
    2. `needs` names what it needs beyond the run under test and custom_sim ("mujoco", the
       twin; "reference", the converged solution): `validate` runs the checks needing neither;
    3. `applies(runs)` says whether it has anything to judge on these runs (no rows otherwise);
    4. `judge(runs)` returns its rows (row.py), and never validates the runs again: Runs holds
       states already known to have the scene's shape and to be finite.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, Protocol

from custom_sim import Scene, Trajectory

from .case import Case
from .row import CheckRow


class Check(Protocol):
    """One check (module docstring, the four rules)."""

    name: str
    needs: frozenset[str]

    def applies(self, runs: Runs) -> bool: ...

    def judge(self, runs: Runs) -> list[CheckRow]: ...


@dataclass(frozen=True)
class Twins:
    """MuJoCo's own contact with each solref mapping, measured against the run under test."""

    by_mapping: dict            # mapping -> metrics.compare row (with its drift and wall time), or {"error": why}
    mujoco: Trajectory          # the scene's own mapping: the native check's and the report's twin
    metrics: dict               # that twin's metrics.compare row


@dataclass(frozen=True)
class Runs:
    """What the checks of one scenario judge: the scene's case, the run under test, the runs
    judged by integrator (custom_sim's four, or the user's one), custom_sim's four, and the
    user's simulator (None: custom_sim is under test)."""

    case: Case
    under_test: Trajectory
    tested: Mapping[str, Trajectory | str]     # integrator -> run judged, or its divergence text
    custom: Mapping[str, Trajectory | str]     # custom_sim by integrator: run or divergence text
    simulator: Any = None                      # compare.usersim's simulator under test, or None
    keeps_state: str | None = field(default=None, compare=False)   # a step that depends on earlier calls

    @property
    def scene(self) -> Scene:
        return self.case.scene

    @property
    def user(self) -> bool:
        """A user's simulator is under test (not custom_sim)."""
        return self.simulator is not None

    @cached_property
    def twins(self) -> Twins:
        """MuJoCo's twins, the scene's own mapping first (computed on first use, once)."""
        from custom_sim import SimulationDiverged
        from mujoco_models import MujocoDiverged
        from scene_types.schema import SOLREF_MAPPINGS

        from . import metrics

        own = self.scene.mujoco.solref
        by_mapping: dict[str, dict] = {}
        native: Trajectory | None = None
        for mapping in (own,) + tuple(m for m in SOLREF_MAPPINGS if m != own):
            try:
                twin = self.case.mujoco(mapping)
            except (SimulationDiverged, MujocoDiverged) as exc:   # shown in the mappings table
                by_mapping[mapping] = {"error": str(exc)}
                continue
            row = metrics.compare(self.under_test, twin)
            row["energy_drift_mujoco"] = metrics.energy_drift(twin)
            row["wall_time_mujoco"] = twin.wall_time
            by_mapping[mapping] = row
            if mapping == own:
                native = twin
        if native is None:
            raise RuntimeError(by_mapping[own]["error"])
        return Twins(by_mapping, native, by_mapping[own])
