"""The check row: frozen, and its JSON form the metrics.json row docs/report-files.md documents."""
import dataclasses
import re
from pathlib import Path

import numpy as np
import pytest

from compare.checks.row import CheckRow

DOCS = Path(__file__).resolve().parents[3] / "docs" / "report-files.md"


def documented_keys() -> list[str]:
    """The keys of the table under "Every row has these keys" in docs/report-files.md."""
    text = DOCS.read_text().split("Every row has these keys:", 1)[1]
    table = text.strip().split("\n\n", 1)[0].splitlines()[2:]   # the rows after the header
    return [key for line in table for key in re.findall(r"`(\w+)`", line.split("|")[1])]


def test_a_row_is_frozen():
    row = CheckRow("step", "one step", "rk4", passed=True)
    with pytest.raises(dataclasses.FrozenInstanceError):
        row.passed = False
    assert dataclasses.replace(row, passed=False).passed is False and row.passed is True


def test_its_json_has_exactly_the_documented_keys_in_their_order():
    keys = documented_keys()
    assert keys == ["name", "isolates", "integrator", "position_error_max", "angle_error_max",
                    "tolerance_position", "tolerance_angle", "pass", "reason"]
    assert list(CheckRow("native", "MuJoCo's own contact").to_json()) == keys


def test_details_keep_their_place_around_the_reason_and_arrays_stay_out():
    row = CheckRow("step", "one step", "rk4", 1e-17, 0.0, 1e-15, 1e-15, False, "round-off",
                   {"first_step": 3, "phase": "flight", "failing_steps": 2}, reason_at=2,
                   residual=np.ones((4, 6)))
    data = row.to_json()
    assert list(data)[7:] == ["pass", "first_step", "phase", "reason", "failing_steps"]
    assert "residual" not in data and row.label == "step (rk4)"
    back = CheckRow.from_json(data)
    assert back == row and back.residual is None and list(back.to_json()) == list(data)
