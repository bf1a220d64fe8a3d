"""The trajectory type both simulators return, and its CSV file: header row, then the initial
state (t = 0) and the state after each step, columns t,x,y,theta,vx,vy,omega,energy."""
from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .errors import CsvError
from .state import STATE_COMPONENTS

CSV_COLUMNS = ("t", *STATE_COMPONENTS, "energy")
REQUIRED_COLUMNS = CSV_COLUMNS[:7]   # energy (and any other column) is optional when reading
CSV_FORMAT = "%.10g"                 # 10 significant digits: a relative rounding of at most 5e-10
CSV_RELATIVE_ROUNDING = 5e-10        # what a write-then-read round trip may change, relative
_UTF8_BOM = b"\xef\xbb\xbf"
# other encodings' byte-order marks (UTF-32 before UTF-16: FF FE 00 00 starts with FF FE)
_OTHER_BOMS = ((b"\xff\xfe\x00\x00", "UTF-32"), (b"\x00\x00\xfe\xff", "UTF-32"),
               (b"\xff\xfe", "UTF-16"), (b"\xfe\xff", "UTF-16"))


@dataclass(frozen=True)
class Trajectory:
    """States of the centre of mass in the scene's 2D frame, row 0 the initial state (t = 0),
    row i the state after step i. Arrays have shape (steps + 1,).

    Units: t s; x, y m; theta rad (counter-clockwise); vx, vy m/s; omega rad/s; energies J.
    energy = kinetic + gravitational (m g y) + elastic contact (sum of k d^2 / 2).
    """

    t: np.ndarray
    x: np.ndarray
    y: np.ndarray
    theta: np.ndarray
    vx: np.ndarray
    vy: np.ndarray
    omega: np.ndarray
    energy_kinetic: np.ndarray
    energy_gravity: np.ndarray
    energy_contact: np.ndarray
    simulator: str = "custom"
    integrator: str = ""
    dt: float = 0.0
    force_evals: int = 0          # evaluations of the force law (RK4: 4 per step, ...)
    newton_iterations: int = 0    # implicit Euler only: Newton iterations over the run
    wall_time: float = 0.0        # s, the time-stepping loop alone
    meta: dict = field(default_factory=dict)

    @property
    def energy(self) -> np.ndarray:
        return self.energy_kinetic + self.energy_gravity + self.energy_contact

    @property
    def steps(self) -> int:
        return len(self.t) - 1

    def states(self) -> np.ndarray:
        """(steps + 1, 6) array of the STATE_COMPONENTS (scene_types/state.py), in their order."""
        return np.column_stack([getattr(self, c) for c in STATE_COMPONENTS])


def csv_text(traj: Trajectory) -> str:
    """The CSV file of a trajectory: header row, then one row per state: the initial state
    (t = 0), then the state after each step (t = dt, 2 dt, ...), so row i of the file is row i
    of the Trajectory. Raises ValueError for a non-finite value."""
    rows = np.column_stack([getattr(traj, c) if c != "energy" else traj.energy for c in CSV_COLUMNS])
    if not np.all(np.isfinite(rows)):
        raise ValueError("refusing to write non-finite values to a CSV file")
    # one format operation for the whole table (formatted in C): a loop over rows took 10 % of a run
    line = ",".join([CSV_FORMAT] * rows.shape[1]) + "\n"
    return ",".join(CSV_COLUMNS) + "\n" + (line * rows.shape[0]) % tuple(rows.ravel().tolist())


def write_csv(traj: Trajectory, path: str | Path) -> None:
    """Write csv_text(traj) as the file path (a non-finite value: ValueError naming it)."""
    try:
        text = csv_text(traj)
    except ValueError:
        raise ValueError(f"refusing to write non-finite values to {path}") from None
    Path(path).write_text(text, encoding="utf-8")


def read_csv_text(path: str | Path) -> str:
    """The text of a CSV file: UTF-8, with or without a byte-order mark (Excel and Windows
    tools write one). Raises CsvError naming the file for a file that cannot be read, or that
    is not UTF-8 text (UTF-16 or UTF-32, with or without its mark, or any other encoding)."""
    path = Path(path)
    try:
        raw = path.read_bytes()
    except OSError as err:
        raise CsvError(path, "file", f"cannot be read ({err.strerror or err})") from None
    for bom, name in _OTHER_BOMS:
        if raw.startswith(bom):
            raise CsvError(path, "file", f"is {name} text (its byte-order mark says so); expected UTF-8 text "
                                         "(save or write it as UTF-8)")
    if raw.startswith(_UTF8_BOM):
        raw = raw[len(_UTF8_BOM):]
    if b"\x00" in raw:   # UTF-16 without its mark: every ASCII character followed or led by a NUL byte
        at = raw.index(b"\x00")
        raise CsvError(path, "file", f"has a NUL byte at byte {at} (UTF-16 text or a binary file?); "
                                     "expected UTF-8 text")
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as err:
        raise CsvError(path, "file", f"is not UTF-8 text (byte {err.start}: {raw[err.start:err.start + 1]!r} "
                                     f"cannot be decoded); expected UTF-8 text") from None


def read_csv(path: str | Path, text: str | None = None) -> dict[str, np.ndarray]:
    """Columns of a trajectory CSV by header name: {name: array (rows,)}.

    t,x,y,theta,vx,vy,omega are required, in any order; energy is returned when present. Other
    columns are not read: they may hold anything (a phase's name, a flag, NaN). Every cell of the
    columns read must be a finite number. Raises CsvError (a ValueError)
    naming the file, the row (1 = the header) or column, and what was expected. The file is
    UTF-8 text, a byte-order mark allowed (read_csv_text); text: its text when already read.
    """
    path = Path(path)
    if text is None:
        text = read_csv_text(path)
    lines = [(n, line) for n, line in enumerate(text.splitlines(), start=1) if line.strip()]
    if not lines:
        raise CsvError(path, "file", "is empty; expected a header row " + ",".join(CSV_COLUMNS))
    header_row, header_line = lines[0]
    header = [name.strip() for name in next(csv.reader([header_line]))]
    seen = set()
    for c, name in enumerate(header, start=1):
        if not name:
            raise CsvError(path, f"row {header_row} column {c}", "empty column name in the header")
        if name in seen:
            raise CsvError(path, f"row {header_row} column {c}", f"column {name!r} appears twice in the header")
        seen.add(name)
    missing = [name for name in REQUIRED_COLUMNS if name not in seen]
    if missing:
        raise CsvError(path, f"row {header_row} (header)",
                       f"missing column{'s' if len(missing) > 1 else ''} {', '.join(missing)}; "
                       f"expected at least {','.join(REQUIRED_COLUMNS)} (found {','.join(header)})")
    if len(lines) == 1:
        raise CsvError(path, "file", "has a header but no rows; expected at least the t = 0 row")
    used = [c for c, name in enumerate(header) if name in CSV_COLUMNS]
    try:  # fast path: numpy parses the body; any fault is then located row by row below
        data = np.loadtxt(io.StringIO(text), delimiter=",", skiprows=header_row, ndmin=2, usecols=used)
        ok = data.shape == (len(lines) - 1, len(used)) and bool(np.all(np.isfinite(data)))
        ok = ok and all(line.count(",") == len(header) - 1 for _, line in lines[1:])
    except ValueError:
        ok = False
    if not ok:
        data = _parse_rows(path, header, used, lines[1:])
    return {header[c]: data[:, j] for j, c in enumerate(used)}


def _parse_rows(path: Path, header: list[str], used: list[int], lines: list[tuple[int, str]]) -> np.ndarray:
    """The columns `used` of the file's body, cell by cell, raising CsvError at the first bad row
    or cell."""
    data = np.empty((len(lines), len(used)))
    for r, (row_no, line) in enumerate(lines):
        cells = next(csv.reader([line]))
        if len(cells) != len(header):
            raise CsvError(path, f"row {row_no}",
                           f"has {len(cells)} cells; expected {len(header)}, one per header column")
        for j, c in enumerate(used):
            cell = cells[c]
            where = f"row {row_no} column {c + 1} ({header[c]})"
            try:
                value = float(cell)
            except ValueError:
                raise CsvError(path, where, f"{cell.strip()!r} is not a number") from None
            if not math.isfinite(value):
                raise CsvError(path, where, f"{cell.strip()} is not a finite number")
            data[r, j] = value
    return data
