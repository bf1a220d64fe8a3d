"""Precomputed runs as the simulator under test: a folder of CSV files, one per scene.

    --trajectories DIR              DIR/<scene name>.csv                      TrajectoryFiles

Columns by header name (t,x,y,theta,vx,vy,omega required, energy optional), first row t = 0,
then one row per step of dt. An optional DIR/simulator.toml may name the integrator.
"""
from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np

from custom_sim import Scene

from .base import UserRun, _check_initial, _Simulator
from .errors import UserCodeError

# A CSV's t column must equal i dt to within this fraction of dt: a row off by one step is
# off by a whole dt, and a time written with too few digits to tell steps apart is refused.
TIME_GRID_TOLERANCE = 0.01


def written_digits(values: np.ndarray, sample: int = 200) -> int | None:
    """Significant digits a CSV's numbers were written with: the fewest that reproduce every
    sampled value exactly (None: 17, full double precision)."""
    rows = values if len(values) <= 2 * sample else np.vstack([values[:sample], values[-sample:]])
    most = 0
    for v in rows.ravel():
        v = float(v)
        if v == 0.0:
            continue
        for p in range(1, 18):
            if float(f"{v:.{p}g}") == v:
                break
        most = max(most, p)
        if most >= 16:
            return None
    return most or None


class TrajectoryFiles(_Simulator):
    """Precomputed runs: DIR/<scene name>.csv, columns by header name (t,x,y,theta,vx,vy,omega
    required; energy optional), first row t = 0, then one row per step of dt."""

    kind = "trajectories"
    reruns = False

    def __init__(self, folder: str):
        self.folder = Path(folder)
        self.label = f"{folder}/<scene>.csv"
        if not self.folder.is_dir():
            raise UserCodeError(f"--trajectories {folder}: no such folder (expected a folder of <scene name>.csv files)")
        self._declared = None
        meta = self.folder / "simulator.toml"
        if meta.is_file():
            try:
                data = tomllib.loads(meta.read_text(encoding="utf-8"))
            except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
                raise UserCodeError(f"{meta}: is not valid TOML ({exc})") from None
            value = data.get("integrator")
            if value is not None and not isinstance(value, str):
                raise UserCodeError(f"{meta}: integrator: expected a string, got {value!r}")
            self._declared = value

    def __reduce__(self):
        return (TrajectoryFiles, (str(self.folder),))

    def integrator_for(self, scene: Scene) -> str:
        return self._declared or scene.integrator

    def path(self, scene: Scene) -> Path:
        return self.folder / f"{scene.name}.csv"

    def _run(self, scene: Scene) -> UserRun:
        from custom_sim import read_csv

        path = self.path(scene)
        if not path.is_file():
            raise UserCodeError(f"{path}: no such file (expected one CSV per scene run, named <scene name>.csv)")
        try:
            cols = read_csv(path)
        except ValueError as exc:  # CsvError: file, row or column, what was expected
            raise UserCodeError(str(exc)) from None
        missing = [c for c in ("t", "x", "y", "theta", "vx", "vy", "omega") if c not in cols]
        if missing:
            raise UserCodeError(f"{path}: header: missing column {', '.join(missing)} "
                                "(expected t,x,y,theta,vx,vy,omega; energy optional)")
        t = cols["t"]
        n, dt = scene.steps, scene.dt
        slack = TIME_GRID_TOLERANCE * dt
        if abs(t[0]) > slack:
            hint = " (the t = 0 row, the initial state, is missing)" if abs(t[0] - dt) <= slack else ""
            raise UserCodeError(f"{path}: row 2 (first data row): t = {t[0]:.10g} s{hint} "
                                "(expected the first row at t = 0, the initial state)")
        grid = np.arange(len(t)) * dt
        off = np.flatnonzero(np.abs(t - grid) > slack)
        if off.size:
            i = int(off[0])
            raise UserCodeError(f"{path}: row {i + 2}, column t: {t[i]:.10g} s is not on the scene's time grid "
                                f"(expected t = {i} x dt = {grid[i]:.10g} s within {slack:.2g} s, dt = {dt:g} s)")
        if len(t) != n + 1:
            raise UserCodeError(f"{path}: {len(t)} data rows, t up to {t[-1]:.10g} s (expected {n + 1} rows: "
                                f"t = 0 to {n * dt:.10g} s = duration {scene.duration:g} s in steps of {dt:g} s)")
        states = np.column_stack([cols[c] for c in ("x", "y", "theta", "vx", "vy", "omega")])
        _check_initial(states[0], scene, f"{path}: row 2 (t = 0)")
        energy = cols.get("energy")
        return UserRun(states, None if energy is None else np.array(energy), None, self.integrator_for(scene),
                       written_digits(states))


