"""One check's verdict on one run: a row of metrics.json `checks` (docs/report-files.md).

    row.to_json() -> the metrics.json dict;  CheckRow.from_json(d) -> the row again (no arrays)
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

# the keys every row has, in metrics.json order (`reason` goes among the details, see reason_at)
COMMON_KEYS = ("name", "isolates", "integrator", "position_error_max", "angle_error_max",
               "tolerance_position", "tolerance_angle", "pass")


@dataclass(frozen=True)
class CheckRow:
    """A check's verdict: what it measured, its tolerance and why; `details` holds the check's
    own JSON keys (docs/report-files.md, "Extra keys"), `residual` the step check's per-step
    array for the plots (never JSON)."""

    name: str                                 # step, dynamics, contact, identical, reference, native, energy
    isolates: str                             # what the check compares, in words
    integrator: str | None = None             # of the run it judges (None: native, or none applies)
    position_error_max: float | None = None   # m (None: not measured)
    angle_error_max: float | None = None      # rad
    tolerance_position: float | None = None   # m (None: not judged)
    tolerance_angle: float | None = None      # rad
    passed: bool | None = None                # metrics.json `pass`; None: shown, not judged
    reason: str = ""                          # where the tolerance comes from, or why not judged
    details: dict[str, Any] = field(default_factory=dict)   # the check's own keys, JSON values, in order
    reason_at: int = 0                        # how many details metrics.json writes before `reason`
    residual: np.ndarray | None = field(default=None, compare=False, repr=False)
    # step: (steps, 6) |independent step - next state| (m, rad, m/s, rad/s), for the plots
    bound: np.ndarray | None = field(default=None, compare=False, repr=False)
    # step: (steps, 6) the round-off bound of each residual (same units), for the plots

    @property
    def label(self) -> str:
        """`dynamics (rk4)`: the name with the integrator."""
        return f"{self.name} ({self.integrator})" if self.integrator else self.name

    def to_json(self) -> dict:
        """The metrics.json row: the common keys, then the details with `reason` among them."""
        head = {"name": self.name, "isolates": self.isolates, "integrator": self.integrator,
                "position_error_max": self.position_error_max, "angle_error_max": self.angle_error_max,
                "tolerance_position": self.tolerance_position, "tolerance_angle": self.tolerance_angle,
                "pass": self.passed}
        items = list(self.details.items())
        return {**head, **dict(items[:self.reason_at]), "reason": self.reason, **dict(items[self.reason_at:])}

    @classmethod
    def from_json(cls, data: dict) -> CheckRow:
        """A metrics.json row read back (its key order kept)."""
        extra = [k for k in data if k not in COMMON_KEYS]
        details = {k: data[k] for k in extra if k != "reason"}
        at = extra.index("reason") if "reason" in extra else len(extra)
        return cls(data["name"], data.get("isolates", ""), data.get("integrator"), data.get("position_error_max"),
                   data.get("angle_error_max"), data.get("tolerance_position"), data.get("tolerance_angle"),
                   data.get("pass"), data.get("reason", ""), details, at)
