"""Location, program, DATFILER.DAT and CHECK.DAT files: the thesis's data, round trips, damage."""

from __future__ import annotations

import random
from pathlib import Path
from typing import Callable

import pytest

from valterm.core.files.datfiler import add_program_name, parse_datfiler, read_datfiler, write_datfiler
from valterm.core.files.errors import FileFormatError
from valterm.core.files.locations import format_locations, parse_locations, read_locations, write_locations
from valterm.core.files.programs import Program, ProgramLine, format_program, parse_program, read_program, write_program
from valterm.core.files.variables import format_variables, parse_variables, read_variables, write_variables
from valterm.core.files import atomic
from valterm.core.files.programs import split_label
from valterm.core.kinematics import Location

REPO = Path(__file__).resolve().parent.parent  # the repository: the bundled data (cells/, programs/)
PROGRAMS = REPO / "programs"


# -- locations -----------------------------------------------------------------

def test_process_locations_are_fig_7_3() -> None:
    points = read_locations(PROGRAMS / "PROCESS.LOC")
    assert list(points) == ["A", "B", "C", "D", "E", "F"]
    assert points["A"] == Location((465.0, -45.0, -245.0), (89.0, 91.0, 0.0))
    assert points["C"] == Location((-180.0, 600.0, -204.16), (90.0, 90.0, -90.0))  # `-204. 16` in the OCR


def test_conv_locations_are_fig_c_21() -> None:
    points = read_locations(PROGRAMS / "CONV.LOC")
    assert list(points) == ["A", "B", "C", "D", "F", "G", "H", "L", "M"]
    assert points["L"] == Location((464.60, 263.35, -431.12), (5.98, 62.57, 0.27))


def test_location_forms_accepted() -> None:
    text = "point p1 , 465. , -45. , -245. , 89. , 91. , 0.\n; taught by hand\n\nPOINT\tLONGNAME9 1 2 3 4 5 6\nPOINT P1,0,0,0,0,0,0\n"
    points = parse_locations(text, "X.LOC")
    assert points["P1"] == Location((0.0, 0.0, 0.0), (0.0, 0.0, 0.0))  # the later line wins
    assert points["LONGNAME9"].oat == (4.0, 5.0, 6.0)


def test_locations_round_trip(tmp_path: Path) -> None:
    points = read_locations(PROGRAMS / "CONV.LOC")
    points["Q9"] = Location((1 / 3, -2.0, 1e-7), (179.999999, -0.5, 12.25))
    write_locations(tmp_path / "T.LOC", points)
    back = read_locations(tmp_path / "T.LOC")
    assert {k: v for k, v in back.items() if k != "Q9"} == {k: v for k, v in points.items() if k != "Q9"}
    # the thesis's 2 decimals (issue 35): what is not a hundredth is rounded to one
    assert back["Q9"] == Location((0.33, -2.0, 0.0), (180.0, -0.5, 12.25))
    assert format_locations(points).splitlines()[0] == "POINT A, -215.78, 534.31, -105.29, -174.00, 56.00, 0.00"
    write_locations(tmp_path / "E.LOC", {})
    assert read_locations(tmp_path / "E.LOC") == {}


LOC_MALFORMED = [
    ("", 0, "empty"),
    ("POINT C, -180., 600., -204. 16, 90., 90., -90.\n", 1, "found 7"),
    ("POINT A, 1, 2, 3, 4, 5\n", 1, "found 5"),
    ("POINT A, 1, 2, 3, 4, 5, 6\nPOINT B, 1, 2, x3, 4, 5, 6\n", 2, "'x3' is not a number"),
    ("PIONT A, 1, 2, 3, 4, 5, 6\n", 1, "expected 'POINT"),
    ("POINT\n", 1, "without a location name"),
    ("POINT TOOLONGNAME123456, 1, 2, 3, 4, 5, 6\n", 1, "not a location name"),  # V+: at most 15
    ("POINT 9A, 1, 2, 3, 4, 5, 6\n", 1, "not a location name"),
    ("POINT A, 1, 2, 3, 4, 5, 6,\n1, 2\n", 2, "expected 'POINT"),
]


@pytest.mark.parametrize("text, line, reason", LOC_MALFORMED)
def test_malformed_locations_give_a_located_message(tmp_path: Path, text: str, line: int, reason: str) -> None:
    path = tmp_path / "BAD.LOC"
    path.write_text(text)
    with pytest.raises(FileFormatError) as caught:
        read_locations(path)
    assert (caught.value.line, reason in caught.value.reason) == (line, True), str(caught.value)


# -- programs --------------------------------------------------------------------

def test_process_program_is_fig_7_4() -> None:
    program = read_program(PROGRAMS / "PROCESS.DAT")
    assert program.name == "PROCESS"
    assert len(program.steps) == 35
    assert program.step(1) == ProgramLine(None, "; PROGRAM : PROCESS", 1)  # a comment line is a step
    assert program.step(6).text == "APPRO A, -50"
    assert program.step(35).text == "STOP"
    assert all(step.label is None for step in program.steps)


def test_conv1_labels_and_conv2_heading() -> None:
    conv1 = read_program(PROGRAMS / "CONV1.DAT")
    assert conv1.step(conv1.find_label(100)).text == "COL=COL+1"
    assert conv1.step(conv1.find_label(300)).text == "ENDIF"
    assert "IF COL.EQ.2, THEN" in [s.text for s in conv1.steps]
    assert conv1.find_label(200) is None
    conv2 = read_program(PROGRAMS / "CONV2.DAT")
    assert conv2.step(1).text == "; PROGRAM CONV2"


@pytest.mark.parametrize(
    "line, label, text",
    [
        ("    READY", None, "READY"),
        ("READY", None, "READY"),
        ("100 COL=COL+1", 100, "COL=COL+1"),
        ("300 ENDIF", 300, "ENDIF"),
        ("  300     ENDIF  ", 300, "ENDIF"),
        ("1234READY", 1234, "READY"),
        ("  12MOVE A", 12, "MOVE A"),
        ("12345 STOP", 12345, "STOP"),
        ("300", 300, ""),
        ("    ; a comment", None, "; a comment"),
        ("    MOVE A ; why", None, "MOVE A ; why"),
        ("    3.5", None, "3.5"),
    ],
)
def test_label_columns_and_free_form(line: str, label: int | None, text: str) -> None:
    assert split_label(line) == (label, text)


def test_tab_goes_to_column_5() -> None:
    program = parse_program("\tREADY\n10\tMOVE A\n", "T")
    assert [(s.label, s.text) for s in program.steps] == [(None, "READY"), (10, "MOVE A")]


def test_blank_lines_are_not_steps_but_line_numbers_are_kept() -> None:
    program = parse_program("    READY\n\n    STOP\n", "T")
    assert [(s.text, s.line) for s in program.steps] == [("READY", 1), ("STOP", 3)]


def test_programs_round_trip(tmp_path: Path) -> None:
    for name in ("PROCESS", "CONV1", "CONV2"):
        program = read_program(PROGRAMS / f"{name}.DAT")
        assert format_program(program) == (PROGRAMS / f"{name}.DAT").read_text()
    made = Program("MINE", [ProgramLine(None, "READY"), ProgramLine(7, "GOTO 7"), ProgramLine(65535, "STOP"),
                            ProgramLine(5, ""), ProgramLine(None, "; note")])
    write_program(tmp_path / "MINE.DAT", made)
    again = read_program(tmp_path / "MINE.DAT")
    assert [(s.label, s.text) for s in again.steps] == [(s.label, s.text) for s in made.steps]


def test_empty_program_is_written_as_its_heading(tmp_path: Path) -> None:
    write_program(tmp_path / "NEW.DAT", Program("NEW"))
    assert [s.text for s in read_program(tmp_path / "NEW.DAT").steps] == ["; PROGRAM NEW"]


def test_a_step_with_a_newline_stays_one_line(tmp_path: Path) -> None:
    write_program(tmp_path / "N.DAT", Program("N", [ProgramLine(None, "TYPE A\nSTOP")]))
    assert len(read_program(tmp_path / "N.DAT").steps) == 1


PROGRAM_MALFORMED = [
    ("", 0, "empty"),
    ("\n\n  \n", 0, "empty"),
    ("    READY\n70000 STOP\n", 2, "too large"),
    ("    READY\n    " + "X" * 300 + "\n", 2, "characters long"),
]


@pytest.mark.parametrize("text, line, reason", PROGRAM_MALFORMED)
def test_malformed_programs_give_a_located_message(tmp_path: Path, text: str, line: int, reason: str) -> None:
    path = tmp_path / "BAD.DAT"
    path.write_text(text)
    with pytest.raises(FileFormatError) as caught:
        read_program(path)
    assert (caught.value.line, reason in caught.value.reason) == (line, True), str(caught.value)
    assert str(caught.value).startswith("BAD.DAT:")


# -- DATFILER.DAT ----------------------------------------------------------------

def test_datfiler_reads_names_with_or_without_dat(tmp_path: Path) -> None:
    assert parse_datfiler("PROCESS.DAT\nconv1\n\nCONV1.DAT\n") == ["PROCESS", "CONV1"]
    path = tmp_path / "DATFILER.DAT"
    write_datfiler(path, ["PROCESS", "conv2.dat"])
    assert path.read_text() == "PROCESS.DAT\nCONV2.DAT\n"
    assert add_program_name(path, "test") is True
    assert add_program_name(path, "TEST.DAT") is False
    assert read_datfiler(path) == ["PROCESS", "CONV2", "TEST"]
    assert read_datfiler(_empty(tmp_path, "DATFILER.DAT")) == []  # an empty directory


@pytest.mark.parametrize("text, line", [("PROCESS.DAT\n../X.DAT\n", 2), ("TOOLONGNAME\n", 1), ("A.SET\n", 1), ("A B\n", 1)])
def test_malformed_datfiler(tmp_path: Path, text: str, line: int) -> None:
    path = tmp_path / "DATFILER.DAT"
    path.write_text(text)
    with pytest.raises(FileFormatError) as caught:
        read_datfiler(path)
    assert caught.value.line == line and "not a program name" in caught.value.reason


# -- CHECK.DAT ---------------------------------------------------------------------

def test_variables_round_trip(tmp_path: Path) -> None:
    values = {"ROW": 10.0, "COL": -2.5, "X1": 1 / 3, "BIG": 1e20}
    path = tmp_path / "CHECK.DAT"
    write_variables(path, values)
    assert path.read_text().splitlines()[:2] == ["ROW=10", "COL=-2.5"]
    assert read_variables(path) == values
    assert parse_variables(" row = 3 \n; kept\n\n") == {"ROW": 3.0}
    assert read_variables(_empty(tmp_path, "E.DAT")) == {}
    with pytest.raises(ValueError):
        format_variables({"ROW": float("inf")})


@pytest.mark.parametrize(
    "text, line, reason",
    [("ROW\n", 1, "NAME=value"), ("ROW=10\nCOL=ten\n", 2, "not a number"), ("1X=2\n", 1, "not a variable name"),
     ("TOOLONGNAME=1\n", 1, "not a variable name"), ("ROW=\n", 1, "not a number")],
)
def test_malformed_variables(tmp_path: Path, text: str, line: int, reason: str) -> None:
    path = tmp_path / "CHECK.DAT"
    path.write_text(text)
    with pytest.raises(FileFormatError) as caught:
        read_variables(path)
    assert (caught.value.line, reason in caught.value.reason) == (line, True), str(caught.value)


# -- what every reader shares ----------------------------------------------------------

READERS: list[tuple[str, Callable[[Path], object]]] = [
    ("X.LOC", read_locations),
    ("X.DAT", read_program),
    ("DATFILER.DAT", read_datfiler),
    ("CHECK.DAT", read_variables),
]


@pytest.mark.parametrize("name, reader", READERS)
def test_binary_junk_and_huge_files_are_refused(tmp_path: Path, name: str, reader: Callable[[Path], object]) -> None:
    path = tmp_path / name
    path.write_bytes(b"POINT A, 1, 2, 3, 4, 5, 6\n\x00\x01\x02")
    with pytest.raises(FileFormatError) as caught:
        reader(path)
    assert caught.value.line == 2
    path.write_bytes(b"\xc3\x28 not utf-8")
    with pytest.raises(FileFormatError, match="undecodable"):
        reader(path)
    with path.open("wb") as handle:
        handle.truncate(50 * 1024 * 1024)  # sparse
    with pytest.raises(FileFormatError, match="too large"):
        reader(path)
    path.unlink()
    with pytest.raises(FileFormatError, match="no such"):
        reader(path)


@pytest.mark.parametrize(
    "source, parse",
    [("PROCESS.LOC", lambda t: parse_locations(t, "F.LOC")), ("CONV1.DAT", lambda t: parse_program(t, "F")),
     ("CONV1.DAT", lambda t: parse_datfiler(t)), ("CONV.LOC", lambda t: parse_variables(t))],
)
def test_random_damage_never_escapes_as_another_exception(source: str, parse: Callable[[str], object]) -> None:
    text = (PROGRAMS / source).read_text()
    rng = random.Random(85)
    alphabet = "0123456789.,-+= \n\tPOINTA;"
    for _ in range(200):
        chars = list(text)
        for _ in range(rng.randint(1, 6)):
            at = rng.randrange(len(chars))
            if rng.random() < 0.5:
                del chars[at]
            else:
                chars.insert(at, rng.choice(alphabet))
        try:
            parse("".join(chars))
        except FileFormatError:
            pass


@pytest.mark.parametrize(
    "write, value",
    [(write_locations, {"A": Location((1.0, 2.0, 3.0), (4.0, 5.0, 6.0))}), (write_program, Program("P", [ProgramLine(None, "STOP")])),
     (write_datfiler, ["P"]), (write_variables, {"ROW": 1.0})],
)
def test_every_writer_is_atomic(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, write: Callable, value: object) -> None:
    path = tmp_path / "OLD.DAT"
    path.write_text("old contents\n")
    monkeypatch.setattr(atomic.os, "replace", lambda *a: (_ for _ in ()).throw(OSError(28, "disk full")))
    with pytest.raises(OSError):
        write(path, value)
    monkeypatch.undo()
    assert path.read_text() == "old contents\n"
    assert [p.name for p in tmp_path.iterdir()] == ["OLD.DAT"]


def _empty(folder: Path, name: str) -> Path:
    path = folder / name
    path.write_text("")
    return path
