"""Every table the harness writes (markdown and terminal, by tabulate) and its number formatter."""
from __future__ import annotations

import math
import numbers
import sys
from collections.abc import Iterable, Sequence

from tabulate import tabulate

DASH = "–"   # a value that does not exist


def number(x, digits: int = 3, *, decimals: int | None = None, none: str = DASH,
           nonfinite: str | None = None, sci: tuple[float, float] | None = None) -> str:
    """A value as a cell: a float to `digits` significant digits (%g) or `decimals` fixed ones;
    None as `none`; nan and inf as `nonfinite` (default: as Python writes them); with
    sci=(low, high) a float outside low <= |x| < high (0 aside) as d.dde+XX; a bool as yes/no;
    an int or text as it is. Units are the caller's."""
    if x is None:
        return none
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, numbers.Integral) or not isinstance(x, numbers.Real):
        return str(x)
    x = float(x)
    if not math.isfinite(x) and nonfinite is not None:
        return nonfinite
    if decimals is not None:
        return f"{x:.{decimals}f}"
    if sci and x != 0 and not sci[0] <= abs(x) < sci[1]:
        return f"{x:.2e}"
    return f"{x:.{digits}g}"


def _cells(row: Iterable, markdown: bool) -> list[str]:
    out = [c if isinstance(c, str) else number(c) for c in row]
    if markdown:   # a pipe or a line break would end the cell
        out = [c.replace("|", r"\|").replace("\n", " ") for c in out]
    return out


def _align(align: str | Sequence[str], n: int) -> list[str]:
    return [align] * n if isinstance(align, str) else list(align)


def markdown(headers: Sequence, rows: Iterable[Sequence], align: str | Sequence[str] = "left") -> str:
    """A markdown (pipe) table; align: "left", "right" or "center", for all columns or each.
    A cell that is not text goes through number()."""
    headers = _cells(headers, True)
    return tabulate([_cells(r, True) for r in rows], headers, tablefmt="pipe", disable_numparse=True,
                    colalign=_align(align, len(headers)))


def text(headers: Sequence, rows: Iterable[Sequence], align: str | Sequence[str] = "left") -> str:
    """The same table for a terminal: columns padded, a dashed line under the header."""
    headers = _cells(headers, False)
    return tabulate([_cells(r, False) for r in rows], headers, tablefmt="simple", disable_numparse=True,
                    colalign=_align(align, len(headers)))


_RULE = {"left": ":---", "right": "---:", "center": ":---:"}


def stream(headers: Sequence, rows: Iterable[Sequence], align: str | Sequence[str] = "left", file=None) -> None:
    """Print a markdown table row by row as `rows` yields them (long surveys): the same table as
    markdown() without the padding, which would wait for the last row."""
    file = file or sys.stdout
    headers = _cells(headers, True)
    print("| " + " | ".join(headers) + " |", file=file)
    print("|" + "|".join(_RULE[a] for a in _align(align, len(headers))) + "|", file=file, flush=True)
    for row in rows:
        print("| " + " | ".join(_cells(row, True)) + " |", file=file, flush=True)
