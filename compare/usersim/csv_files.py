"""Precomputed runs as the simulator under test: a folder of CSV files, one per scene.

    --trajectories DIR              DIR/<scene name>.csv                      TrajectoryFiles

Columns by header name (t,x,y,theta,vx,vy,omega required, energy optional), first row t = 0,
then one row per step of dt. An optional DIR/simulator.toml may name the integrator.
"""
from __future__ import annotations

import re
import tomllib
from pathlib import Path

import numpy as np

from custom_sim import Scene
from custom_sim.model import initial_state
from scene_types.state import STATE_COMPONENTS
from scene_types.trajectory import REQUIRED_COLUMNS

from ..oracle.one_step import Rounding
from .base import UserRun, _check_initial, _Simulator, declared_integrator
from .errors import UserCodeError

# A CSV's t column must equal i dt to within this fraction of dt: a row off by one step is
# off by a whole dt, and a time written with too few digits to tell steps apart is refused.
TIME_GRID_TOLERANCE = 0.01


STATE_COLUMNS = STATE_COMPONENTS
# Rows read to find how a file was written: its first and last SAMPLE_ROWS (a %g writer drops
# trailing zeros, so the most digits any sampled cell shows is the writer's count).
SAMPLE_ROWS = 200
# A decimal number as text: sign, integer digits, fraction digits, exponent.
_NUMBER = re.compile(r"[+-]?(\d*)(?:\.(\d*))?(?:[eE][+-]?\d+)?")


def rounding_of_text(text: str, columns=STATE_COLUMNS, sample: int = SAMPLE_ROWS) -> Rounding | None:
    """How a CSV's state columns were written, read off the text of their cells (the first and
    last `sample` rows): Rounding("decimals", d) when no cell has an exponent and every cell
    with a decimal point has exactly d digits after it (%.6f, %.9f: an absolute half unit);
    otherwise Rounding("significant", p), p the most significant digits any cell shows (%.8g,
    %g, exponent notation: a relative half unit); None when that is 17, a double kept exactly
    (Python's repr, %.17g). Cells without a point or exponent ("0", "1") fit any rounding and
    decide nothing; quotes around a cell are ignored. A %g file whose sampled values all share one decade
    also shows one count of decimals: it is then taken as fixed decimals, whose half unit is
    the larger of the two there."""
    lines = [line for line in text.splitlines() if line.strip()]
    if len(lines) < 2:
        return None
    header = [name.strip() for name in lines[0].split(",")]
    cols = [header.index(c) for c in columns if c in header]
    body = lines[1:]
    if len(body) > 2 * sample:
        body = body[:sample] + body[-sample:]
    decimals: set[int] = set()
    exponent = False
    significant = 0
    for line in body:
        cells = line.split(",")
        for c in cols:
            if c >= len(cells):
                continue
            cell = cells[c].strip().strip('"').strip()
            m = _NUMBER.fullmatch(cell)
            if m is None or not (m.group(1) or m.group(2)):
                continue   # not a number: read_csv has refused it already
            whole, frac = m.group(1), m.group(2)
            has_exp = "e" in cell or "E" in cell
            if frac is None and not has_exp:
                continue   # an integer: exact under any rounding
            exponent |= has_exp
            frac = frac or ""
            if not has_exp:
                decimals.add(len(frac))
            digits = (whole + frac).lstrip("0")
            significant = max(significant, len(digits))
    if not exponent and len(decimals) == 1:
        return Rounding("decimals", decimals.pop())
    if significant == 0 or significant >= 17:
        return None
    return Rounding("significant", significant)


def rounding_of_values(values: np.ndarray, sample: int = SAMPLE_ROWS) -> Rounding | None:
    """How numbers were rounded, from their values alone (no text at hand): the fewest decimals
    d and the fewest significant digits p that reproduce every sampled value; fixed decimals
    when d <= p (a %.6f file's small values show few significant digits), significant digits
    otherwise (a %g file's small values need many decimals); None at 16 or more significant
    digits (full precision)."""
    rows = values if len(values) <= 2 * sample else np.vstack([values[:sample], values[-sample:]])
    most_p = most_d = 0
    for v in np.asarray(rows, dtype=float).ravel():
        v = float(v)
        if v == 0.0 or not np.isfinite(v):
            continue
        for p in range(1, 18):
            if float(f"{v:.{p}g}") == v:
                break
        most_p = max(most_p, p)
        if most_p >= 16:
            return None
        for d in range(0, 40):
            if float(f"{v:.{d}f}") == v:
                break
        most_d = max(most_d, d)
    if most_p == 0:
        return None
    return Rounding("decimals", most_d) if most_d <= most_p else Rounding("significant", most_p)


def _initial_as_written(z0: np.ndarray, scene: Scene, rounding: Rounding | None) -> bool:
    """Whether the t = 0 row is the scene's initial state as the file's rounding writes it:
    within a half unit of it (of either value: a relative half unit scales with the value),
    plus a few ulps for reading the decimal back. %.6f writes y = 0.0497548 as 0.049755, a
    relative 4e-6 off, which the generic six-significant-digit test refuses."""
    if rounding is None:
        return False
    want = initial_state(scene)
    slack = (np.maximum(rounding.half_unit(want), rounding.half_unit(z0))
             + 4.0 * np.finfo(float).eps * np.maximum(np.abs(want), np.abs(z0)))
    return bool(np.all(np.abs(z0 - want) <= slack))


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
                data = tomllib.loads(meta.read_text(encoding="utf-8-sig"))   # a byte-order mark allowed
            except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
                raise UserCodeError(f"{meta}: is not valid TOML ({exc})") from None
            value = data.get("integrator")
            if value is not None and not isinstance(value, str):
                raise UserCodeError(f"{meta}: integrator: expected a string, got {value!r}")
            self._declared = value

    def __reduce__(self):
        return (TrajectoryFiles, (str(self.folder),))

    def integrator_for(self, scene: Scene) -> str:
        return declared_integrator(self._declared, f"{self.folder / 'simulator.toml'}: integrator", scene.integrator)

    def path(self, scene: Scene) -> Path:
        return self.folder / f"{scene.name}.csv"

    def _run(self, scene: Scene) -> UserRun:
        from custom_sim import read_csv
        from scene_types.trajectory import read_csv_text

        path = self.path(scene)
        if not path.is_file():
            raise UserCodeError(f"{path}: no such file (expected one CSV per scene run, named <scene name>.csv)")
        try:
            text = read_csv_text(path)   # UTF-8, a byte-order mark allowed; else "expected UTF-8 text"
            cols = read_csv(path, text=text)
        except ValueError as exc:  # CsvError: file, row or column, what was expected
            raise UserCodeError(str(exc)) from None
        missing = [c for c in REQUIRED_COLUMNS if c not in cols]
        if missing:
            raise UserCodeError(f"{path}: header: missing column {', '.join(missing)} "
                                f"(expected {','.join(REQUIRED_COLUMNS)}; energy optional)")
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
        states = np.column_stack([cols[c] for c in STATE_COLUMNS])
        rounding = rounding_of_text(text)
        if not _initial_as_written(states[0], scene, rounding):
            _check_initial(states[0], scene, f"{path}: row 2 (t = 0)")
        energy = cols.get("energy")
        return UserRun(states, None if energy is None else np.array(energy), None, self.integrator_for(scene),
                       rounding)


