"""compare/table.py: the one table writer and number formatter of the reports and commands."""
from __future__ import annotations

import io
import math

import numpy as np
import pytest
from markdown_table import parse, rows

from compare.table import DASH, markdown, number, stream, text


def test_a_markdown_table_has_a_header_a_rule_and_the_same_cells_in_every_row():
    table = markdown(["scene", "error (m)", "note"], [["box_drop", number(1.23456e-5), "a | b"],
                                                      ["point_drop", number(None), ""]])
    header, align, rows = parse(table)
    assert header == ["scene", "error (m)", "note"] and align == ["left"] * 3
    assert rows == [["box_drop", "1.23e-05", "a | b"], ["point_drop", DASH, ""]]


def test_alignment_is_written_in_the_rule():
    _, align, _ = parse(markdown(["a", "b", "c"], [["x", "1", "y"]], align=["left", "right", "center"]))
    assert align == ["left", "right", "center"]
    _, align, _ = parse(markdown(["a", "b"], [["x", "1"]], align="right"))
    assert align == ["right", "right"]


def test_cells_are_written_as_given():
    """No number parsing (1.50 stays 1.50), no line break inside a row, headers may be empty."""
    header, _, rows = parse(markdown(["", ""], [["1.50", "1e-3"], ["two\nlines", ""]]))
    assert header == ["", ""] and rows == [["1.50", "1e-3"], ["two lines", ""]]


def test_a_cell_that_is_not_text_goes_through_number():
    _, _, rows = parse(markdown(["a", "b", "c", "d"], [[None, 0.000123456, 12, True]]))
    assert rows == [[DASH, "0.000123", "12", "yes"]]


def test_rows_reads_every_table_of_a_page():
    page = "\n".join(["# page", "", markdown(["a"], [["1"], ["2"]]), "", "text | not a table", "",
                       markdown(["b", "c"], [["x", "y"]])])
    assert rows(page) == [["1"], ["2"], ["x", "y"]]


def test_an_empty_table_keeps_its_header():
    header, _, rows = parse(markdown(["a", "b"], []))
    assert header == ["a", "b"] and rows == []


def test_a_streamed_table_is_the_same_table_unpadded():
    out = io.StringIO()
    stream(["scene", "x"], iter([["a", "1"], ["b|c", "2"]]), align=["left", "right"], file=out)
    assert out.getvalue().splitlines()[0] == "| scene | x |"
    assert parse(out.getvalue()) == parse(markdown(["scene", "x"], [["a", "1"], ["b|c", "2"]],
                                                   align=["left", "right"]))


def test_a_terminal_table_lines_up_its_columns():
    lines = text(["scene", "ns/step"], [["box_drop", "12.5"], ["t_shape_drop", "3.0"]],
                 align=["left", "right"]).splitlines()
    assert lines[0].split() == ["scene", "ns/step"] and set(lines[1]) == {"-", " "}
    assert [line.split() for line in lines[2:]] == [["box_drop", "12.5"], ["t_shape_drop", "3.0"]]
    assert len({len(line) for line in lines}) == 1, "padded to the same width"
    assert lines[2].endswith("12.5") and lines[3].endswith(" 3.0"), "right-aligned"


@pytest.mark.parametrize("x, options, shown", [
    (None, {}, DASH),                           # the report's dash for a value that does not exist
    (None, {"none": "-"}, "-"),                 # the sweep's and the study's
    (None, {"none": ""}, ""),                   # the diagnosis: an empty cell
    (None, {"none": "diverged"}, "diverged"),   # the calibration's errors
    (0.000123456, {}, "0.000123"),              # 3 significant digits by default (%g)
    (123456.0, {}, "1.23e+05"),
    (2.0, {}, "2"),
    (-0.0012345, {"digits": 4}, "-0.001234"),
    (1.23456, {"decimals": 2}, "1.23"),          # fixed decimals (ratios)
    (math.nan, {}, "nan"),
    (math.inf, {}, "inf"),
    (math.nan, {"nonfinite": "-"}, "-"),
    (-math.inf, {"decimals": 2, "nonfinite": "-"}, "-"),
    (12345, {}, "12345"),                        # a count as it is
    (np.int64(7), {}, "7"),
    (np.float32(0.5), {}, "0.5"),
    (True, {}, "yes"), (False, {}, "no"),
    ("text", {}, "text"),
])
def test_number(x, options, shown):
    assert number(x, **options) == shown


@pytest.mark.parametrize("x, shown", [
    (0.0, "0"), (0.001, "0.001"), (1234.5678, "1235"), (9999.0, "9999"),   # 4 digits inside 1e-3..1e4
    (1e4, "1.00e+04"), (0.000999, "9.99e-04"), (-2.5e-7, "-2.50e-07"),    # d.dde+XX outside
    (math.nan, "nan"),
])
def test_number_with_a_range_for_plain_digits(x, shown):
    """The report pages' numbers: 4 significant digits, scientific outside 1e-3 <= |x| < 1e4."""
    assert number(x, 4, sci=(1e-3, 1e4)) == shown
