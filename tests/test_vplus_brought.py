"""The programs people bring (issue 36, items 4-6): precision points under the controller rules,
the main program of a file, V+ names, software signals, SPEED ... MMPS ALWAYS, waits within the run
limits, a file checked whole, export-program --out, and other VAL descendants named."""

from __future__ import annotations

import io
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import pytest

from valterm.cli import main

from valterm.core.errors import ValtermError
from valterm.core.cycletime import robot_timing
from valterm.core.events import Error, Event, Message, Motion, TypeOut
from valterm.core.files.errors import FileFormatError
from valterm.core.files.locations import read_location_file
from valterm.core.files.vplus import parse_vplus
from valterm.core.kinematics import indicators, robot_geometry
from valterm.core.rules import CONTROLLER
from valterm.core.signals import SignalPanel
from valterm.core.simulator import Simulator
from valterm.core.val.interpreter import Interpreter
from valterm.ui.screens.signals import parse_input_command

STOPS = robot_geometry().stops


def controller_run(*lines: str) -> tuple[Simulator, list[Event]]:
    """One V+ program run under the controller rules (a real PUMA), as `valterm run` sets them."""
    text = ".PROGRAM t()\n" + "\n".join(f"    {line}" for line in lines) + "\n.END\n"
    programs = {b.program.name: b.program for b in parse_vplus(text, "T.v2")}
    sim = Simulator(None)
    sim.set_rules(CONTROLLER)
    interpreter = Interpreter(sim, lambda name: programs[name], {})
    return sim, list(interpreter.execute("T"))


def error_texts(events: list[Event]) -> list[str]:
    return [e.message for e in events if isinstance(e, Error)]


# -- item 4: a precision point is its joints (SPEC §3a, controller rules) -----------------------

def test_a_precision_point_with_wrist_angles_past_180_ends_exactly_there() -> None:
    # V+: #PPOINT's values are the joint positions themselves; 250 is inside JT4's and JT6's -266..266
    sim, events = controller_run("MOVE #PPOINT(0,-90,60,250,40,250)")
    assert not error_texts(events)
    assert sim.joints == pytest.approx([0, -90, 60, 250, 40, 250])
    assert sim.where().joints == pytest.approx((0, -90, 60, 250, 40, 250))


def _near_stop(joint: int, side: int, margin: float) -> list[float]:
    goal = [0.0, -90.0, 90.0, 0.0, 0.0, 0.0]
    low, high = STOPS[joint]
    goal[joint] = high - margin if side > 0 else low + margin
    return goal


@pytest.mark.parametrize("joint", range(6))
@pytest.mark.parametrize("side", [-1, 1])
def test_each_joint_one_degree_inside_its_stop_ends_exactly_there(joint: int, side: int) -> None:
    goal = _near_stop(joint, side, 1.0)
    sim, events = controller_run(f"MOVE #PPOINT({','.join(f'{v:g}' for v in goal)})")
    assert not error_texts(events)
    assert sim.joints == pytest.approx(goal, abs=1e-9)


@pytest.mark.parametrize("joint", range(6))
@pytest.mark.parametrize("side", [-1, 1])
def test_a_precision_point_beyond_a_stop_is_refused_naming_the_joint(joint: int, side: int) -> None:
    goal = _near_stop(joint, side, -1.0)  # one degree past the stop
    sim, events = controller_run(f"MOVE #PPOINT({','.join(f'{v:g}' for v in goal)})")
    errors = error_texts(events)
    assert errors and f"joint {joint + 1} beyond its stop" in errors[0].lower()
    assert sim.joints == pytest.approx(list(robot_geometry().ready))  # nothing moved


def test_the_1985_rules_still_take_the_equivalent_nearest_where_the_joint_is() -> None:
    sim = Simulator(None)
    list(sim.move_joints([0, -90, 60, 250, 40, 250]))
    assert sim.joints == pytest.approx([0, -90, 60, -110, 40, -110])


def test_a_transformation_keeps_the_arms_configuration() -> None:
    # LEFTY by a precision point, then a transformation: the arm stays LEFTY (SPEC §3a)
    sim, events = controller_run("MOVE #PPOINT(10,-40,120,0,20,0)", "HERE p", "MOVE #PPOINT(-20,-40,120,0,20,0)",
                                 "DECOMPOSE v[1] = p", "MOVE TRANS(v[1],v[2],v[3],v[4],v[5],v[6])")
    assert not error_texts(events)
    assert indicators(sim.joints).arm == -1
    assert sim.joints == pytest.approx([10, -40, 120, 0, 20, 0], abs=1e-6)
    changes = [e.text for e in events if isinstance(e, Message) and "CHANGED" in e.text]
    assert changes == ["ARM CONFIGURATION CHANGED: RIGHTY TO LEFTY"]  # the first precision point only


# -- item 5: the main program of a file is the one no other program CALLs ----------------------

def run_cli(tmp_path: Path, text: str, *options: str, name: str = "cell.v2") -> tuple[int, str, str]:
    """`valterm run FILE` on a file of ``text``; exit status, stdout and stderr."""
    path = tmp_path / name
    path.write_text(text)
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        status = main(["--workspace", str(tmp_path / "ws"), "run", str(path), *options])
    return status, out.getvalue(), err.getvalue()


SUBROUTINE_FIRST = """\
.PROGRAM pen.up()
    TYPE "PEN UP"
.END
.PROGRAM drawing()
    CALL pen.up()
    TYPE "DRAWN"
.END
"""


def test_the_main_program_is_the_one_no_other_program_calls(tmp_path: Path) -> None:
    status, out, _ = run_cli(tmp_path, SUBROUTINE_FIRST)
    assert status == 0
    assert "PROGRAM DRAWING COMPLETED" in out
    assert out.index("PEN UP") < out.index("DRAWN")


TWO_MAINS = SUBROUTINE_FIRST + """\
.PROGRAM test.pen()
    CALL pen.up()
    TYPE "TESTED"
.END
"""


def test_several_candidates_are_listed_and_none_runs(tmp_path: Path) -> None:
    status, out, err = run_cli(tmp_path, TWO_MAINS)
    assert status == 1 and "PEN UP" not in out
    assert "DRAWING" in err and "TEST.PEN" in err and "--program" in err and "PEN.UP" not in err.split(":")[-1]


def test_program_chooses_the_main_program(tmp_path: Path) -> None:
    status, out, _ = run_cli(tmp_path, TWO_MAINS, "--program", "test.pen")
    assert status == 0 and "TESTED" in out and "DRAWN" not in out
    status, _, err = run_cli(tmp_path, TWO_MAINS, "--program", "nothing")
    assert status == 1 and "NOTHING" in err and "DRAWING" in err


# -- item 5: V+ names in .LOC files (a letter, then letters, digits, '_' or '.', at most 15) -----

def test_a_loc_file_accepts_v_plus_names_with_underscores(tmp_path: Path) -> None:
    path = tmp_path / "CELL.LOC"
    path.write_text("POINT l_storage, 400, 0, 300, 90, 90, 0\nPOINT Pick_2.a, 400, 100, 300, 90, 90, 0\n"
                    "POINT #safe_1, 0, -90, 90, 0, 0, 0\nPOINT abcdefghijklmno, 1, 2, 3, 0, 0, 0\n")
    locations, points = read_location_file(path)
    assert set(locations) == {"L_STORAGE", "PICK_2.A", "ABCDEFGHIJKLMNO"}
    assert locations["L_STORAGE"].xyz == (400.0, 0.0, 300.0)
    assert points["#SAFE_1"] == (0.0, -90.0, 90.0, 0.0, 0.0, 0.0)


@pytest.mark.parametrize("name", ["abcdefghijklmnop", "1abc", "_abc", "pick-1"])
def test_a_name_no_rule_allows_is_refused_stating_the_rules(tmp_path: Path, name: str) -> None:
    path = tmp_path / "CELL.LOC"
    path.write_text(f"POINT {name}, 400, 0, 300, 90, 90, 0\n")
    with pytest.raises(FileFormatError) as refused:
        read_location_file(path)
    text = str(refused.value)
    assert "CELL.LOC:1" in text and "15" in text and "'_'" in text and "'.'" in text and "V+" in text


def test_a_program_runs_with_a_loc_file_of_v_plus_names(tmp_path: Path) -> None:
    (tmp_path / "L.LOC").write_text("POINT l_storage, 400, 100, 300, 90, 90, 0\n")
    status, out, err = run_cli(tmp_path, ".PROGRAM t()\n    MOVE l_storage\n.END\n", "--loc", str(tmp_path / "L.LOC"))
    assert status == 0, err
    assert "PROGRAM T COMPLETED" in out


# -- item 5: software signals 2001-2512 (V+: set by programs and read like inputs) --------------

MENU = """\
.PROGRAM menu()
    WAIT SIG(2001)
    TYPE "CHOICE 1 AT ", TIMER(1)
.END
"""


def test_an_inputs_script_sets_a_software_signal(tmp_path: Path) -> None:
    (tmp_path / "in.txt").write_text("0 2001 0\n1.5 2001 ON\n")
    status, out, err = run_cli(tmp_path, MENU, "--inputs", str(tmp_path / "in.txt"))
    assert status == 0, err
    assert "SIGNAL 2001 ON" in out and "PROGRAM MENU COMPLETED" in out


def test_an_inputs_script_still_refuses_an_output(tmp_path: Path) -> None:
    (tmp_path / "in.txt").write_text("1.5 7 ON\n")
    status, _, err = run_cli(tmp_path, MENU, "--inputs", str(tmp_path / "in.txt"))
    assert status == 1 and "in.txt:1" in err and "2001-2512" in err and "1001-1512" in err


def test_the_panel_takes_a_software_signal() -> None:
    panel = SignalPanel()
    assert parse_input_command("2001", panel) == (2001, True)
    assert parse_input_command("2512 on", panel) == (2512, True)
    panel.set_input(2001, True)
    assert panel.sig(2001) == -1.0
    with pytest.raises(ValtermError, match="2001-2512"):
        parse_input_command("2513", panel)


# -- item 5: SPEED n MMPS / IPS, ALWAYS (V+ reference: SPEED speed_factor, r_speed_factor units ALWAYS)

def motion_seconds(events: list[Event]) -> list[float]:
    return [e.seconds for e in events if isinstance(e, Motion)]


LINE = ("MOVE TRANS(-150, 400, 300, 0, 180, 0)", "MOVES TRANS(150, 400, 300, 0, 180, 0)")  # 300 mm straight


@pytest.mark.parametrize("speed, mm_per_s", [("100 MMPS", 100.0), ("2 IPS", 50.8), ("250 MMPS", 250.0)])
def test_speed_in_mmps_is_the_tool_tip_speed_of_a_straight_line(speed: str, mm_per_s: float) -> None:
    # the reference: with MMPS or IPS the value is the linear tool tip speed; the line starts and
    # ends at rest, accelerating at the robot file's tool acceleration (a trapezoid)
    accel = robot_timing().tool_accel
    _, events = controller_run(LINE[0], f"SPEED {speed} ALWAYS", LINE[1])
    assert not error_texts(events)
    assert motion_seconds(events)[-1] == pytest.approx(300.0 / mm_per_s + mm_per_s / accel, rel=1e-4)


def test_speed_without_always_is_for_the_next_motion_only() -> None:
    there, back = "MOVE #PPOINT(40,-90,90,0,0,0)", "MOVE #PPOINT(0,-90,90,0,0,0)"
    _, events = controller_run(there, back, "SPEED 50", there, back, "SPEED 50 ALWAYS", there, back)
    full, _, half, after, slow, slow_back = motion_seconds(events)
    assert half == pytest.approx(2 * full) and after == pytest.approx(full)  # only the next motion
    assert slow == pytest.approx(2 * full) and slow_back == pytest.approx(2 * full)  # ALWAYS: in force


def test_speed_with_a_rotation_factor_and_always_is_accepted() -> None:
    _, events = controller_run("SPEED 100 MMPS ALWAYS", "SPEED 40, 20 ALWAYS", "SPEED 100, 100 MMPS", *LINE)
    assert not error_texts(events)


def test_a_tool_speed_beyond_the_robots_is_said_and_held_at_its_maximum() -> None:
    top = robot_timing().tool_speed
    _, events = controller_run(LINE[0], "SPEED 100 IPS ALWAYS", LINE[1])
    said = [e.text for e in events if isinstance(e, Message) and "SPEED" in e.text]
    assert said and f"{top:g} MM/S" in said[0]
    assert motion_seconds(events)[-1] == pytest.approx(300.0 / top + top / robot_timing().tool_accel, rel=1e-4)


# -- item 5: waits are bounded by the run limits (no hidden 3600 s) ------------------------------

def test_a_wait_of_two_hours_ends_when_the_timer_gets_there() -> None:
    _, events = controller_run("TIMER 1 = 0", "WAIT TIMER(1) > 7200", 'TYPE "WAITED"')
    assert not error_texts(events)
    assert any(isinstance(e, TypeOut) and e.text == "WAITED" for e in events)


def test_a_wait_past_the_run_limit_stops_naming_the_limit(tmp_path: Path) -> None:
    text = '.PROGRAM t()\n    TIMER 1 = 0\n    WAIT TIMER(1) > 200\n    TYPE "WAITED"\n.END\n'
    status, out, _ = run_cli(tmp_path, text, "--max-seconds", "100")
    assert status == 1 and "WAITED" not in out
    said = next(line for line in out.splitlines() if line.startswith("***"))
    assert "100 SECONDS" in said and "--max-seconds" in said.lower()
    assert "CYCLE TIME 100.00 S" in out  # the robot waited up to the limit


def test_the_default_limit_is_the_one_a_wait_meets() -> None:
    _, events = controller_run("TIMER 1 = 0", "WAIT TIMER(1) > 90000")
    errors = error_texts(events)
    assert errors and "86400 SECONDS" in errors[0]


# -- item 5: a file is checked whole before any step runs ----------------------------------------

BAD_IN_A_CALLED_PROGRAM = """\
.PROGRAM main()
    TYPE "STARTED"
    CALL sub()
.END
.PROGRAM sub()
    MOVE
    TYPE "IN SUB"
    FOO BAR
.END
"""


def test_a_file_with_bad_steps_is_refused_before_any_step_runs(tmp_path: Path) -> None:
    status, out, err = run_cli(tmp_path, BAD_IN_A_CALLED_PROGRAM)
    assert status == 1
    assert "STARTED" not in out and "MAIN        1" not in out  # no step ran
    lines = [line for line in err.splitlines() if line.startswith("cell.v2:")]
    assert [line.split(":")[1] for line in lines] == ["6", "8"]  # every error, with its line
    assert "SUB step 1" in lines[0] and "SUB step 3" in lines[1]


def test_a_bad_step_of_the_main_program_is_refused_up_front_too(tmp_path: Path) -> None:
    status, out, err = run_cli(tmp_path, '.PROGRAM t()\n    TYPE "STARTED"\n    FOO BAR\n.END\n')
    assert status == 1 and "STARTED" not in out and "cell.v2:3:" in err


def test_a_step_only_the_controller_runs_is_no_reason_to_refuse_the_file(tmp_path: Path) -> None:
    status, out, _ = run_cli(tmp_path, '.PROGRAM t()\n    TYPE "STARTED"\n    IF 0 THEN\n'
                                       '        ATTACH (lun, 4) "TCP"\n    END\n.END\n')
    assert status == 0 and "STARTED" in out


# -- item 5: export-program --out is relative to the current folder ------------------------------

def test_export_program_out_is_relative_to_the_current_folder(tmp_path: Path,
                                                              monkeypatch: pytest.MonkeyPatch) -> None:
    workspace, here = tmp_path / "ws", tmp_path / "here"
    workspace.mkdir()
    here.mkdir()
    (workspace / "P1.DAT").write_text("1 TYPE HELLO\n")
    monkeypatch.chdir(here)
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        assert main(["--workspace", str(workspace), "export-program", "P1", "--out", "p1.v2"]) == 0
    assert (here / "p1.v2").is_file() and not (workspace / "p1.v2").exists()
    assert "PROGRAM p1" in (here / "p1.v2").read_text().replace("P1", "p1")


# -- item 6: another VAL descendant is named in one message ---------------------------------------

KAWASAKI = """\
.PROGRAM pick()
  SPEED 50 ALWAYS
  JMOVE #home
  LAPPRO part, 100
  LMOVE part
  TWAIT 0.5
  LDEPART 100
.END
"""
VAL3 = """\
<?xml version="1.0" encoding="utf-8"?>
<Programs xmlns="http://www.staubli.com/robotics/VAL3/Program/2">
  <Program name="start">
    <Code><![CDATA[begin
  movej(jHome, tTool, mNomSpeed)
  movel(pPick, tTool, mNomSpeed)
end]]></Code>
  </Program>
</Programs>
"""


@pytest.mark.parametrize("text, name, language, line", [
    (KAWASAKI, "pick.as", "a Kawasaki AS program", 3),
    (KAWASAKI, "pick.pg", "a Kawasaki AS program", 3),
    (".PROGRAM main()#0\n  HOME\n.END\n.TRANS\npart 400 0 300 0 180 0\n.END\n", "main.as", "a Kawasaki AS program", 1),
    (VAL3, "start.pgx", "a Staubli VAL3 program", 2),
    ("begin\n  movej(jHome, tTool, mNomSpeed)\nend\n", "start.DAT", "a Staubli VAL3 program", 2),
])
@pytest.mark.parametrize("command", ["run", "check"])
def test_another_val_descendant_is_named_in_one_message(tmp_path: Path, text: str, name: str, language: str,
                                                        line: int, command: str) -> None:
    path = tmp_path / name
    path.write_text(text)
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        status = main(["--workspace", str(tmp_path / "ws"), command, str(path)])
    said = (out.getvalue() + err.getvalue()).strip().splitlines()
    assert status == 1
    assert said == [f"valterm: {name}:{line}: {said[0].split(': ', 2)[2]}"]  # one message, located
    assert f"{language} (" in said[0] and said[0].endswith("valterm runs VAL-II and V+")


def test_the_workspace_names_the_language_of_a_program_it_is_asked_for(tmp_path: Path) -> None:
    from valterm.core.workspace import Workspace

    workspace = Workspace(tmp_path)
    (tmp_path / "KAWA.DAT").write_text("JMOVE #home\nTWAIT 1\n")
    with pytest.raises(FileFormatError, match="a Kawasaki AS program"):
        workspace.read_program("KAWA")


def test_a_v_plus_program_using_such_a_word_as_a_variable_is_still_v_plus() -> None:
    _, events = controller_run("twait = 2", "accuracy = twait*2", "TYPE accuracy")
    assert not error_texts(events)
