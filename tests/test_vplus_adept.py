"""V+ as Adept defines it (issue 23): transformations in X Y Z yaw pitch roll through the
interpreter and `valterm run`, TYPE's number formats, and `run NAME` for workspace V+ programs.
Expected values are computed by hand from the V+ definitions (R = RZ(yaw) RY(pitch) RZ(roll))."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from app_helpers import until

from valterm.cli import main
from valterm.core.events import Event, TypeOut, Where
from valterm.core.files.vplus import parse_vplus
from valterm.core.kinematics import Location
from valterm.core.simulator import Simulator
from valterm.core.text.transcript import where_lines
from valterm.core.val.interpreter import Interpreter


def vplus(text: str, sim: Simulator | None = None) -> tuple[Interpreter, list[Event]]:
    programs = {b.program.name: b.program for b in parse_vplus(text, "T.v2")}
    interpreter = Interpreter(sim or Simulator(None), lambda name: programs[name], {})
    return interpreter, list(interpreter.execute(next(iter(programs))))


def body(*lines: str) -> str:
    return ".PROGRAM t()\n" + "\n".join(f"    {line}" for line in lines) + "\n.END\n"


def typed(events: list[Event]) -> list[str]:
    return [e.text for e in events if isinstance(e, TypeOut)]


def decomposed(expression: str, sim: Simulator | None = None) -> list[float]:
    _, events = vplus(body(f"DECOMPOSE v[1] = {expression}",
                           "TYPE /F12.4, v[1], v[2], v[3], v[4], v[5], v[6]"), sim)
    lines = typed(events)
    assert len(lines) == 1, events
    return [float(v) for v in lines[0].split()]


TABLE = [  # the table
    ("TRANS(0,0,0,0,0,0):TRANS(0,0,50)", (0, 0, 50, 0, 0, 0)),
    ("TRANS(100,200,300,30,40,50):TRANS(0,0,50)", (127.83, 216.07, 338.30, 30, 40, 50)),
    ("INVERSE(TRANS(100,200,300,30,40,50))", (-62.31, -117.41, -349.76, 130, 40, 150)),
    ("NULL", (0, 0, 0, 0, 0, 0)),
    ("TRANS(100,200,300,30,40,50):INVERSE(TRANS(100,200,300,30,40,50))", (0, 0, 0, 0, 0, 0)),
]
MORE = [  # a dozen more, from the V+ definitions
    ("TRANS(300,200,100,0,180,0):TRANS(0,0,100)", (300, 200, 0, 0, 180, 0)),
    ("TRANS(0,0,0,90,0,0):TRANS(10,0,0)", (0, 10, 0, 0, 0, 90)),
    ("TRANS(0,0,0,0,90,0):TRANS(0,0,10)", (10, 0, 0, 0, 90, 0)),
    ("TRANS(0,0,0,0,90,90):TRANS(10,0,0)", (0, 10, 0, 0, 90, 90)),
    ("RX(90):TRANS(0,10,0)", (0, 0, 10, -90, 90, 90)),
    ("RZ(45)", (0, 0, 0, 0, 0, 45)),
    ("INVERSE(TRANS(10,0,0,90,0,0))", (0, 10, 0, 0, 0, -90)),
    ("SHIFT(TRANS(1,2,3,10,20,30) BY 10,0,-5)", (11, 2, -2, 10, 20, 30)),
    ("TRANS(0,0,0,10,-20,30)", (0, 0, 0, -170, 20, -150)),
    ("TRANS(5,6,7,0,180,45)", (5, 6, 7, 0, 180, 45)),
    ("TRANS(5,6,7,-45,180,0)", (5, 6, 7, 0, 180, 45)),
    ("FRAME(TRANS(0,0,0), TRANS(0,10,0), TRANS(-5,0,0), TRANS(1,2,3))", (1, 2, 3, 0, 0, 90)),
    ("TRANS(1,2,3,30,40,50):TRANS(4,5,6,-60,70,-80):INVERSE(TRANS(4,5,6,-60,70,-80))", (1, 2, 3, 30, 40, 50)),
]


@pytest.mark.parametrize(("expression", "expected"), TABLE + MORE)
def test_decompose_in_the_interpreter(expression: str, expected: tuple[float, ...]) -> None:
    assert np.allclose(decomposed(expression), expected, atol=0.01)


def test_yaw_pitch_roll_round_trip_through_a_stored_location() -> None:
    # SET stores the pose (the simulator keeps O A T); DECOMPOSE gives back the same six numbers
    for angles in ((30, 40, 50), (-120, 135, 170), (0, 180, 0), (90, 90, -90)):
        _, events = vplus(body(f"SET p = TRANS(400, -100, 250, {angles[0]}, {angles[1]}, {angles[2]})",
                               "DECOMPOSE v[1] = p", "TYPE /F10.3, v[4], v[5], v[6]"))
        assert np.allclose([float(v) for v in typed(events)[0].split()], angles, atol=0.01)


def test_distance_and_dx_dy_dz() -> None:
    _, events = vplus(body("SET b = TRANS(100,200,300,30,40,50)", "SET c = b:TRANS(0,0,50)",
                           "TYPE /F9.2, DISTANCE(b, c), DX(c), DY(c), DZ(c)"))
    assert [float(v) for v in typed(events)[0].split()] == pytest.approx([50, 127.83, 216.07, 338.30], abs=0.01)


def test_a_workspace_location_is_the_same_pose_in_both_dialects() -> None:
    sim = Simulator(None)
    sim.locations["DOWN"] = Location((400.0, 0.0, 0.0), (90.0, 90.0, 0.0))  # the thesis's tool down
    assert np.allclose(decomposed("down", sim), (400, 0, 0, 0, 180, 0), atol=0.01)
    # 50 mm along the tool's Z of a tool pointing down is 50 mm lower
    assert np.allclose(decomposed("down:TRANS(0,0,50)", sim)[:3], (400, 0, -50), atol=0.01)


def test_here_and_where_in_yaw_pitch_roll() -> None:
    _, events = vplus(body("DECOMPOSE v[1] = HERE", "TYPE /F8.2, v[4], v[5], v[6]", "WHERE"))
    assert typed(events)[0].split() == ["0.00", "0.00", "0.00"]  # READY: the tool straight up
    where = next(e for e in events if isinstance(e, Where))
    assert where.ypr == (0.0, 0.0, 0.0) and where.oat == (90.0, -90.0, 0.0)
    head, values = where_lines(where)[:2]
    assert head.split() == ["OPENED", "X", "Y", "Z", "YAW", "PITCH", "ROLL"]
    assert values.split()[1:] == ["0.00", "158.75", "990.60", "0.00", "0.00", "0.00"]


def test_valterm_run_gives_the_table_and_the_other_cases(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    lines = [f"DECOMPOSE v[1] = {expression}" + "\n    TYPE /F10.2, v[1], v[2], v[3], v[4], v[5], v[6]"
             for expression, _ in TABLE + MORE]
    program = tmp_path / "table.v2"
    program.write_text(body(*lines))
    assert main(["--workspace", str(tmp_path / "ws"), "run", str(program), "--json"]) == 0
    events = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    outputs = [[float(v) for v in e["text"].split()] for e in events if e["event"] == "type"]
    assert len(outputs) == len(TABLE + MORE)
    for got, (_, expected) in zip(outputs, TABLE + MORE):
        assert np.allclose(got, expected, atol=0.01)
    end = events[-1]
    assert end["event"] == "end" and end["where"]["ypr"] == [0.0, 0.0, 0.0]


# -- TYPE -------------------------------------------------------------------------------------

def test_type_separates_numbers_and_types_rounding_noise_as_zero() -> None:
    _, events = vplus(body("TYPE 100, 200, 300, 0, COS(90), -5",
                           'TYPE "T", 0, " X=", 2.5', "TYPE /F6.2, -COS(90), 1, /D, 3, 4",
                           "TYPE 1/3", "TYPE /I1, 1, 2"))
    assert typed(events) == ["100 200 300 0 0 -5", "T0 X=2.5", "  0.00  1.00 3 4", "0.333333", "12"]


# -- run NAME ---------------------------------------------------------------------------------

def test_run_finds_a_program_of_a_workspace_vplus_file(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    workspace = tmp_path / "ws"
    assert main(["--workspace", str(workspace), "run", "nothing.here"]) == 1  # seeds the workspace
    (workspace / "CELLJOB.V2").write_text(body('TYPE "MAIN"') + ".PROGRAM pick.part()\n    TYPE \"PICKED\"\n.END\n")
    capsys.readouterr()
    assert main(["--workspace", str(workspace), "run", "pick.part"]) == 0
    assert "PICKED" in capsys.readouterr().out
    assert main(["--workspace", str(workspace), "run", "t"]) == 0
    assert "MAIN" in capsys.readouterr().out
    assert main(["--workspace", str(workspace), "run", "no.such"]) == 1


# -- one clock: waits take simulated time ------------------------------------------------------

BLINK = """.PROGRAM blink()
    ; output 1 on for 0.5 s, off for 0.25 s, three times; then output 2 blinks with DELAY
    AUTO i, n
    FOR i = 1 TO 3
        SIGNAL 1
        TIMER 1 = 0
        WAIT TIMER(1) > 0.5
        SIGNAL -1
        TIMER 1 = 0
        WAIT TIMER(1) >= 0.25
    END
    n = 0
    WHILE n < 2 DO
        SIGNAL 2
        DELAY 1
        SIGNAL -2
        WAIT.EVENT , 0.5
        n = n+1
    END
.END
"""


def test_a_blink_program_runs_its_whole_length(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    program = tmp_path / "blink.v2"
    program.write_text(BLINK)
    assert main(["--workspace", str(tmp_path / "ws"), "run", str(program), "--json"]) == 0
    events = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    signals = [(e["number"], e["on"], e["time"]) for e in events if e["event"] == "signal"]
    assert signals == [
        (1, True, 0.0), (1, False, 0.5), (1, True, 0.75), (1, False, 1.25), (1, True, 1.5), (1, False, 2.0),
        (2, True, 2.25), (2, False, 3.25), (2, True, 3.75), (2, False, 4.75)]
    assert events[-1]["cycle_time_s"] == pytest.approx(5.25, abs=1e-3)


def test_a_wait_ends_at_an_input_or_a_timer_whichever_comes_first() -> None:
    from valterm.core.signals import parse_inputs

    text = body("TIMER 1 = 0", "WAIT SIG(1001) OR TIMER(1) > 5", "TYPE /F6.2, TIMER(1)",
                "WAIT SIG(1002) OR TIMER(1) > 5", "TYPE /F6.2, TIMER(1)",
                "WAIT TIMER(1) > 3600+10")
    programs = {b.program.name: b.program for b in parse_vplus(text, "T.v2")}
    interpreter = Interpreter(Simulator(None), lambda name: programs[name], {})
    interpreter.machine.inputs = parse_inputs("2.0 1001 1\n9.0 1002 1\n", "in.txt")
    events = list(interpreter.execute("T"))
    assert typed(events) == ["  2.00", "  5.00"]
    errors = [e.message for e in events if e.event == "error"]
    assert errors == []  # no hidden limit: 3610 s is inside the run's limit of robot time (one day)
    assert interpreter.cycle_seconds == pytest.approx(3610.0, abs=1e-3)


def test_a_wait_nothing_can_end_stops_at_once() -> None:
    interpreter, events = vplus(body("TIMER 1 = 0", "WAIT TIMER(1) < 0"))
    assert [e.message for e in events if e.event == "error"] == [
        "WAIT TIMER(1) < 0: IT NEVER BECOMES TRUE (NO MORE INPUTS ARE SCRIPTED)"]
    assert interpreter.cycle_seconds == 0.0  # looking ahead took no time


# -- statements and functions real programs use -------------------------------------------------

def test_exit_and_next_leave_or_continue_loops() -> None:
    _, events = vplus(body(
        "FOR i = 1 TO 10", "  IF i == 2 THEN", "    NEXT", "  END", "  FOR j = 1 TO 10",
        "    IF j > 2 THEN", "      EXIT", "    END", "    IF i == 4 THEN", "      EXIT 2", "    END",
        "    TYPE i, j", "  END", "END",
        "n = 0", "WHILE n < 5 DO", "  n = n+1", "  IF n == 3 THEN", "    NEXT", "  END", '  TYPE "W", n', "END",
        "DO", "  n = n-1", "  IF n == 2 THEN", "    EXIT", "  END", "UNTIL n < 0", 'TYPE "N", n'))
    assert typed(events) == ["1 1", "1 2", "3 1", "3 2", "W1", "W2", "W4", "W5", "N2"]


def test_exit_outside_a_loop_is_reported_by_check(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    program = tmp_path / "bad.v2"
    program.write_text(body("FOR i = 1 TO 2", "  EXIT 2", "END", "EXIT"))
    assert main(["--workspace", str(tmp_path / "ws"), "check", str(program)]) == 1
    out = capsys.readouterr().out
    assert "EXIT 2: NOT INSIDE 2 NESTED LOOPS" in out and "EXIT 1: NOT INSIDE A LOOP" in out


def test_string_functions_bmask_and_last() -> None:
    _, events = vplus(body(
        '$s = "HELLO WORLD"',
        'TYPE LEN($s), " ", $LEFT($s, 5), "|", $MID($s, 7, 3), "|", $MID($s, 7), "|", $MID($s, 20, 2), "|"',
        "TYPE BMASK(1), BMASK(3), BMASK(1, 3), BMASK(1, 2, 3, 4)",
        "a[1] = 3", "a[7] = 2", "SET p[4] = TRANS(1, 2, 3)", '$n[2] = "X"',
        "TYPE LAST(a[]), LAST(b[]), LAST(p[]), LAST($n[])",
        'TYPE VAL("12.5X"), ASC("A"), LEN("")',
        'IF LEN($s) > 3 AND $LEFT($s, 1) == "H" AND $s <> "X" THEN', '  TYPE "OK"', "END"))
    assert typed(events) == ["11 HELLO|WOR|WORLD||", "1 4 5 15", "7 -1 4 2", "12.5 65 0", "OK"]


def test_precision_points_from_joint_angles() -> None:
    sim = Simulator(None)
    interpreter, events = vplus(body(
        "SET #p = #PPOINT(30, -90, 90, 0, 0, 0)", "MOVE #p", "DECOMPOSE j[1] = #p", "TYPE j[1], j[2], j[3]",
        "#q = #PPOINT(10)", "DECOMPOSE j[1] = #PPOINT(1, 2, 3)", "TYPE j[1], j[2], j[3], j[4]",
        "SET a = #PPOINT(0, -90, 90, 0, 0, 0)", "DECOMPOSE j[1] = a", "TYPE /F8.2, j[1], j[2], j[3], j[5]"), sim)
    assert typed(events) == ["30 -90 90", "1 2 3 0", "    0.00  158.75  990.60    0.00"]
    assert sim.joints[0] == pytest.approx(30.0)
    assert interpreter.machine.precision["#Q"] == (10.0, 0.0, 0.0, 0.0, 0.0, 0.0)


# -- V+ files: data sections, 8-bit comments, one problem does not refuse the file ------------

STORED = b""".REALS
count  2
.END
; a comment in latin-1: caf\xe9
.PROGRAM main(x y, 1bad)
    TYPE $ENCODE(/L, 5)
    FOO BAR
.END
.PROGRAM good()
    TYPE count, " ", $title, " ", LAST(slot[])
    DECOMPOSE v[1] = pick.1
    TYPE /F8.2, v[1], v[2], v[3], v[4], v[5], v[6]
    DECOMPOSE j[1] = #safe
    TYPE j[1], j[2], j[3]
.END
.LOCATIONS
pick.1      465.00  -45.00  -245.00  10.00  170.00  20.00
slot[3]     0 0 0 0 180 0
#safe       0.00  -90.00  90.00  0.00  0.00  0.00
broken      1 2 3
.END
.STRINGS
$title      "Caf\xe9 report"
.END
"""


def test_check_reports_each_problem_and_goes_on(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    program = tmp_path / "stored.v2"
    program.write_bytes(STORED)
    assert main(["--workspace", str(tmp_path / "ws"), "check", str(program)]) == 1
    lines = capsys.readouterr().out.splitlines()
    assert "stored.v2:5: .PROGRAM MAIN: 'X Y' is not a parameter name" in lines
    assert "stored.v2:6: MAIN step 1: TYPE: $ENCODE: /L IS NOT A FORMAT (/Fw.d /Ew.d /Iw /Hw /D /Xn /Cn /S)" in lines
    assert "stored.v2:7: MAIN step 2: FOO IS NOT A V+ INSTRUCTION THE SIMULATOR KNOWS" in lines
    assert any(line.startswith("stored.v2:20: .LOCATIONS: BROKEN needs X Y Z yaw pitch roll") for line in lines)
    assert any(line.startswith("GOOD: 5 steps, no errors") for line in lines)  # checked after MAIN


def test_data_sections_are_loaded_by_run(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    from valterm.core.files.vplus import read_vplus_file

    program = tmp_path / "stored.v2"
    program.write_bytes(STORED.replace(b".PROGRAM good()", b".PROGRAM agood()").replace(
        b".PROGRAM main(x y, 1bad)\n    TYPE $ENCODE(/L, 5)\n    FOO BAR\n.END\n", b""))
    data = read_vplus_file(program).data
    assert data.reals == {"COUNT": 2.0} and data.strings == {"$TITLE": "Caf\u00e9 report"}
    assert data.precision == {"#SAFE": (0.0, -90.0, 90.0, 0.0, 0.0, 0.0)}
    assert main(["--workspace", str(tmp_path / "ws"), "run", str(program)]) == 0
    captured = capsys.readouterr()
    assert "2 Caf\u00e9 report 3" in captured.out
    assert "  465.00  -45.00 -245.00   10.00  170.00   20.00" in captured.out
    assert "0 -90 90" in captured.out
    assert "BROKEN needs X Y Z yaw pitch roll" in captured.err  # said, and the run went on


def test_export_program_writes_data_sections_that_read_back(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    from valterm.core.files.vplus import read_vplus_file
    from valterm.core.transform import Transform
    from valterm.core.workspace import Workspace

    workspace = tmp_path / "ws"
    loc = tmp_path / "CELL.LOC"
    loc.write_text("POINT A, 465., -45., -245., 89., 91., 0.\nPOINT #SAFE, -25.08, -68.28, 205.27, -0.59, 43.92, -23.65\n")
    Workspace.open(workspace).write_variables({"COUNT": 3.0})
    (workspace / "P1.DAT").write_text("    MOVE A\n")
    out = tmp_path / "out.v2"
    assert main(["--workspace", str(workspace), "export-program", "P1", "--out", str(out),
                 "--loc", str(loc), "--with-variables"]) == 0
    text = out.read_text()
    assert ".LOCATIONS" in text and ".REALS" in text
    data = read_vplus_file(out).data
    original = Transform.of(Location((465.0, -45.0, -245.0), (89.0, 91.0, 0.0))).matrix
    assert np.allclose(Transform.of(data.locations["A"]).matrix, original, atol=1e-4)
    assert data.precision["#SAFE"] == pytest.approx((-25.08, -68.28, 205.27, -0.59, 43.92, -23.65))
    assert data.reals["COUNT"] == 3.0


def test_each_bad_step_is_named_and_the_rest_is_checked(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    program = tmp_path / "errs.v2"
    program.write_text(body("x = 1 +", "SET a = TRANS(1,2", '$s = $LEFT("A")', "TYPE /Q, 3", "MOVE",
                            "DO", "  EXIT 3", "UNTIL TRUE", "TYPE 1") + ".PROGRAM later()\n    TYPE 2\n.END\n")
    assert main(["--workspace", str(tmp_path / "ws"), "check", str(program)]) == 1
    lines = capsys.readouterr().out.splitlines()
    assert lines[:6] == [
        "errs.v2:2: T step 1: ASSIGNMENT TO X: expression ends too soon: '1 +'",
        "errs.v2:3: T step 2: SET: expected ')', found the end in 'TRANS(1,2'",
        "errs.v2:4: T step 3: ASSIGNMENT TO $S: $LEFT takes a string and a count: $LEFT($s, n)",
        "errs.v2:5: T step 4: TYPE: /Q IS NOT A FORMAT (/Fw.d /Ew.d /Iw /Hw /D /Xn /Cn /S)",
        "errs.v2:6: T step 5: MOVE: EXPECTED MOVE <location>",
        "errs.v2:8: T step 7: EXIT 3: NOT INSIDE 3 NESTED LOOPS (FOR, WHILE or DO)"]
    assert lines[6].startswith("T: 9 steps, 6 error(s)")
    assert lines[7].startswith("LATER: 1 steps, no errors")


# -- the same in the app ---------------------------------------------------------------------

APP_PROGRAM = """.PROGRAM table()
    DECOMPOSE v[1] = TRANS(100,200,300,30,40,50):TRANS(0,0,50)
    TYPE /F8.2, v[1], v[2], v[3], v[4], v[5], v[6]
    DECOMPOSE v[1] = INVERSE(TRANS(100,200,300,30,40,50))
    TYPE /F8.2, v[1], v[2], v[3], v[4], v[5], v[6]
    TYPE 1, 2, COS(90)
    TIMER 1 = 0
    SIGNAL 1
    WAIT TIMER(1) > 0.5
    SIGNAL -1
    TYPE /F6.3, TIMER(1)
    WHERE
.END
"""


def test_the_app_shows_the_same_values(tmp_path: Path) -> None:
    import asyncio
    import math

    from valterm.core.session import Session
    from valterm.ui.app import ValtermApp
    from valterm.ui.screens.valmode import ValModeScreen

    class Host(ValtermApp):
        def on_mount(self) -> None:
            pass

    async def run() -> None:
        app = Host(session=Session(tmp_path / "ws"), motion_rate=math.inf)
        async with app.run_test(size=(140, 45)) as pilot:
            (app.session.workspace.root / "TABLE.V2").write_text(APP_PROGRAM)
            screen = ValModeScreen(show_menu=False)
            await app.push_screen(screen)
            await pilot.pause()
            await pilot.press(*"EXECUTE table", "enter")
            await until(pilot, lambda: any("COMPLETED" in line for line in screen.transcript), "the program's end")
            text = list(screen.transcript)
            assert "  127.83  216.07  338.30   30.00   40.00   50.00" in text, "\n".join(text)
            assert "  -62.31 -117.41 -349.76  130.00   40.00  150.00" in text
            assert "1 2 0" in text and " 0.500" in text
            assert any(line.split()[:3] == ["X", "Y", "Z"] for line in text) or any(
                line.split()[1:4] == ["X", "Y", "Z"] for line in text), text

    asyncio.run(run())


def test_execute_in_the_workspace_loads_the_file_s_data_once(tmp_path: Path) -> None:
    from valterm.core.session import Session

    session = Session(tmp_path / "ws")
    (session.workspace.root / "STORED.V2").write_text(
        ".PROGRAM counter()\n    count = count+1\n    TYPE count, \" \", $title\n"
        "    DECOMPOSE v[1] = spot\n    TYPE /F7.1, v[1], v[5]\n.END\n"
        ".REALS\ncount 10\n.END\n.STRINGS\n$title \"RUN\"\n.END\n"
        ".LOCATIONS\nspot 400 0 100 0 180 0\n.END\n")
    first = [e.text for e in session.command("EXECUTE counter") if isinstance(e, TypeOut)]
    second = [e.text for e in session.command("EXECUTE counter") if isinstance(e, TypeOut)]
    assert first == ["11 RUN", "  400.0  180.0"]
    assert second[0] == "12 RUN"  # loaded once, as LOAD would: the count goes on
    assert session.simulator.locations["SPOT"].xyz == (400.0, 0.0, 100.0)


def test_motion_tuning_statements_are_accepted_and_change_nothing() -> None:
    _, events = vplus(body("ACCEL 50, 80", "ACCEL 100 ALWAYS", "DURATION 0.5", "COARSE", "FINE 50 ALWAYS",
                           "NONULL", "NULL ALWAYS", "SINGLE", "MULTIPLE", 'TYPE /B, "DONE"'))
    assert typed(events) == ["DONE"] and not [e for e in events if e.event == "error"]
    _, events = vplus(body("ACCEL 1, 2, 3"))
    assert "ACCEL: EXPECTED ACCEL {<value>} {ALWAYS}" in [e.message for e in events if e.event == "error"][0]


def test_check_finds_a_program_of_a_workspace_vplus_file(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    workspace = tmp_path / "ws"
    assert main(["--workspace", str(workspace), "run", "nothing.here"]) == 1  # seeds the workspace
    (workspace / "CELLJOB.V2").write_text(body('TYPE "MAIN"') + ".PROGRAM pick.part()\n    EXIT\n.END\n")
    capsys.readouterr()
    assert main(["--workspace", str(workspace), "check", "pick.part"]) == 1
    assert "CELLJOB.V2:5: PICK.PART step 1: EXIT 1: NOT INSIDE A LOOP" in capsys.readouterr().out
    assert main(["--workspace", str(workspace), "check", "no.such"]) == 1


def test_location_arrays() -> None:
    sim = Simulator(None)
    _, events = vplus(body("FOR i = 1 TO 3", "  SET p[i] = TRANS(400+i*10, 0, 100, 0, 180, 0)", "END",
                           "MOVE p[2]", "DECOMPOSE v[1] = p[i-1]", "TYPE v[1]", "HERE q[1]",
                           "TYPE LAST(p[]), DX(q[1])"), sim)
    assert typed(events) == ["430", "3 420"]
    assert np.allclose(sim.where().xyz, (420, 0, 100), atol=0.01)
    assert np.allclose(sim.locations["Q[1]"].xyz, (420, 0, 100), atol=0.01)


def test_bits_sets_and_reads_signals_as_a_number() -> None:
    interpreter, events = vplus(body("BITS 1, 4 = 5", "TYPE BITS(1, 4), SIG(1), SIG(2), SIG(3)", "BITS 3 = 0",
                                     "TYPE BITS(1, 4)", "BITS 1001, 2 = 3"))
    assert typed(events) == ["5 -1 0 -1", "1"]
    assert interpreter.machine.signals.outputs_on() == [1]
    assert "1001 IS AN INPUT" in [e.message for e in events if e.event == "error"][0]


def test_a_loc_file_in_yaw_pitch_roll_is_the_same_poses(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    from valterm.core.files.locations import format_locations, parse_locations
    from valterm.core.transform import Transform

    thesis = {"A": Location((465.0, -45.0, -245.0), (89.0, 91.0, 0.0)),
              "DOWN": Location((400.0, 0.0, 100.0), (90.0, 90.0, 0.0))}
    text = format_locations(thesis, convention="YPR")
    assert text.splitlines()[0] == "; ANGLES YAW PITCH ROLL"
    assert "POINT DOWN, 400.00, 0.00, 100.00, 0.00, 180.00, 0.00" in text
    back = parse_locations(text, "V.LOC")
    for name, location in thesis.items():
        assert np.allclose(Transform.of(back[name]).matrix, Transform.of(location).matrix, atol=1e-4)
    # a V+ program reads such a file with --loc and gets the pose as written
    (tmp_path / "V.LOC").write_text("; ANGLES YAW PITCH ROLL\nPOINT spot, 400, 0, 100, 0, 180, 30\n")
    program = tmp_path / "p.v2"
    program.write_text(body("DECOMPOSE v[1] = spot", "TYPE /F8.2, v[1], v[2], v[3], v[4], v[5], v[6]"))
    assert main(["--workspace", str(tmp_path / "ws"), "run", str(program), "--loc", str(tmp_path / "V.LOC")]) == 0
    assert "  400.00    0.00  100.00    0.00  180.00   30.00" in capsys.readouterr().out


def test_the_bundled_blink_program_runs_its_whole_length(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    from valterm.core import resources

    blink = resources.data_path("programs", "vplus") / "blink.v2"
    assert main(["--workspace", str(tmp_path / "ws"), "run", str(blink), "--json"]) == 0
    events = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    output_1 = [(e["on"], e["time"]) for e in events if e["event"] == "signal" and e["number"] == 1]
    assert output_1 == [(True, 0.0), (False, 0.5), (True, 0.75), (False, 1.25), (True, 1.5), (False, 2.0)]
    output_2 = [(e["on"], e["time"]) for e in events if e["event"] == "signal" and e["number"] == 2]
    assert output_2 == [(True, 2.25), (False, 3.25)]
    assert [e["text"] for e in events if e["event"] == "type"][1] == "LAST COUNT 14 MASK 14 BLINKS 3"
    assert events[-1]["cycle_time_s"] == pytest.approx(7.25)
