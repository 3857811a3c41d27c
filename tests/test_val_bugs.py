"""Issue 14: each bug of the 1985 interpreter listed there, against the real simulator."""

from __future__ import annotations

from pathlib import Path

import pytest

from valterm.cli import main
from valterm.core.events import Error, Event, Message, TypeOut
from valterm.core.files.programs import Program
from valterm.core.kinematics import Location
from valterm.core.simulator import Simulator
from valterm.core.val.checker import check_program
from valterm.core.val.interpreter import Interpreter, program_from_lines
from valterm.core.text.transcript import event_lines


def execute(lines: list[str], sim: Simulator | None = None) -> tuple[Simulator, list[Event]]:
    sim = sim or Simulator(None)
    programs = {"P": program_from_lines("P", lines)}

    def load(name: str) -> Program:
        return programs[name]

    interpreter = Interpreter(sim, load, {})
    return sim, list(interpreter.execute("P"))


def typed(events: list[Event]) -> list[str]:
    return [e.text for e in events if isinstance(e, TypeOut)]


def errors(events: list[Event]) -> list[Error]:
    return [e for e in events if isinstance(e, Error)]


def completed(events: list[Event]) -> bool:
    return any(isinstance(e, Message) and "COMPLETED" in e.text for e in events)


def check(lines: list[str]) -> list[str]:
    return [str(d) for d in check_program(program_from_lines("P", lines)).diagnostics]


def test_type_of_quoted_text_prints_no_quotes() -> None:
    _, events = execute(['TYPE "PICK UP THE PART"'])
    assert typed(events) == ["PICK UP THE PART"]


def test_type_of_a_list_prints_the_values_and_formats() -> None:
    _, events = execute(["X=2.5", 'TYPE "X=", X', 'TYPE "HALF ", /F6.3, X/2'])
    assert typed(events) == ["X=2.5", "HALF  1.250"]


def test_the_thesis_type_forms_are_unchanged() -> None:
    _, events = execute(["COL=3", "TYPE COL=", "TYPE PICK UP THE FIRST PART"])
    assert typed(events) == ["COL = 3", "PICK UP THE FIRST PART"]


def test_a_bad_type_list_fails_the_check() -> None:
    assert check(['TYPE "OPEN']) == ["P step 1: TYPE: A QUOTE IS NOT CLOSED"]


def test_set_to_here_records_the_present_location() -> None:
    sim, events = execute(["READY", "SET B = HERE"])
    assert not errors(events) and completed(events)
    assert sim.locations["B"] == sim.here_location()


def test_a_step_that_fails_the_check_stops_the_program() -> None:
    _, events = execute(['TYPE "BEFORE"', "JUMP 3", 'TYPE "AFTER"'])
    assert typed(events) == ["BEFORE"]
    assert [(e.program, e.step) for e in errors(events)] == [("P", 2)]
    assert not completed(events)


def test_drive_of_joint_7_fails_the_check_and_the_run() -> None:
    assert check(["DRIVE 7,10,50"]) == ["P step 1: DRIVE: JOINT NUMBER 7 IS NOT 1 TO 6"]
    _, events = execute(["DRIVE 7,10,50"])
    assert "JOINT NUMBER 7 IS NOT 1 TO 6" in errors(events)[0].message and not completed(events)


@pytest.mark.parametrize(("line", "wanted"), [
    ("z_pick = 80", "Z_PICK IS NOT A VARIABLE NAME"),
    ("a[i] = i", "ARRAYS ARE V+"),
    ("z.pick = 80", "DOTTED, $STRING AND #PRECISION NAMES ARE V+"),
])
def test_assignments_to_other_names_say_what_is_wrong(line: str, wanted: str) -> None:
    (message,) = check([line])
    assert wanted in message
    assert "is not a command" not in message and "ambiguous" not in message


def test_while_without_do_is_reported_at_the_while() -> None:
    lines = ["X=1", "WHILE X < 3", "X=X+1", "END"]
    assert check(lines) == ["P step 2: WHILE: expected WHILE <condition> DO"]
    _, events = execute(lines)
    assert errors(events)[0].step == 2
    assert not any("END without" in e.message for e in errors(events))


def test_whole_program_errors_do_not_say_step_0() -> None:
    _, events = execute(["IF X THEN"])
    lines = [line for e in errors(events) for line in event_lines(e)]
    assert lines[-1] == "*** P: THE PROGRAM CANNOT RUN (PASS 1 FOUND THE ERRORS ABOVE)"
    assert not any("step 0" in line for line in lines)


def test_a_joint_move_beyond_a_stop_names_the_angle_and_the_stop() -> None:
    _, events = execute(["READY", "DRIVE 2,400,50"])
    (error,) = errors(events)
    assert error.step == 2 and "joint 2 beyond its stop" in error.message
    assert "deg" in error.message and "stop -225..45" in error.message


def test_a_location_beyond_a_stop_names_the_angle_and_the_stop() -> None:
    sim = Simulator(None)
    sim.locations["TW"] = Location((400.0, 100.0, -200.0), (0.0, -90.0, 0.0))
    _, events = execute(["LEFTY", "MOVE TW"], sim)
    (error,) = errors(events)
    assert error.step == 2
    assert "joint 5 beyond its stop (173.93 deg, stop -100..100)" in error.message


def test_run_writes_check_dat_as_its_docstring_says(tmp_path: Path) -> None:
    from valterm.commands import run as run_command

    (tmp_path / "ROWS.DAT").write_text("    ROW=7\n")
    assert main(["--workspace", str(tmp_path), "run", str(tmp_path / "ROWS.DAT")]) == 0
    assert (tmp_path / "CHECK.DAT").read_text().strip() == "ROW=7"
    assert "written back" in (run_command.__doc__ or "")
