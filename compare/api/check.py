"""One check's verdict on one scene, as the API gives it: a row of metrics.json `checks`, typed."""
from __future__ import annotations

from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any
from collections.abc import Mapping

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
        return cls.of(CheckRow.from_json(row))

    @classmethod
    def of(cls, row) -> Check:
        """The check of a CheckRow (compare/checks/row.py), read by attribute."""
        from ..run.lines import failure_text

        quantity, value, tolerance, unit = _largest(row)
        return cls(row.name, row.integrator, row.passed, value, tolerance, unit, quantity, row.reason,
                   failure_text(row) if row.passed is False else "", MappingProxyType(row.to_json()))


def _largest(row) -> tuple:
    """(quantity, value, tolerance, unit) of a CheckRow to report: the quantity with the largest
    share of its tolerance; without tolerances, the position when it was measured."""
    measured = (("position", row.position_error_max, row.tolerance_position, "m"),
                ("angle", row.angle_error_max, row.tolerance_angle, "rad"))

    def share(q):
        quantity, value, tolerance, _ = q
        if value is None:
            return -2.0
        if not tolerance:
            return -1.0 if quantity == "position" else -1.5
        return value / tolerance
    return max(measured, key=share)
