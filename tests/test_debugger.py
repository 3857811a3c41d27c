"""The debugger on the interpreter (BPT, XSTEP, SSTEP, WATCH, TRACE), driven through LineMonitor."""

from __future__ import annotations

from pathlib import Path

import pytest

from valterm.core.events import Breakpoint, Pause, Status, Step, Trace, Watch
from valterm.core.monitor import LineMonitor
from valterm.core.session import Session
from valterm.core.val.interpreter import program_from_lines


@pytest.fixture
def session(tmp_path: Path) -> Session:
    session = Session(tmp_path / "ws", setup=None)
    write = session.workspace.write_program
    write(program_from_lines("MAIN", ["    K=1", "    CALL SUB", "    K=K+1", "    TYPE K="]))
    write(program_from_lines("SUB", ["    ; a comment step", "    K=K+10", "    RETURN"]))
    return session


def monitor(session: Session) -> tuple[LineMonitor, list[str]]:
    out: list[str] = []
    return LineMonitor(session, out.append), out


def test_the_hook_is_attached_only_while_the_debugger_has_something_to_do(session: Session) -> None:
    interpreter = session.interpreter
    assert interpreter.hook is None and interpreter.pass_end is None
    mon, out = monitor(session)
    mon.line("WATCH K")
    assert interpreter.hook is not None
    mon.line("WATCH -K")
    mon.line("BPT MAIN,3")
    mon.line("BPT -MAIN,3")
    assert interpreter.hook is None and interpreter.pass_end is None
    mon.line("XSTEP MAIN")  # a single step attaches it; the end of the program detaches it
    mon.line("PROCEED")
    assert interpreter.hook is None and not mon.failed
    assert out[-1] == "PROGRAM MAIN COMPLETED: 1 LOOP"


def test_a_breakpoint_set_while_paused_stops_the_same_pass_even_inside_a_call(session: Session) -> None:
    mon, out = monitor(session)
    mon.line("SSTEP MAIN")
    mon.line("BPT SUB,2")
    mon.line("SSTEP")  # over the CALL, but the breakpoint in SUB stops it first
    assert out[-1] == "BREAKPOINT BEFORE SUB STEP 2: K=K+10"
    assert session.interpreter.call_depth == 1
    mon.line("PROCEED")
    assert out[-1] == "PROGRAM MAIN COMPLETED: 1 LOOP"
    assert session.interpreter.variables["K"] == 12


def test_ctrl_c_at_a_breakpoint_aborts_before_the_step_runs(session: Session) -> None:
    mon, out = monitor(session)
    mon.line("BPT MAIN,3")
    mon.line("EXECUTE MAIN")
    assert mon.paused and session.interpreter.variables["K"] == 11
    mon.abort()
    assert out[-1] == "*** MAIN STEP 3: ABORTED"
    assert not mon.paused and not session.interpreter.running
    assert session.interpreter.variables["K"] == 11  # step 3 never ran
    assert mon.end() == 1


def test_the_events_carry_what_the_app_needs(session: Session) -> None:
    interpreter = session.interpreter
    list(interpreter.command("BPT MAIN,3"))
    list(interpreter.command("WATCH K"))
    list(interpreter.command("TRACE ON"))
    events, run = [], interpreter.command("EXECUTE MAIN")  # kept: a dropped generator ends the run
    for event in run:
        events.append(event)
        if isinstance(event, Pause):
            break
    stop = events[-1]
    assert isinstance(stop, Breakpoint) and isinstance(stop, Pause)  # the app's PAUSE machinery
    assert stop.to_json() == {"event": "breakpoint", "program": "MAIN", "step": 3, "text": "K=K+1",
                              "reason": "BPT"}
    assert interpreter.paused and interpreter.debugger.paused_at == Step("MAIN", 3, "K=K+1")
    watches = [e for e in events if isinstance(e, Watch)]
    assert [(w.old, w.new, w.program, w.step) for w in watches] == [(None, 1.0, "MAIN", 1), (1.0, 11.0, "SUB", 2)]
    traces = [e for e in events if isinstance(e, Trace)]
    assert [(t.program, t.step, t.assigned) for t in traces] == [
        ("MAIN", 1, (("K", 1.0),)), ("MAIN", 2, ()), ("SUB", 2, (("K", 11.0),)), ("SUB", 3, ())]
    [status] = interpreter.command("STATUS")
    assert isinstance(status, Status) and status.to_json()["cycle_time_s"] == 0.0  # no motion yet


def test_a_single_step_left_pending_at_the_end_is_forgotten(session: Session) -> None:
    mon, out = monitor(session)
    mon.line("XSTEP MAIN,4")  # the last step: the program ends
    assert out[-1] == "PROGRAM MAIN COMPLETED: 1 LOOP"
    mon.line("EXECUTE MAIN")
    assert not mon.paused and out[-1] == "PROGRAM MAIN COMPLETED: 1 LOOP"


@pytest.mark.parametrize(("line", "message"), [
    ("BPT MAIN", "*** BPT MAIN: EXPECTED BPT <PROGRAM>,<STEP> OR BPT -<PROGRAM>,<STEP>"),
    ("BPT NOPE,1", "*** PROGRAM NOPE DOES NOT EXIST"),
    ("BPT SUB,1", "*** SUB STEP 1 CANNOT HAVE A BREAKPOINT (A COMMENT OR BLANK STEP)"),
    ("BPT SUB,9", "*** SUB STEP 9 CANNOT HAVE A BREAKPOINT (IT HAS 3 STEPS)"),
    ("XSTEP", "*** NO PROGRAM IS PAUSED (XSTEP <PROGRAM> STARTS ONE)"),
    ("XSTEP MAIN,9", "*** PROGRAM MAIN HAS NO STEP 9 THAT CAN RUN"),
    ("WATCH 9X", "*** WATCH 9X: 9X IS NOT A VARIABLE NAME"),
    ("WATCH -K", "*** K IS NOT WATCHED"),
    ("TRACE MAYBE", "*** TRACE MAYBE: EXPECTED TRACE ON OR TRACE OFF"),
    ("AUTOCONFIG 1", "*** AUTOCONFIG 1: EXPECTED AUTOCONFIG ON OR AUTOCONFIG OFF"),
])
def test_bad_debugger_commands_say_what_is_wrong(session: Session, line: str, message: str) -> None:
    mon, out = monitor(session)
    mon.line(line)
    assert out == [message] and mon.failed
    assert session.interpreter.hook is None


def test_the_monitor_lists_programs_and_refuses_what_needs_the_app(session: Session) -> None:
    mon, out = monitor(session)
    mon.line("LISTP SUB")
    assert out == ["PROGRAM SUB", "   1.     ; a comment step", "   2.     K=K+10", "   3.     RETURN"]
    assert not mon.failed
    mon.line("EDIT SUB")
    assert out[-1].startswith("*** EDIT NEEDS THE APP") and mon.failed


def test_a_value_typed_between_runs_is_told_as_typed_not_as_the_first_step(session: Session) -> None:
    mon, out = monitor(session)
    mon.line("WATCH K")
    mon.line("K=5")
    mon.line("EXECUTE MAIN")
    assert [line for line in out if line.startswith("WATCH K:")] == [
        "WATCH K: UNDEFINED -> 5 (TYPED)", "WATCH K: 5 -> 1 (MAIN STEP 1)",
        "WATCH K: 1 -> 11 (SUB STEP 2)", "WATCH K: 11 -> 12 (MAIN STEP 3)"]
