"""The v+ dialect (issue 14): statements, expressions, CALL, signals, files and the CLI options."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from valterm.cli import main
from valterm.core.events import Error, Event, Message, Signal, TypeOut
from valterm.core.files.errors import FileFormatError
from valterm.core.files.locations import (
    format_locations,
    parse_locations,
    read_location_file,
)
from valterm.core.files.programs import Program
from valterm.core.files.vplus import format_vplus, parse_vplus, read_vplus
from valterm.core.kinematics import Location
from valterm.core.simulator import Simulator
from valterm.core.val.checker import check_program
from valterm.core.val.dialects import check_dialect
from valterm.core.val.interpreter import Interpreter, program_from_lines

PROGRAMS = Path(__file__).resolve().parent.parent / "programs"


def vplus(text: str, sim: Simulator | None = None) -> tuple[Interpreter, list[Event]]:
    """Run the first program of a V+ text (all its programs callable) against a real simulator."""
    programs = {b.program.name: b.program for b in parse_vplus(text, "T.v2")}
    sim = sim or Simulator(None)
    interpreter = Interpreter(sim, lambda name: programs[name], {})
    return interpreter, list(interpreter.execute(next(iter(programs))))


def body(*lines: str) -> str:
    return ".PROGRAM t()\n" + "\n".join(f"    {line}" for line in lines) + "\n.END\n"


def typed(events: list[Event]) -> list[str]:
    return [e.text for e in events if isinstance(e, TypeOut)]


def errors(events: list[Event]) -> list[Error]:
    return [e for e in events if isinstance(e, Error)]


def completed(events: list[Event]) -> bool:
    return any(isinstance(e, Message) and "COMPLETED" in e.text for e in events)


def check_errors(text: str, dialect: str | None = None) -> list[str]:
    return [str(d) for b in parse_vplus(text, "T.v2") for d in check_program(b.program, dialect=dialect).errors]


# -- structured control ---------------------------------------------------------------------

def test_for_loops_count_up_down_and_skip_an_empty_range() -> None:
    _, events = vplus(body("FOR i = 1 TO 7 STEP 3", 'TYPE "UP ", i', "END",
                           "FOR i = 3 TO 1 STEP -1", 'TYPE "DOWN ", i', "END",
                           "FOR i = 5 TO 1", 'TYPE "NEVER"', "END", 'TYPE "AFTER ", i'))
    assert typed(events) == ["UP 1", "UP 4", "UP 7", "DOWN 3", "DOWN 2", "DOWN 1", "AFTER 5"]


def test_case_takes_the_first_matching_value_then_any_then_nothing() -> None:
    program = body("FOR k = 1 TO 4", "CASE k OF", "VALUE 1, 3:", 'TYPE "ODD ", k', "VALUE 2:",
                   'TYPE "TWO"', "ANY", 'TYPE "OTHER ", k', "END", "END",
                   "CASE 9 OF", "VALUE 1:", 'TYPE "NO"', "END", 'TYPE "DONE"')
    _, events = vplus(program)
    assert typed(events) == ["ODD 1", "TWO", "ODD 3", "OTHER 4", "DONE"]


def test_while_do_until_and_true_false() -> None:
    _, events = vplus(body("n = 0", "WHILE n < 3 DO", "n = n+1", "END", "DO", "n = n-2", "UNTIL n < 0",
                           "flag = NOT FALSE", 'TYPE n, " ", flag, " ", TRUE'))
    assert typed(events) == ["-1 -1 -1"]


def test_structure_errors_say_where_and_which_dialect() -> None:
    assert check_errors(body("VALUE 1:")) == ["T step 1: VALUE without CASE"]
    assert check_errors(body("WHILE x < 1", "END")) == ["T step 1: WHILE: EXPECTED WHILE <condition> DO"]
    assert check_errors(body("END")) == ["T step 1: END without IF, WHILE, FOR or CASE"]
    assert check_errors(body("FOR i = 1 TO 3")) == ["T step 1: FOR without END"]
    assert check_errors(body("CASE x OF", "ANY", "VALUE 2:", "END"))[0].startswith("T step 3: VALUE after ANY")
    assert check_errors(body("MOVE a b")) and check_errors(body("FROB 3"))[0].endswith(
        "FROB IS NOT A V+ INSTRUCTION THE SIMULATOR KNOWS")


def test_a_bad_step_stops_a_vplus_program_too() -> None:
    _, events = vplus(body('TYPE "BEFORE"', "FROB 3", 'TYPE "AFTER"'))
    assert typed(events) == ["BEFORE"] and errors(events)[0].step == 2 and not completed(events)


# -- expressions ----------------------------------------------------------------------------

def test_functions_arrays_dotted_names_and_operators() -> None:
    _, events = vplus(body("z.pick = 80", "a[2] = z.pick/4", "t[1,2] = 3",
                           'TYPE SQRT(16), " ", ABS(-2), " ", INT(-2.7), " ", MOD(7, 3), " ", SIGN(-5)',
                           'TYPE MAX(1, a[2], 3), " ", MIN(4, t[1,2]), " ", /F5.1, ATAN2(1, 1), SIN(30), COS(60)',
                           'TYPE 2^3, " ", 6 BAND 3, " ", 6 BOR 1, " ", 7 MOD 4, " ", TAN(45)'))
    assert typed(events) == ["4 2 -2 1 -1", "20 3  45.0  0.5  0.5", "8 2 7 3 1"]


def test_strings_and_formats() -> None:
    _, events = vplus(body('$a = "Pick"', '$b = $a + " and place"', "x = 3.14159",
                           'TYPE $b, ":", /F7.3, x, /X2, /I3, 42, /D, " ", x', '$c = $ENCODE(/F4.1, x)', "TYPE $c"))
    assert typed(events) == ["Pick and place:  3.142   42 3.14159", " 3.1"]


@pytest.mark.parametrize("line, message", [("x = SQRT(-1)", "NOT A NUMBER (MATH DOMAIN ERROR)"),
                                           ("y = 10^400", "NUMBER TOO LARGE"),
                                           ("z = MOD(1, 0)", "NOT A NUMBER (MATH DOMAIN ERROR)")])
def test_math_errors_are_reported_not_raised(line: str, message: str) -> None:
    _, events = vplus(body(line, 'TYPE "ON"'))
    assert [e.message for e in errors(events)] == [message]
    assert typed(events) == []  # as the controller does: the program stops at the step (issue 36)


def test_an_undefined_variable_or_string_stops_with_its_name() -> None:
    _, events = vplus(body("TYPE $nothing"))
    assert "STRING $NOTHING IS NOT DEFINED" in errors(events)[0].message
    _, events = vplus(body("x = y+1", 'TYPE "NOT HERE"'))
    assert errors(events)[0].message == "VARIABLE Y IS NOT DECLARED"


# -- CALL -----------------------------------------------------------------------------------

def test_call_passes_variables_by_reference_and_expressions_by_value() -> None:
    text = body("a = 1", "b = 2", "CALL swap(a, b)", "CALL twice(a+10, r)", 'TYPE a, " ", b, " ", r') + (
        ".PROGRAM swap(x, y)\n    AUTO tmp\n    tmp = x\n    x = y\n    y = tmp\n.END\n"
        ".PROGRAM twice(v, out)\n    out = 2*v\n    v = 0\n.END\n")
    interpreter, events = vplus(text)
    assert typed(events) == ["2 1 24"]
    assert "TMP" not in interpreter.variables and "X" not in interpreter.variables  # the callee's own


def test_recursion_keeps_each_calls_parameters() -> None:
    text = body("CALL fact(6, r)", 'TYPE r') + (
        ".PROGRAM fact(n, result)\n    AUTO sub\n    IF n <= 1 THEN\n        result = 1\n    ELSE\n"
        "        CALL fact(n-1, sub)\n        result = n*sub\n    END\n.END\n")
    _, events = vplus(text)
    assert typed(events) == ["720"]


def test_endless_recursion_and_wrong_argument_counts_stop_the_run() -> None:
    _, events = vplus(body("CALL down(1)") + ".PROGRAM down(n)\n    CALL down(n+1)\n.END\n")
    assert "MORE THAN 20 NESTED CALLS" in errors(events)[-1].message and not completed(events)
    _, events = vplus(body("CALL one(1, 2)") + ".PROGRAM one(n)\n    TYPE n\n.END\n")
    assert "2 ARGUMENTS FOR 1 PARAMETERS" in errors(events)[0].message


# -- transformations, precision points ---------------------------------------------------------

def test_transformations_compose_invert_and_decompose() -> None:
    sim = Simulator(None)
    sim.locations["C"] = Location((-180.0, 600.0, -204.16), (90.0, 90.0, -90.0))
    sim.locations["D"] = Location((-100.0, 600.0, -204.16), (90.0, 90.0, -90.0))
    _, events = vplus(body("SET f = FRAME(c, d, SHIFT(c BY 0, -100, 0), c)",
                           "SET back = f:INVERSE(f):c", "DECOMPOSE v[0] = back",
                           'TYPE /F8.2, v[0], v[1], v[2], DISTANCE(back, c), DX(INVERSE(f):d)',
                           "SET r = RZ(90):TRANS(10, 0, 0)", 'TYPE /F6.1, DX(r), DY(r), DZ(r)'), sim)
    assert typed(events) == [" -180.00  600.00 -204.16    0.00   80.00", "   0.0  10.0   0.0"]
    assert np.allclose(sim.locations["BACK"].xyz, sim.locations["C"].xyz)


def test_precision_points_are_joint_angles() -> None:
    sim = Simulator(None)
    interpreter, events = vplus(body("HERE #home", "DRIVE 1, 30, 100", "HERE #turned", "MOVE #home",
                                     "DECOMPOSE j[1] = #turned", "TYPE j[1], \" \", j[2]"), sim)
    assert not errors(events)
    assert typed(events) == ["30 -90"]
    assert sim.joints[0] == pytest.approx(0.0)
    assert interpreter.machine.precision["#TURNED"][0] == pytest.approx(30.0)


# -- signals ----------------------------------------------------------------------------------

def test_signals_set_outputs_and_refuse_inputs() -> None:
    _, events = vplus(body("SIGNAL 1, 2, -1", "TYPE SIG(2), SIG(-1), SIG(1, 2)", "STATUS", "SIGNAL 1001"))
    assert [(e.number, e.on) for e in events if isinstance(e, Signal)] == [(1, True), (2, True), (1, False)]
    assert typed(events)[:2] == ["-1 -1 0", "SIGNALS ON: OUTPUTS 2  INPUTS NONE"]  # V+ separates numbers
    assert "1001 IS AN INPUT" in errors(events)[0].message


def test_wait_needs_a_scripted_input_and_time_passes() -> None:
    from valterm.core.signals import parse_inputs

    text = body("TIMER 2 = 0", "WAIT SIG(1005)", "WAIT.EVENT , 1.5", 'TYPE /F5.1, TIMER(2)')
    programs = {b.program.name: b.program for b in parse_vplus(text, "T.v2")}
    interpreter = Interpreter(Simulator(None), lambda name: programs[name], {})
    interpreter.machine.inputs = parse_inputs("2.0 1005 1\n", "in.txt")
    events = list(interpreter.execute("T"))
    assert typed(events) == ["  3.5"]
    _, events = vplus(body("WAIT SIG(1005)"))
    assert "NEVER BECOMES TRUE" in errors(events)[0].message


# -- dialects and files -----------------------------------------------------------------------

def test_react_calls_its_program_once_when_the_signal_changes() -> None:
    text = body("REACT 2001, alarm", "REACT -1002, gone", "IGNORE -1002", "SIGNAL 2001", 'TYPE "BACK"',
                "SIGNAL -2001", "SIGNAL 2001", 'TYPE "END"') + '.PROGRAM alarm()\n    TYPE "ALARM"\n.END\n'
    _, events = vplus(text)
    assert typed(events) == ["ALARM", "BACK", "END"]  # once: REACT must be given again to re-arm
    assert any(isinstance(e, Message) and e.text == "REACT 2001: CALL ALARM" for e in events)
    _, events = vplus(body("REACT 99999, x"))
    assert "THERE IS NO SIGNAL 99999" in errors(events)[0].message


def test_dialects_are_checked_and_named() -> None:
    assert check_dialect("V+") == "v+" and check_dialect("vplus") == "v+" and check_dialect("1985") == "1985"
    with pytest.raises(ValueError, match="use 1985 or v\\+"):
        check_dialect("VAL3")
    program = program_from_lines("P", ["FOR i = 1 TO 2", "END"])
    assert check_program(program).against == "DIALECT 1985 (COMMAND.DAT)"
    assert not check_program(program).ok
    report = check_program(program, dialect="v+")
    assert report.ok and report.against.startswith("DIALECT V+")


def test_the_thesis_programs_run_the_same_in_a_vplus_interpreter_only_when_asked() -> None:
    # a .DAT program is 1985 unless --dialect v+: its unquoted TYPE text is not V+
    program = Program("P", program_from_lines("P", ["TYPE PICK UP THE PART"]).steps)
    interpreter = Interpreter(Simulator(None), lambda name: program, {})
    assert typed(list(interpreter.execute("P"))) == ["PICK UP THE PART"]
    interpreter = Interpreter(Simulator(None), lambda name: program, {}, dialect="v+")
    assert errors(list(interpreter.execute("P")))


def test_location_files_hold_dotted_names_and_precision_points(tmp_path: Path) -> None:
    text = "POINT pick.1, 400, 0, -200, 0, 90, 0\nPOINT #SAFE, 0, -90, 90, 0, 0, 0\nPOINT A, 1, 2, 3, 4, 5, 6\n"
    points: dict[str, tuple[float, ...]] = {}
    found = parse_locations(text, "X.LOC", points)
    assert list(found) == ["PICK.1", "A"] and points == {"#SAFE": (0.0, -90.0, 90.0, 0.0, 0.0, 0.0)}
    assert parse_locations(format_locations(found), "Y.LOC") == found
    path = tmp_path / "X.LOC"
    path.write_text(text)
    assert read_location_file(path)[1] == points
    with pytest.raises(FileFormatError, match="JT1..JT6"):
        parse_locations("POINT #P, 1, 2\n", "Z.LOC")


def test_export_program_round_trips_and_runs_the_same(capsys: pytest.CaptureFixture[str], tmp_path: Path,
                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)  # --out is relative to the current folder
    assert main(["--workspace", str(tmp_path), "export-program", "CONV1", "--with-calls", "--out", "conv.v2"]) == 0
    assert "2 program(s) written (CONV1, CONV2)" in capsys.readouterr().out
    blocks = read_vplus(tmp_path / "conv.v2")
    assert [b.program.name for b in blocks] == ["CONV1", "CONV2"]
    assert all(b.program.dialect == "1985" for b in blocks)
    original = (PROGRAMS / "CONV1.DAT").read_text().splitlines()
    assert [s.text for s in blocks[0].program.steps] == [line.strip().split(None, 1)[-1] if line[:4].strip()
                                                         else line.strip() for line in original if line.strip()]
    assert format_vplus(blocks) == (tmp_path / "conv.v2").read_text()
    ends = []
    for program in ("CONV1", str(tmp_path / "conv.v2")):  # both stop where CONV1's wrist meets its stop
        capsys.readouterr()
        # the same rules for both (a V+ file's default is the controller's): the real wrist's stop
        assert main(["--workspace", str(tmp_path), "run", program, "--cell", "CONV.SET", "--loc", "CONV.LOC",
                     "--json", "--rules", "controller"]) == 1
        lines = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
        ends.append(([e for e in lines if e["event"] == "error"], lines[-1]["where"]))
    assert ends[0] == ends[1] and ends[0][0]
    assert main(["--workspace", str(tmp_path), "export-program", "CONV1", "--out", "x.txt"]) == 2


def test_run_config_inputs_and_dialect_options(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    program = tmp_path / "REACH.DAT"
    program.write_text("    MOVE A\n")
    common = ["--workspace", str(tmp_path), "run", str(program), "--loc", "PROCESS.LOC", "--json"]
    assert main(common) == 1  # RIGHTY (the default) cannot reach A
    assert main([*common, "--config", "LEFTY,ABOVE,NOFLIP"]) == 0
    assert json.loads(capsys.readouterr().out.splitlines()[-1])["where"]["config"]["arm"] == "LEFTY"
    assert main([*common, "--config", "LEFT"]) == 2
    assert "LEFT is not one of" in capsys.readouterr().err
    bad = tmp_path / "in.txt"
    bad.write_text("1.0 7 1\n")
    assert main([*common, "--inputs", str(bad)]) == 1
    assert "in.txt:1" in capsys.readouterr().err
    loop = tmp_path / "LOOP.DAT"
    loop.write_text('    FOR i = 1 TO 2\n    TYPE "I=", i\n    END\n')
    assert main(["--workspace", str(tmp_path), "run", str(loop), "--dialect", "v+"]) == 0
    assert "I=2" in capsys.readouterr().out
    assert main(["--workspace", str(tmp_path), "run", str(loop)]) == 1
