"""V+ forms found in published programs (issue 23 follow-up): each test is a small program of
our own that uses the same statement or function, with values worked out from the V+ reference."""

from __future__ import annotations

from pathlib import Path

import pytest

from valterm.cli import main
from valterm.core.events import Event, TypeOut
from valterm.core.files.vplus import parse_vplus
from valterm.core.simulator import Simulator
from valterm.core.val.interpreter import Interpreter


def vplus(text: str) -> tuple[Interpreter, list[Event]]:
    programs = {b.program.name: b.program for b in parse_vplus(text, "T.v2")}
    interpreter = Interpreter(Simulator(None), lambda name: programs[name], {})
    return interpreter, list(interpreter.execute(next(iter(programs))))


def body(*lines: str) -> str:
    return ".PROGRAM t()\n" + "\n".join(f"    {line}" for line in lines) + "\n.END\n"


def typed(*lines: str) -> list[str]:
    _, events = vplus(body(*lines))
    return [e.text for e in events if isinstance(e, TypeOut)]


def check(tmp_path: Path, capsys: pytest.CaptureFixture[str], text: str) -> tuple[int, list[str]]:
    program = tmp_path / "c.v2"
    program.write_text(text)
    capsys.readouterr()
    status = main(["--workspace", str(tmp_path / "ws"), "check", str(program)])
    return status, capsys.readouterr().out.splitlines()


def test_a_case_whose_selector_does_not_decode_is_reported_not_a_crash(
        capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    status, lines = check(tmp_path, capsys, body("CASE NOSUCH(5) OF", "  VALUE 1:", "    x = 1",
                                                 "  ANY", "    x = 2", "END", "TYPE 1"))
    assert status == 1
    assert any("T step 1: CASE: NOSUCH is not a V+ function" in line for line in lines), lines
    assert any(line.startswith("T: 7 steps, 1 error(s)") for line in lines), lines


def test_byte_functions_pack_and_unpack_the_most_significant_byte_first() -> None:
    assert typed('$s = $LNGB(-2)+$INTB(258)+$FLTB(1.5)',
                 "TYPE LEN($s), LNGB($s), INTB($s, 5), FLTB($s, 7)",
                 "TYPE ASC($s, 1), ASC($s, 4), ASC($s, 5), ASC($s, 6), ASC($s, 7)",
                 "TYPE LNGB($LNGB(123456789)), $LNGB(2.6) == $LNGB(3), DBLB($DBLB(0.1)) == 0.1",
                 '$t = $CHR(64)+$CHR(73)+$CHR(15)+$CHR(219)', "TYPE /F8.5, FLTB($t)") == [
        "10 -2 258 1.5",  # 4 + 2 + 4 characters
        "255 254 1 2 63",  # -2 is FF FF FF FE; 258 is 01 02; 1.5 is 3F C0 00 00
        "123456789 -1 -1",  # a value is rounded to the nearest integer
        " 3.14159",  # 40 49 0F DB is single-precision pi
    ]


@pytest.mark.parametrize(("line", "message"), [
    ("TYPE LNGB(\"ABC\")", "LNGB: NEEDS 4 CHARACTERS FROM CHARACTER 1; THE STRING HAS 3"),
    ("$s = $INTB(40000)", "$INTB: 40000 IS NOT A 16-BIT INTEGER"),
])
def test_byte_functions_refuse_short_strings_and_large_values(line: str, message: str) -> None:
    from valterm.core.events import Error

    _, events = vplus(body(line))
    assert any(isinstance(e, Error) and message in e.message for e in events), events


def test_string_arrays_concatenated_type_items_and_defined() -> None:
    assert typed('$a[1] = "ONE"', '$a[2] = "TWO"', "i = 2",
                 'TYPE "got: "+$a[i]+"!", " ", $a[1]+$a[i], /F5.1, 3',
                 "TYPE DEFINED(i), DEFINED(zz), DEFINED($a[1]), DEFINED($a[3]), DEFINED($b), DEFINED(k[1])",
                 "SET p = TRANS(1, 2, 3)", "TYPE DEFINED(p), DEFINED(q)",
                 'TYPE "x = "+$ENCODE(/F4.1, i)') == [
        "got: TWO! ONETWO  3.0", "-1 0 -1 0 0 0", "-1 0", "x =  2.0"]


def test_a_string_array_element_is_passed_by_reference() -> None:
    text = body('$in = "ABCD"', "i = 3", "CALL rev($in, $out[i])", "CALL rev($out[3], $back)",
                'TYPE $out[3], " ", $back, " ", LAST($out[])')
    text += ".PROGRAM rev($a, $b)\n  AUTO k\n  $b = \"\"\n  FOR k = LEN($a) TO 1 STEP -1\n" \
            "    $b = $b+$MID($a, k, 1)\n  END\n.END\n"
    _, events = vplus(text)
    assert [e.text for e in events if isinstance(e, TypeOut)] == ["DCBA ABCD 3"]


def test_accel_takes_a_profile_number_in_parentheses(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    status, lines = check(tmp_path, capsys, body("ACCEL (1) 100, 50", "ACCEL (2) 80", "ACCEL 50, 50 ALWAYS",
                                                 "ACCEL (FOO(1)) 100"))
    assert status == 1
    assert [line for line in lines if " step " in line] == [
        "c.v2:5: T step 4: ACCEL: FOO is not a V+ function the simulator knows"], lines


def test_array_elements_are_call_arguments_by_reference() -> None:
    text = body("AUTO p[3], k[2]", "SET p[1] = TRANS(100, 0, 0)", "SET p[2] = TRANS(0, 50, 0)", "k[1] = 4",
                "FOR i = 1 TO 2", "  CALL lift(p[i], k[1])", "END",
                "DECOMPOSE d[1] = p[1]", "DECOMPOSE e[1] = p[2]",
                "TYPE d[1], d[3], e[2], e[3], k[1]")
    text += ".PROGRAM lift(loc, n)\n  SET loc = SHIFT(loc BY 0, 0, 10 * n)\n  n = n + 1\n.END\n"
    _, events = vplus(text)
    assert [e.text for e in events if isinstance(e, TypeOut)] == ["100 40 50 50 6"]


def test_select_robot_1_and_attaching_the_robot_run_other_robots_stop() -> None:
    from valterm.core.events import Error

    _, events = vplus(body("SELECT ROBOT = 1", "ATTACH ()", "ATTACH", "DETACH (0)", 'TYPE "ok"', "r = 2",
                           "SELECT ROBOT = r", 'TYPE "never"'))
    assert [e.text for e in events if isinstance(e, TypeOut)] == ["ok"]
    assert [e.message for e in events if isinstance(e, Error)] == [
        "SELECT ROBOT = 2: THE SIMULATOR HAS ONE ROBOT, ROBOT 1"]


def test_check_names_device_and_task_statements_as_the_controller_s_warnings_not_errors(
        capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    # real V+ accepts these lines: check warns (no error), a run stops at the first (issue 23)
    status, lines = check(tmp_path, capsys, body('ATTACH (lun, 4) "TCP"', "x = IOSTAT(lun)", "EXECUTE 2 t()",
                                                 "IF TASK(1) <> 4 THEN", "END", "DETACH (lun)",
                                                 'TYPE "failed: "+$ERROR(x)'))
    assert status == 1  # check's exit says something was reported
    assert any(", 0 error(s), 6 warning(s)" in line for line in lines), lines
    warned = [line.split(": ", 2)[2] for line in lines if " step " in line]
    assert all(w.startswith("warning: ") and w.endswith("(a real controller accepts it; a run stops here)")
               for w in warned), warned
    steps = [w.removeprefix("warning: ").removesuffix(" (a real controller accepts it; a run stops here)")
             for w in warned]
    assert steps == [
        "ATTACH IS A V+ STATEMENT FOR THE CONTROLLER'S I/O DEVICES (DISK, NETWORK, SERIAL LINES), "
        "WHICH THE SIMULATOR DOES NOT HAVE",
        "ASSIGNMENT TO X: IOSTAT is a V+ function of the I/O devices (disk, network, serial lines), "
        "which the simulator does not have",
        "EXECUTE IS A V+ STATEMENT FOR OTHER PROGRAM TASKS OR ROBOTS, WHICH THE SIMULATOR DOES NOT HAVE "
        "(ONE TASK, ONE ROBOT)",
        "IF: TASK is a V+ function of program tasks and the robot's state, which the simulator does not have",
        "DETACH IS A V+ STATEMENT FOR THE CONTROLLER'S I/O DEVICES (DISK, NETWORK, SERIAL LINES), "
        "WHICH THE SIMULATOR DOES NOT HAVE",
        "TYPE: $ERROR is a V+ function of the controller's table of error messages, which the simulator "
        "does not have",
    ], lines


def test_a_wait_alone_lets_one_major_cycle_pass_so_a_polling_loop_sees_its_input() -> None:
    from valterm.core.signals import parse_inputs

    text = body("TIMER 1 = 0", "n = 0", "WHILE SIG(-1001) DO", "  WAIT", "  n = n + 1", "END",
                "TYPE n, TIMER(1)")
    programs = {b.program.name: b.program for b in parse_vplus(text, "T.v2")}
    interpreter = Interpreter(Simulator(None), lambda name: programs[name], {})
    interpreter.machine.inputs = parse_inputs("0.1 1001 1\n", "in.txt")
    events = list(interpreter.execute("T"))
    # 16 ms a cycle: the input is seen after the 7th (0.112 s), never in a busy loop
    assert [e.text for e in events if isinstance(e, TypeOut)] == ["7 0.112"]


def test_an_expression_of_array_elements_is_still_passed_by_value() -> None:
    text = body("a[1] = 2", "a[2] = 3", '$s[1] = "X"', '$s[2] = "Y"', "CALL show(a[1]+a[2], $s[1]+$s[2])",
                'TYPE a[1], a[2], " ", $s[1], $s[2]')
    text += ".PROGRAM show(n, $t)\n  TYPE n, \" \", $t\n  n = 0\n  $t = \"\"\n.END\n"
    _, events = vplus(text)
    assert [e.text for e in events if isinstance(e, TypeOut)] == ["5 XY", "2 3 XY"]


def test_a_run_stops_at_the_first_statement_only_a_controller_can_run() -> None:
    from valterm.core.events import Error

    _, events = vplus(body('TYPE "before"', 'ATTACH (lun, 4) "TCP"', 'TYPE "never"'))
    assert [e.text for e in events if isinstance(e, TypeOut)] == ["before"]
    [error] = [e for e in events if isinstance(e, Error)]
    assert error.step == 2 and "I/O DEVICES" in error.message


def test_an_unknown_string_function_is_named_whatever_its_arguments(
        capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    """A string function the simulator does not know is said so, not taken for its argument's
    error (its string argument read as a number said "a string is not a number"); a known one
    given the wrong count says what it takes."""
    status, lines = check(tmp_path, capsys, body('$u = $NOSUCH("mixed Case")', "$v = $NOSUCH(1, 2)",
                                                 '$w = $CHR(65, 66)', 'TYPE $NOSUCH("x")'))
    assert status == 1
    assert [line for line in lines if " step " in line] == [
        "c.v2:2: T step 1: ASSIGNMENT TO $U: $NOSUCH is not a V+ string function the simulator knows",
        "c.v2:3: T step 2: ASSIGNMENT TO $V: $NOSUCH is not a V+ string function the simulator knows",
        "c.v2:4: T step 3: ASSIGNMENT TO $W: $CHR takes one value: $CHR(value)",
        "c.v2:5: T step 4: TYPE: $NOSUCH is not a V+ string function the simulator knows"], lines
