"""The VAL-II syntax checker and ``valterm check``."""

from __future__ import annotations

from pathlib import Path

import pytest

from valterm.cli import main
from valterm.core.files.programs import parse_program, read_program
from valterm.core.val.checker import check_program, check_statement

REPO = Path(__file__).resolve().parent.parent  # the repository: the bundled data (cells/, programs/)
PROGRAMS = REPO / "programs"


def check(text: str, name: str = "TEST", exists=None):  # type: ignore[no-untyped-def]
    return check_program(parse_program(text, name), program_exists=exists)


def messages(report) -> list[str]:  # type: ignore[no-untyped-def]
    return [str(d) for d in report.diagnostics]


@pytest.mark.parametrize("name", ["PROCESS", "CONV1", "CONV2"])
def test_the_thesis_programs_are_clean(name: str) -> None:
    report = check_program(read_program(PROGRAMS / f"{name}.DAT"))
    assert report.ok, messages(report)
    assert report.summary().endswith("no errors")


def test_every_bad_line_is_reported_with_program_step_and_reason() -> None:
    report = check(
        "; PROGRAM BAD\n"
        "    MOVE\n"
        "    JUMP 10\n"
        "    APPRO A\n"
        "    READY\n"
        "    D\n"
        "    COL=COL+\n",
        "BAD",
    )
    lines = messages(report)
    assert lines[0].startswith("BAD step 2: MOVE: expected MOVE <location>")
    assert lines[1].startswith("BAD step 3: JUMP is not a command")
    assert lines[2].startswith("BAD step 4: APPRO")
    assert lines[3].startswith("BAD step 6: D is ambiguous")
    assert lines[4].startswith("BAD step 7:")
    assert len(report.errors) == 5 and not report.warnings


@pytest.mark.parametrize("text, expected", [
    ("    IF X .EQ. 1 THEN\n    READY\n", "step 1: IF without END"),
    ("    WHILE X .LT. 1 DO\n    READY\n", "step 1: WHILE without END"),
    ("    DO\n    READY\n", "step 1: DO without UNTIL"),
    ("    READY\n    UNTIL X .EQ. 1\n", "step 2: UNTIL without DO"),
    ("    READY\n    END\n", "step 2: END without IF or WHILE"),
    ("    ELSE\n", "step 1: ELSE without IF"),
    ("    IF X THEN\n    ELSE\n    ELSE\n    END\n", "step 3: second ELSE"),
    ("    DO\n    END\n    UNTIL X\n", "step 2: END without IF or WHILE (the DO at step 1 needs UNTIL first)"),
    ("    WHILE X DO\n    UNTIL X\n    END\n", "step 2: UNTIL without DO (the WHILE at step 1 needs END first)"),
    ("    WHILE X DO\n    ENDIF\n", "step 2: ENDIF closes the WHILE at step 1: use END"),
    ("10  READY\n10  READY\n", "step 2: step label 10 is already used at step 1"),
    ("    EXECUTE CONV1\n", "step 1: EXECUTE is a monitor command"),
])
def test_structure_errors(text: str, expected: str) -> None:
    report = check(text)
    assert any(expected in line for line in messages(report)), messages(report)
    assert not report.ok


def test_nested_structures_are_fine() -> None:
    report = check(
        "    I=0\n"
        "    DO\n"
        "    WHILE I .LT. 3 DO\n"
        "    IF I .EQ. 1 THEN\n"
        "    TYPE ONE\n"
        "    ELSE\n"
        "    IF I .EQ. 2, THEN\n"
        "    TYPE TWO\n"
        "    ENDIF\n"
        "    END\n"
        "    I=I+1\n"
        "    END\n"
        "    UNTIL I .GE. 3.\n"
    )
    assert report.ok, messages(report)


def test_goto_to_a_missing_label_is_a_warning() -> None:
    report = check("    GOTO 400\n    GRASP 50, 500\n    IF X GOTO 600\n100 READY\n    GOTO 100\n")
    assert [d.severity for d in report.diagnostics] == ["warning"] * 3
    assert "step 1: warning: GOTO 400: no step has label 400" in messages(report)[0]
    assert not report.ok and not report.errors


def test_call_of_a_missing_program_is_a_warning() -> None:
    report = check("    CALL CONV2\n    CALL NOSUCH\n", exists=lambda name: name == "CONV2")
    assert messages(report) == ["TEST step 2: warning: CALL NOSUCH: there is no program NOSUCH.DAT"]


def test_check_statement_for_the_editor() -> None:
    assert check_statement("    MOVE A") is None
    assert check_statement("300 ENDIF") is None
    assert check_statement("; a comment") is None
    assert "expected MOVE" in (check_statement("    MOVE") or "")
    assert "monitor command" in (check_statement("EXEC PROCESS") or "")


# -- the command line ----------------------------------------------------------------


def test_cli_check_clean_program(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    program = tmp_path / "GOOD.DAT"
    program.write_text("    READY\n    CALL SUB\n")
    (tmp_path / "SUB.DAT").write_text("    RETURN\n")
    assert main(["check", str(program)]) == 0
    assert "GOOD: 2 steps, no errors" in capsys.readouterr().out


def test_cli_check_reports_and_exits_1(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    program = tmp_path / "BAD.DAT"
    program.write_text("    READY\n    MOVE\n    IF X THEN\n    CALL NOSUCH\n")
    assert main(["check", str(program)]) == 1
    out = capsys.readouterr().out
    assert "BAD step 2: MOVE: expected MOVE <location>" in out
    assert "BAD step 3: IF without END" in out
    assert "BAD step 4: warning: CALL NOSUCH" in out
    assert "2 error(s), 1 warning(s)" in out


def test_cli_check_workspace_name(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--workspace", str(tmp_path / "ws"), "check", "CONV1", "CONV2.DAT"]) == 0
    out = capsys.readouterr().out
    assert "CONV1: 56 steps, no errors" in out and "CONV2" in out


def test_cli_check_unreadable_file_exits_1(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    binary = tmp_path / "JUNK.DAT"
    binary.write_bytes(b"\x00\x01\x02 READY\n")
    assert main(["check", str(binary)]) == 1
    assert "JUNK.DAT" in capsys.readouterr().err
    assert main(["check", str(tmp_path / "none" / "X.DAT")]) == 1
