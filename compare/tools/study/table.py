"""study.csv: one row per run, a column per varied field (named as on the command line), then
the measured columns; floats written with every digit (repr), so a value read back is the
value computed, bit for bit. An empty cell is a value that does not exist (an unstable run has
no error), and the `note` column says why. Parquet beside it when pyarrow is installed.
"""
from __future__ import annotations

import csv
import io
from pathlib import Path

from ...files import write_text_atomically

# After the varied fields, in this order. The first eight are the table's fixed contract;
# the rest are added after them (`simulator`: custom_sim, or yours with --sim).
MEASURED = ("integrator", "stable", "position_error_max", "twin_position_error_max", "wall_time",
            "force_evals", "status", "stable_step_theory", "note", "run", "simulator")


def columns(names: list[str]) -> list[str]:
    return [*names, *MEASURED]


def _cell(value) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    return str(value)


def records(names: list[str], rows: list[dict]) -> list[dict]:
    """Rows as flat records keyed by column name."""
    out = []
    for row in rows:
        rec = dict(zip(names, row["values"]))
        rec.update({c: row.get(c) for c in MEASURED if c not in ("run", "simulator")})
        rec["run"] = row["key"]
        rec["simulator"] = row.get("simulator") or "custom_sim"   # rows kept before the column
        out.append(rec)
    return out


def write_csv(path: Path, names: list[str], rows: list[dict]) -> None:
    """Written beside its place and renamed into it: a reader never sees half a table."""
    text = io.StringIO(newline="")
    writer = csv.writer(text)
    writer.writerow(columns(names))
    for rec in records(names, rows):
        writer.writerow([_cell(rec[c]) for c in columns(names)])
    write_text_atomically(path, text.getvalue())


def write_parquet(path: Path, names: list[str], rows: list[dict]) -> bool:
    """study.parquet beside study.csv, if pyarrow is importable; returns whether it was written."""
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        return False
    recs = records(names, rows)
    table = pa.table({c: [r[c] for r in recs] for c in columns(names)})
    pq.write_table(table, path)
    return True


def read_csv(path: Path) -> list[dict]:
    """study.csv back as dicts of strings (tests, and users without pandas)."""
    with Path(path).open(newline="") as fh:
        return list(csv.DictReader(fh))
