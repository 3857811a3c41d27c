"""One clock of the robot's time per interpreter: STATUS's cycle time, ``run``'s, V+ TIMER and
scripted inputs all read it; the hand's time is the robot file's until PARAMETER HAND.TIME."""

from __future__ import annotations

import pytest

from valterm.core.cycletime import robot_timing
from valterm.core.events import Event, Hand, Motion, TypeOut
from valterm.core.files.vplus import parse_vplus
from valterm.core.signals import parse_inputs
from valterm.core.simulator import Simulator
from valterm.core.val.interpreter import Interpreter, program_from_lines


def interpreter_for(text: str) -> Interpreter:
    programs = {b.program.name: b.program for b in parse_vplus(text, "T.v2")}
    return Interpreter(Simulator(None), lambda name: programs[name], {})


def body(*lines: str) -> str:
    return ".PROGRAM t()\n" + "\n".join(f"    {line}" for line in lines) + "\n.END\n"


def robot_seconds(events: list[Event], hand_time: float) -> float:
    """What the events themselves say the robot took: motions, and the hand's time each."""
    return (sum(e.seconds for e in events if isinstance(e, Motion))
            + hand_time * sum(isinstance(e, Hand) for e in events))


def test_a_vplus_program_s_cycle_time_has_its_motions_hand_and_waits() -> None:
    interpreter = interpreter_for(body("DRIVE 1, 30, 100", "OPENI", "WAIT SIG(1005)",
                                       "WAIT.EVENT , 1.5", "DELAY 0.25", "DRIVE 2, -20, 100"))
    interpreter.machine.inputs = parse_inputs("4.0 1005 1\n", "in.txt")
    events = list(interpreter.execute("T"))
    moving = robot_seconds(events, robot_timing().hand_time)
    assert sum(isinstance(e, Motion) for e in events) == 2 and moving > 0.5
    # the WAIT ends when input 1005 comes on at 4.0 s; then 1.5 s, 0.25 s and the last drive
    last = [e for e in events if isinstance(e, Motion)][-1].seconds
    assert interpreter.cycle_seconds == pytest.approx(4.0 + 1.5 + 0.25 + last, abs=0.06)
    assert interpreter.status().cycle_time_s == pytest.approx(interpreter.cycle_seconds, abs=1e-3)


def test_the_cycle_time_is_since_the_last_execute_while_timers_keep_counting() -> None:
    interpreter = interpreter_for(body("DELAY 2", 'TYPE /F5.1, TIMER(1)'))
    list(interpreter.command("TIMER 1 = 0"))
    first = list(interpreter.execute("T"))
    second = list(interpreter.execute("T"))
    assert interpreter.cycle_seconds == pytest.approx(2.0)
    list(interpreter.command("DELAY 3"))  # typed after the run: time passes, not the cycle's
    assert interpreter.cycle_seconds == pytest.approx(2.0)
    assert interpreter.machine.timer(1) == pytest.approx(7.0)
    # TIMER 1 was set before the first EXECUTE: it saw both runs' DELAYs
    assert [e.text for e in first + second if isinstance(e, TypeOut)] == ["  2.0", "  4.0"]


def test_hand_time_is_the_robot_file_s_until_a_program_sets_it() -> None:
    interpreter = interpreter_for(body('TYPE /F5.2, PARAMETER(HAND.TIME)', "OPENI",
                                       "PARAMETER HAND.TIME = 0.5", "CLOSEI",
                                       'TYPE /F5.2, PARAMETER(HAND.TIME)'))
    events = list(interpreter.execute("T"))
    assert [e.text for e in events if isinstance(e, TypeOut)] == [
        f"{robot_timing().hand_time:5.2f}", " 0.50"]
    assert interpreter.cycle_seconds == pytest.approx(robot_timing().hand_time + 0.5)


def test_a_1985_program_s_cycle_time_is_its_events_time() -> None:
    program = program_from_lines("P", ["DRIVE 1, 30, 50", "OPENI", "DELAY 1", "DRIVE 1, -30, 50"])
    interpreter = Interpreter(Simulator(None), lambda name: program, {})
    events = list(interpreter.execute("P"))
    expected = robot_seconds(events, robot_timing().hand_time) + 1.0
    assert interpreter.cycle_seconds == pytest.approx(expected)


def test_status_says_so_far_only_while_the_program_runs() -> None:
    from valterm.core.events import Status

    assert Status(100.0, "P", 0, 2, 1.5).cycle_text == "CYCLE TIME 1.50 S SO FAR (ESTIMATE FOR THE REAL PUMA)"
    assert Status(100.0, "P", 2, 0, 3.25).cycle_text == "CYCLE TIME 3.25 S (ESTIMATE FOR THE REAL PUMA)"
