"""Writing the report: the umask's permissions (not mkstemp's 0600 and mkdtemp's 0700), JSON that
never holds NaN or infinity and never raises on them, and the stability warning said once."""
from __future__ import annotations

import dataclasses
import json
import math
import os
import stat
from types import SimpleNamespace

import numpy as np
import pytest

from compare import files as atomic
from compare.report import pages


@pytest.fixture(params=[0o022, 0o027], ids=["umask022", "umask027"])
def umask(request):
    old = os.umask(request.param)
    try:
        yield request.param
    finally:
        os.umask(old)


def mode(path) -> int:
    return stat.S_IMODE(os.stat(path).st_mode)


def test_the_umask_is_read_without_changing_it(umask):
    assert atomic.current_umask() == umask
    assert atomic.current_umask() == umask


def test_an_atomic_file_and_a_temporary_folder_get_the_umask_permissions(tmp_path, umask):
    path = tmp_path / "index.md"
    atomic.write_text_atomically(path, "one\n")
    atomic.write_text_atomically(path, "two\n")   # replacing keeps the mode open() would give
    assert path.read_text() == "two\n" and mode(path) == 0o666 & ~umask
    folder = atomic.temporary_folder(tmp_path, ".scene.")
    assert folder.parent == tmp_path and folder.name.startswith(".scene.") and mode(folder) == 0o777 & ~umask
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([folder.name, "index.md"]), "no temporary left"


def test_the_index_is_written_with_the_umask_permissions(tmp_path, umask):
    path = pages.write_index(tmp_path, [], [])
    assert path.read_text().startswith("# ") and mode(path) == 0o666 & ~umask


def _stub_report(monkeypatch, data):
    """write_scenario with its content stubbed: only its folder, its files and metrics.json."""
    monkeypatch.setattr(pages, "metrics_json", lambda result: data)
    monkeypatch.setattr(pages, "run_csv", lambda case, which: "t\n0\n")
    monkeypatch.setattr(pages.metrics, "differences", lambda a, b: None)
    monkeypatch.setattr(pages.plots, "draw_all", lambda figures, warnings: {}, raising=False)
    for name in ("states", "path_in_plane", "error", "energy", "snapshots", "step_residuals"):
        monkeypatch.setattr(pages.plots, name, lambda *a, **k: None)
    monkeypatch.setattr(pages, "scenario_page", lambda result, data, figures: "# page\n")
    run = SimpleNamespace()
    return SimpleNamespace(scene=SimpleNamespace(name="huge"), custom=run, mujoco=SimpleNamespace(), case=None,
                           under_test=run, residuals={}, checks=[], reference=None, warnings=[])


def test_a_scenario_folder_gets_the_umask_permissions(tmp_path, monkeypatch, umask):
    result = _stub_report(monkeypatch, {"name": "huge", "pass": True})
    pages.write_scenario(result, tmp_path, "<mujoco/>")
    folder = tmp_path / "huge"
    assert mode(folder) == 0o777 & ~umask
    for path in folder.iterdir():
        assert mode(path) == 0o666 & ~umask, path.name
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]


def test_metrics_json_holds_no_infinity_and_says_which_numbers_were_not_finite(tmp_path, monkeypatch):
    """A user's states of 1e308 make the derived errors inf: metrics.json is still written, as
    JSON (null where a number was not finite), and lists those numbers under non_finite."""
    user_x, custom_x = 1e308, -1e308
    data = {"name": "huge", "pass": False, "position_error_max": user_x - custom_x,   # inf
            "energy_drift_custom": float("-inf"), "angle_error_max": np.float64("nan"),
            "checks": [{"name": "step", "tolerance_position": 1e-15, "position_error_max": math.inf}],
            "events_custom": {"bounce_apex_heights": (0.25, float("nan"))}, "dt": 5e-5}
    result = _stub_report(monkeypatch, data)
    assert pages.write_scenario(result, tmp_path, "<mujoco/>") is data
    text = (tmp_path / "huge" / "metrics.json").read_text()
    written = json.loads(text, parse_constant=lambda c: pytest.fail(f"{c} written to metrics.json"))
    assert written["position_error_max"] is None and written["energy_drift_custom"] is None
    assert written["angle_error_max"] is None and written["checks"][0]["position_error_max"] is None
    assert written["checks"][0]["tolerance_position"] == 1e-15 and written["dt"] == 5e-5
    assert written["events_custom"]["bounce_apex_heights"] == [0.25, None]
    assert written["non_finite"] == [
        {"key": "position_error_max", "value": "inf"}, {"key": "energy_drift_custom", "value": "-inf"},
        {"key": "angle_error_max", "value": "nan"}, {"key": "checks[0].position_error_max", "value": "inf"},
        {"key": "events_custom.bounce_apex_heights[1]", "value": "nan"}]
    assert data["position_error_max"] == math.inf, "the caller's data is not changed"


def test_finite_json_leaves_finite_data_as_json_dumps_writes_it():
    data = {"a": 1.5, "b": [1, 2.0, None, True], "c": {"d": "x"}, "e": np.float64(2.5), "f": np.int64(3),
            "g": np.array([1.0, 2.0]), "h": (1, 2)}
    text = atomic.finite_json(data, indent=2)
    assert json.loads(text) == {"a": 1.5, "b": [1, 2.0, None, True], "c": {"d": "x"}, "e": 2.5, "f": 3,
                                "g": [1.0, 2.0], "h": [1, 2]}
    assert "non_finite" not in text
    assert atomic.finite_json([math.inf, 1.0]) == "[null, 1.0]"


def test_the_stability_warning_does_not_say_warning_itself():
    """run prints "warning: " + the line; the line itself must not start with it again."""
    from compare.scenarios import load
    from custom_sim.stability import warning

    scene = dataclasses.replace(load("point_drop"), dt=2e-4)   # above its friction limit, 9.5e-5 s
    line = warning(scene)
    assert line is not None and line.startswith("point_drop: dt = 0.0002 s is outside the stability limit")
    assert not line.lower().startswith("warning")
