"""A scenario's metrics.json read back, typed: what the index, the verdict lines, the API and
the exit status read (attributes, never the file's keys), and a failed step typed.

    read_summary(row)   the Summary of a metrics.json dict (the one place that reads its keys)
    StepFailure.of(row) where a step row first failed (None: it did not), and .describe()
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

from .result import SHOWN
from .row import CheckRow
from .status import Status


@dataclass(frozen=True)
class StepFailure:
    """Where a step check's run first left round-off: the step, its time (s), the contact phase
    in words, the component (x, y, theta, vx, vy, omega) and its residual and round-off bound
    in that component's unit (m, rad, m/s, rad/s)."""

    step: int
    time: float
    phase: str
    component: str
    residual: float
    bound: float

    @property
    def unit(self) -> str:
        from .step_check import UNIT_OF
        return UNIT_OF[self.component]

    @classmethod
    def of(cls, row: CheckRow) -> StepFailure | None:
        """The failure a step row records (its details' first_*), or None."""
        d = row.details
        if d.get("first_residual") is None:
            return None
        return cls(d["first_step"], d["first_time"], d["phase"], d["component"], d["first_residual"],
                   d["first_bound"])

    def over(self) -> str:
        """The component off, by how much, against its round-off."""
        return f"{self.component} off by {self.residual:.3e} {self.unit} (round-off {self.bound:.3e} {self.unit})"

    def describe(self) -> str:
        """The one way a step failure is told: what was off, then where."""
        return f"{self.over()} at step {self.step} (t = {self.time:.6g} s, {self.phase})"


@dataclass(frozen=True)
class Summary:
    """One scenario that reached a verdict, as its metrics.json holds it."""

    name: str
    status: Status
    checks: tuple[CheckRow, ...]
    simulator: str = "custom_sim"
    law: Mapping[str, Any] | None = None             # metrics.json `law`
    diagnosis: Mapping[str, Any] | None = None       # a user's simulator: which mistake explains it
    warnings: tuple[str, ...] = ()
    failed_checks: tuple[str, ...] = ()              # labels
    cache_hits: int | None = None                    # scene-only runs from the cache (None: not counted)
    cache_misses: int | None = None
    shape: str = ""                                  # the body's
    integrator: str = ""                             # the scene's
    integrator_under_test: str = ""                  # the one the simulator under test ran
    dt: float = 0.0                                  # s
    position_error_max: float | None = None          # m, against MuJoCo's own contact
    position_error_rms: float | None = None          # m
    angle_error_max: float | None = None             # rad
    wall_time_custom: float | None = None            # s, the simulator under test's stepping
    wall_time_mujoco: float | None = None            # s
    energy_balance: Mapping[str, Any] = field(default_factory=dict)   # run -> its balance (E, W, R)
    row: Mapping[str, Any] = field(default_factory=dict, compare=False, repr=False)   # the metrics.json dict

    @property
    def passed(self) -> bool:
        return self.status is Status.PASSED

    @property
    def judged(self) -> tuple[CheckRow, ...]:
        return tuple(c for c in self.checks if c.passed is not None)

    @property
    def not_judged(self) -> tuple[str, ...]:
        """The labels of the checks that could have been judged and were not."""
        return tuple(c.label for c in self.checks if c.passed is None and c.name not in SHOWN)


def read_summary(row: Mapping[str, Any]) -> Summary:
    """The Summary of a metrics.json dict (a scenario's, as result.metrics_json wrote it, with
    `run`'s `cache` counts where it added them)."""
    if isinstance(row, Summary):
        return row
    status = row.get("status") or ("pass" if row["pass"] else "FAIL")
    cache = row.get("cache")
    return Summary(row["name"], Status.of(status), tuple(CheckRow.from_json(c) for c in row["checks"]),
                   row.get("simulator", "custom_sim"), row.get("law"), row.get("diagnosis"),
                   tuple(row.get("warnings", ())), tuple(row.get("failed_checks", ())),
                   None if cache is None else cache["hits"], None if cache is None else cache["misses"],
                   row.get("shape", ""), row.get("integrator", ""),
                   row.get("integrator_under_test", row.get("integrator", "")), row.get("dt", 0.0),
                   row.get("position_error_max"), row.get("position_error_rms"), row.get("angle_error_max"),
                   row.get("wall_time_custom"), row.get("wall_time_mujoco"), row.get("energy_balance", {}),
                   MappingProxyType(dict(row)))
