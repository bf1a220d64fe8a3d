"""Trajectory CSV files: written from t = 0, read back by header name, bad files named precisely."""
import dataclasses

import numpy as np
import pytest

from custom_sim import CsvError, load_scene, read_csv, simulate, write_csv
from scene_types.trajectory import CSV_COLUMNS, CSV_RELATIVE_ROUNDING, REQUIRED_COLUMNS

GOOD = "t,x,y,theta,vx,vy,omega\n0,0,0.5,0,1,0,0\n0.001,0.001,0.5,0,1,0,0\n"


@pytest.fixture(scope="module")
def trajectory():
    scene = dataclasses.replace(load_scene("scenarios/box_drop.toml"), duration=0.05)
    return scene, simulate(scene)


def test_round_trip_keeps_every_row_from_t0(tmp_path, trajectory):
    scene, tr = trajectory
    path = tmp_path / "t.csv"
    write_csv(tr, path)
    assert path.read_text().splitlines()[0] == ",".join(CSV_COLUMNS)
    cols = read_csv(path)
    assert set(cols) == set(CSV_COLUMNS)
    assert len(cols["t"]) == scene.steps + 1, "the t = 0 row, then one row per step"
    assert cols["t"][0] == 0.0 and cols["t"][1] == pytest.approx(scene.dt)
    states = np.column_stack([cols[c] for c in REQUIRED_COLUMNS[1:]])
    scale = np.maximum(np.abs(tr.states()), 1e-300)
    worst = np.max(np.abs(states - tr.states()) / scale)
    assert worst <= CSV_RELATIVE_ROUNDING, f"state changed by a relative {worst:.2e} in the round trip"
    assert np.allclose(cols["energy"], tr.energy, rtol=CSV_RELATIVE_ROUNDING, atol=0)
    assert np.array_equal(states[0], tr.states()[0]), "row 0 is the initial state"


@pytest.mark.parametrize("notes", [("7", "8"), ("sliding", "stuck"), ("nan", ""), ('"a, b"', "1")])
def test_columns_are_read_by_name_in_any_order_and_others_left_unread(tmp_path, notes):
    """A column the harness does not read may hold anything (a phase's name, a flag, NaN, a
    quoted comma): it is neither parsed nor returned."""
    path = tmp_path / "u.csv"
    path.write_text(f"omega,vy,vx,theta,y,x,t,note\n3,2,1,0.5,0.25,0.125,0,{notes[0]}\n"
                    f"3,2,1,0.5,0.25,0.25,0.1,{notes[1]}\n")
    cols = read_csv(path)
    assert list(cols["x"]) == [0.125, 0.25] and list(cols["t"]) == [0.0, 0.1] and list(cols["omega"]) == [3.0, 3.0]
    assert set(cols) == set(REQUIRED_COLUMNS)


def test_a_row_with_a_cell_too_many_is_named_even_in_an_unread_column(tmp_path):
    path = tmp_path / "u.csv"
    path.write_text("t,x,y,theta,vx,vy,omega,note\n0,0,0.5,0,1,0,0,a\n0.001,0.001,0.5,0,1,0,0,b,c\n")
    with pytest.raises(CsvError, match="row 3: has 9 cells; expected 8"):
        read_csv(path)


def test_energy_is_optional(tmp_path):
    path = tmp_path / "u.csv"
    path.write_text(GOOD)
    assert "energy" not in read_csv(path) and len(read_csv(path)["t"]) == 2


BAD = {
    "missing_column": ("t,x,y,theta,vx,vy\n0,0,0,0,0,0\n", ["row 1", "missing column omega"]),
    "not_a_number": (GOOD.replace("0.001,0.001", "0.001,abc"), ["row 3 column 2 (x)", "'abc' is not a number"]),
    "nan": (GOOD.replace("0.001,0.001", "0.001,nan"), ["row 3 column 2 (x)", "not a finite number"]),
    "ragged": (GOOD + "0.002,0,0\n", ["row 4", "has 3 cells; expected 7"]),
    "empty": ("", ["file", "is empty"]),
    "header_only": ("t,x,y,theta,vx,vy,omega\n", ["file", "no rows"]),
    "duplicate": ("t,x,x,y,theta,vx,vy,omega\n0,0,0,0,0,0,0,0\n", ["row 1 column 3", "appears twice"]),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_file_names_the_file_the_place_and_the_expectation(tmp_path, case):
    text, expected = BAD[case]
    path = tmp_path / f"{case}.csv"
    path.write_text(text)
    with pytest.raises(CsvError) as info:
        read_csv(path)
    message = str(info.value)
    assert isinstance(info.value, ValueError) and message.startswith(str(path))
    for part in expected:
        assert part in message, f"{part!r} not in {message!r}"


def test_missing_file_is_a_csv_error(tmp_path):
    with pytest.raises(CsvError, match="cannot be read"):
        read_csv(tmp_path / "absent.csv")


def test_a_byte_order_mark_is_accepted(tmp_path):
    """Excel and Windows tools start a UTF-8 file with a byte-order mark: the header still reads."""
    path = tmp_path / "bom.csv"
    path.write_bytes(GOOD.encode("utf-8-sig"))
    cols = read_csv(path)
    assert list(cols["t"]) == [0.0, 0.001] and list(cols["x"]) == [0.0, 0.001]


@pytest.mark.parametrize("encoding", ["utf-16", "utf-16-le", "utf-16-be", "utf-32", "latin-1"])
def test_another_encoding_is_a_csv_error_naming_the_file(tmp_path, encoding):
    path = tmp_path / f"{encoding}.csv"
    text = GOOD + ("0.002,0,0.5,0,1,0,0,  # café\n" if encoding == "latin-1" else "")   # latin-1: é is one byte, not UTF-8
    path.write_bytes(text.encode(encoding))
    with pytest.raises(CsvError) as info:
        read_csv(path)
    message = str(info.value)
    assert message.startswith(f"{path}: file: ") and "expected UTF-8 text" in message, message
