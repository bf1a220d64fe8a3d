"""Markdown tables read back as a markdown parser reads them: cells, not whitespace."""
from __future__ import annotations

import re


def cells(line: str) -> list[str]:
    """A pipe-table row's cells, stripped (an escaped pipe is part of its cell)."""
    assert line.startswith("|") and line.endswith("|"), line
    return [c.strip().replace("\\|", "|") for c in re.split(r"(?<!\\)\|", line)[1:-1]]


def parse(table: str) -> tuple[list[str], list[str], list[list[str]]]:
    """(header, alignments, rows) of one GitHub-flavoured markdown table; asserts it is one:
    a header, a rule of dashes, and as many cells in every row."""
    lines = table.strip().splitlines()
    header, rule, rows = cells(lines[0]), cells(lines[1]), [cells(line) for line in lines[2:]]
    assert all(re.fullmatch(r":?-{3,}:?", r) for r in rule), lines[1]
    assert len(rule) == len(header) and all(len(r) == len(header) for r in rows), table
    align = ["center" if r.startswith(":") and r.endswith(":") else "right" if r.endswith(":") else "left"
             for r in rule]
    return header, align, rows


def rows(text: str) -> list[list[str]]:
    """The cells of every row of every table in a text (headers and rules left out)."""
    found, lines = [], text.splitlines()
    for i, line in enumerate(lines):
        if line.startswith("|") and i + 1 < len(lines) and re.fullmatch(r"\|(\s*:?-{3,}:?\s*\|)+", lines[i + 1]):
            block = [line]
            for more in lines[i + 1:]:
                if not more.startswith("|"):
                    break
                block.append(more)
            found += parse("\n".join(block))[2]
    return found
