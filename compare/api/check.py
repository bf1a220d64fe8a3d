"""One check's verdict on one scene, as the API gives it: a row of metrics.json `checks`, typed."""
from __future__ import annotations

from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any
from collections.abc import Mapping

# the two measured quantities of a row (metrics.json keys) and their units
QUANTITIES = (("position", "position_error_max", "tolerance_position", "m"),
              ("angle", "angle_error_max", "tolerance_angle", "rad"))


@dataclass(frozen=True)
class Check:
    """A check's row: `difference` is the largest of what it measured, in `unit`, the quantity
    (position in m or angle in rad) furthest outside, or nearest to, its `tolerance`."""

    name: str                       # step, dynamics, contact, identical, reference, native, ...
    integrator: str | None          # of the run it judges (None: none applies)
    passed: bool | None             # None: shown, not judged (`reason` says why)
    difference: float | None        # the largest difference measured, in `unit` (None: not measured)
    tolerance: float | None         # the bound it is judged against, in `unit` (None: not judged)
    unit: str                       # "m" or "rad"
    quantity: str                   # "position" or "angle"
    reason: str                     # where the tolerance comes from, or why it is not judged
    text: str = ""                  # a failed check: what the verdict line says of it
    data: Mapping[str, Any] = field(default_factory=dict, compare=False, repr=False)   # the metrics.json row

    @property
    def label(self) -> str:
        """`step (rk4)`: the name with the integrator, as the verdict line writes it."""
        return f"{self.name} ({self.integrator})" if self.integrator else self.name

    @classmethod
    def from_row(cls, row: dict) -> Check:
        """The check of a metrics.json `checks` row."""
        from ..checks.row import CheckRow
        from ..run.lines import failure_text

        quantity, _, _, unit = _largest(row)
        value_key, tolerance_key = next((v, t) for q, v, t, _ in QUANTITIES if q == quantity)
        passed = row.get("pass")
        return cls(row["name"], row.get("integrator"), passed, row.get(value_key), row.get(tolerance_key), unit,
                   quantity, row.get("reason", ""),
                   failure_text(CheckRow.from_json(row)) if passed is False else "", MappingProxyType(dict(row)))


def _largest(row: dict) -> tuple:
    """The quantity of a row to report: the one with the largest share of its tolerance; without
    tolerances, the position when it was measured."""
    def share(q):
        _, value_key, tolerance_key, _ = q
        value, tolerance = row.get(value_key), row.get(tolerance_key)
        if value is None:
            return -2.0
        if not tolerance:
            return -1.0 if q[0] == "position" else -1.5
        return value / tolerance
    return max(QUANTITIES, key=share)
