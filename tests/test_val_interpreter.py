"""The two-pass VAL-II interpreter, against a fake simulator (and once against the real one)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Iterator

import pytest

from valterm.core.events import (
    Delay,
    Error,
    Event,
    Help,
    Message,
    Monitor,
    Motion,
    Pause,
    Status,
    Step,
    TypeOut,
    Where,
)
from valterm.core.files.programs import Program, read_program
from valterm.core.kinematics import Location
from valterm.core.motion import MotionRefused
from valterm.core.simulator import UndefinedLocation
from valterm.core.val.interpreter import FOREVER_LOOPS, MAX_CALL_DEPTH, Interpreter, program_from_lines
from valterm.core.val.limits import RunLimits
from valterm.core.arms import thesis_arm
from valterm.core.cycletime import robot_timing

REPO = Path(__file__).resolve().parent.parent  # the repository: the bundled data (cells/, programs/)
PROGRAMS = REPO / "programs"


class FakeSim:
    """The Simulator's VAL-II surface: records every call, moves nothing."""

    def __init__(self) -> None:
        self.speed = 100.0
        self.calls: list[tuple] = []
        self.locations: dict[str, Location] = {
            "A": Location((400.0, 0.0, 0.0), (90.0, 90.0, 0.0)),
            "B": Location((300.0, 100.0, 0.0), (90.0, 90.0, 0.0)),
        }
        self.refuse: set[str] = set()  # commands to refuse
        self.graspable = False
        # the rest of the interpreter's surface (core/val/protocol.py): the thesis's robot
        self.rules = "1985"
        self.arm = thesis_arm()
        self.timing = robot_timing()
        self.joints: tuple[float, ...] = (0.0,) * 6
        self.stored: list[str] = []

    def set_rules(self, name: str) -> str:
        self.calls.append(("rules", name))
        self.rules = name.lower()
        return self.rules

    def mark_locations_stored(self, names: Any = None) -> None:
        self.stored.extend(self.locations if names is None else names)

    def set_program_speed(self, value: float, mm_per_s: bool, always: bool) -> float:
        return self.set_speed(value)

    def in_range(self, location: Location) -> tuple[int, ...] | None:
        return ()

    def move_joints(self, goal: Any) -> Iterator[Event]:
        return self._motion("move_joints", tuple(goal))

    def _motion(self, name: str, *args: Any, **kwargs: Any) -> Iterator[Event]:
        if name in self.refuse:
            raise MotionRefused(f"JOINT 3 IS BEYOND ITS STOP ({name})", joint=3)
        self.calls.append((name, *args, *(f"{k}={v}" for k, v in kwargs.items())))
        yield Motion("joint", 1, (0.0,) * 6)

    def set_speed(self, percent: float) -> float:
        self.speed = min(100.0, max(10.0, percent))
        self.calls.append(("speed", percent))
        return self.speed

    def set_indicator(self, word: str) -> None:
        self.calls.append(("indicator", word))

    def location(self, name: str) -> Location:
        if name not in self.locations:
            raise UndefinedLocation(name)  # as the simulator does (a bare KeyError would be a bug)
        return self.locations[name]

    def here(self, name: str) -> None:
        self.calls.append(("here", name))
        self.locations[name] = Location((1.0, 2.0, 3.0), (0.0, 0.0, 0.0))

    def where(self) -> Where:
        return Where((1.0, 2.0, 3.0), (0.0, 90.0, 0.0), (0.0,) * 6, {"arm": "RIGHTY"})

    def set_location(self, dst: str, src: str) -> None:
        self.locations[dst] = self.location(src)
        self.calls.append(("set", dst, src))

    def shift(self, name: str, dx: float, dy: float, dz: float) -> None:
        loc = self.location(name)
        self.locations[name] = Location((loc.xyz[0] + dx, loc.xyz[1] + dy, loc.xyz[2] + dz), loc.oat)
        self.calls.append(("shift", name, dx, dy, dz))

    def set_base(self, dx: Any = None, dy: Any = None, dz: Any = None, rz: Any = None) -> Iterator[Event]:
        self.calls.append(("base", dx, dy, dz, rz))
        yield Message("BASE")

    def move(self, target: Any, straight: bool = False) -> Iterator[Event]:
        if isinstance(target, str):
            self.location(target)
        return self._motion("move", target, straight=straight)

    def appro(self, target: Any, distance: float, straight: bool = False) -> Iterator[Event]:
        return self._motion("appro", target, distance, straight=straight)

    def depart(self, distance: float, straight: bool = False) -> Iterator[Event]:
        return self._motion("depart", distance, straight=straight)

    def drive(self, joint: int, degrees: float, speed: float) -> Iterator[Event]:
        return self._motion("drive", joint, degrees, speed)

    def draw(self, dx: float, dy: float, dz: float) -> Iterator[Event]:
        return self._motion("draw", dx, dy, dz)

    def ready(self) -> Iterator[Event]:
        return self._motion("ready")

    def align(self) -> Iterator[Event]:
        return self._motion("align")

    def open(self, immediate: bool = False) -> Iterator[Event]:
        return self._motion("open", immediate=immediate)

    def close(self, immediate: bool = False) -> Iterator[Event]:
        return self._motion("close", immediate=immediate)

    def grasp_possible(self) -> bool:
        return self.graspable


def make(programs: dict[str, list[str]] | None = None, sim: FakeSim | None = None,
         variables: dict | None = None) -> Interpreter:
    programs = programs or {}

    def load(name: str) -> Program:
        if name not in programs:
            raise FileNotFoundError(f"{name}.DAT: no such program file")
        return program_from_lines(name, programs[name])

    return Interpreter(sim or FakeSim(), load, variables if variables is not None else {})


def run(lines: list[str], loops: int = 1, sim: FakeSim | None = None, **more: list[str]) -> tuple[Interpreter, list[Event]]:
    interpreter = make({"MAIN": lines, **more}, sim)
    return interpreter, list(interpreter.execute("MAIN", loops))


def typed(events: list[Event]) -> list[str]:
    return [e.text for e in events if isinstance(e, TypeOut)]


def errors(events: list[Event]) -> list[Error]:
    return [e for e in events if isinstance(e, Error)]


def steps(events: list[Event]) -> list[int]:
    return [e.step for e in events if isinstance(e, Step)]


# -- statements --------------------------------------------------------------------------


def test_assignment_and_type() -> None:
    interpreter, events = run(["    ROW=10", "    ROW=ROW+2*(3-1)", "    X=-ROW/4", "    TYPE ROW=",
                               "    TYPE X=", "    TYPE Pick up the part"])
    assert interpreter.variables == {"ROW": 14.0, "X": -3.5}
    assert typed(events) == ["ROW = 14", "X = -3.5", "Pick up the part"]
    assert not errors(events)
    assert isinstance(events[-1], Message) and "COMPLETED" in events[-1].text


def test_steps_scroll_with_labels_and_skip_comments() -> None:
    _, events = run(["; PROGRAM MAIN", "    X=1", "300 ENDIF" if False else "300 X=2", "    ; note", "    STOP"])
    shown = [(e.step, e.text) for e in events if isinstance(e, Step)]
    assert shown == [(2, "X=1"), (3, "300 X=2"), (5, "STOP")]


def test_motion_and_hand_commands_reach_the_simulator() -> None:
    sim = FakeSim()
    _, events = run([
        "    READY", "    MOVE A", "    MOVES B", "    APPRO A, -50", "    APPROS B, 25",
        "    DEPART 100", "    DEPARTS -20", "    DRIVE 2, -30, 100", "    DRAW 10", "    ALIGN",
        "    OPEN", "    OPENI 100", "    CLOSE 40", "    CLOSEI 50",
    ], sim=sim)
    assert not errors(events)
    assert sim.calls == [
        ("ready",), ("move", "A", "straight=False"), ("move", "B", "straight=True"),
        ("appro", "A", -50.0, "straight=False"), ("appro", "B", 25.0, "straight=True"),
        ("depart", 100.0, "straight=False"), ("depart", -20.0, "straight=True"),
        ("drive", 2, -30.0, 100.0), ("draw", 10.0, 0.0, 0.0), ("align",),
        ("open", "immediate=False"), ("open", "immediate=True"),
        ("close", "immediate=False"), ("close", "immediate=True"),
    ]
    assert sum(isinstance(e, Motion) for e in events) == 14


def test_location_commands() -> None:
    sim = FakeSim()
    _, events = run(["    HERE P1", "    SET P2=A", "    SHIFT P2 BY 0,0,-200", "    SHIFT B, 10, , 5",
                     "    BASE ,,300,", "    WHERE", "    MOVE SHIFT(A BY 0,0,50)"], sim=sim)
    assert not errors(events)
    assert ("here", "P1") in sim.calls and ("set", "P2", "A") in sim.calls
    assert sim.locations["P2"].xyz == (400.0, 0.0, -200.0)
    assert ("shift", "B", 10.0, 0.0, 5.0) in sim.calls
    assert ("base", None, None, 300.0, None) in sim.calls
    assert any(isinstance(e, Where) for e in events)
    target = sim.calls[-1][1]
    assert isinstance(target, Location) and target.xyz == (400.0, 0.0, 50.0)
    assert sim.locations["A"].xyz == (400.0, 0.0, 0.0)  # SHIFT(...) in a motion leaves A alone


def test_configuration_speed_delay_status() -> None:
    sim = FakeSim()
    interpreter, events = run(["    LE", "    AB", "    FLIP", "    NOFLIP", "    RIGHTY", "    BELOW",
                               "    SPEED 5", "    SPEED 50", "    DELAY 1.5", "    STATUS"], loops=3, sim=sim)
    words = [c[1] for c in sim.calls if c[0] == "indicator"]
    assert words[:6] == ["LEFTY", "ABOVE", "FLIP", "NOFLIP", "RIGHTY", "BELOW"]
    assert any(isinstance(e, Message) and "SPEED SET TO 10" in e.text for e in events)
    assert sim.speed == 50.0
    assert [e.seconds for e in events if isinstance(e, Delay)] == [1.5] * 3
    statuses = [e for e in events if isinstance(e, Status)]
    assert [(s.loops_done, s.loops_left) for s in statuses] == [(0, 3), (1, 2), (2, 1)]
    assert statuses[0].speed == 50.0 and statuses[0].program == "MAIN"
    assert "LOOPS COMPLETED 0  REMAINING 3" in statuses[0].text
    assert interpreter.status().loops_left == 0  # nothing runs now


def test_grasp_branches_when_the_part_is_graspable() -> None:
    program = ["    GRASP 50, 100", "    TYPE MISSED", "    STOP", "100 TYPE GOT IT"]
    sim = FakeSim()
    _, events = run(program, sim=sim)
    assert typed(events) == ["MISSED"] and not sim.calls
    sim.graspable = True
    _, events = run(program, sim=sim)
    assert typed(events) == ["GOT IT"] and sim.calls == [("close", "immediate=True")]


# -- control -------------------------------------------------------------------------------


def test_if_else_end_and_endif() -> None:
    program = ["    IF X .EQ. 1 THEN", "    TYPE ONE", "    ELSE", "    TYPE OTHER", "    END",
               "    IF X.GT.0, THEN", "    TYPE POSITIVE", "    ENDIF", "    TYPE DONE"]
    for x, expected in ((1.0, ["ONE", "POSITIVE", "DONE"]), (0.0, ["OTHER", "DONE"])):
        interpreter = make({"MAIN": program})
        interpreter.variables["X"] = x
        assert typed(list(interpreter.execute("MAIN"))) == expected


def test_nested_if_in_while_in_do() -> None:
    program = [
        "    I=0", "    N=0", "    DO", "    J=0", "    WHILE J .LT. 3 DO",
        "    IF J .EQ. 1 THEN", "    N=N+10", "    ELSE", "    IF J .EQ. 2, THEN", "    N=N+100",
        "    ELSE", "    N=N+1", "    ENDIF", "    END", "    J=J+1", "    END", "    I=I+1",
        "    UNTIL I .EQ. 2.", "    TYPE N=",
    ]
    interpreter, events = run(program)
    assert typed(events) == ["N = 222"]
    assert not errors(events)


def test_goto_and_if_goto() -> None:
    program = ["    I=0", "10  I=I+1", "    IF I .LT. 5 GOTO 10", "    GOTO 30", "    TYPE SKIPPED",
               "30  TYPE I="]
    _, events = run(program)
    assert typed(events) == ["I = 5"]


def test_goto_missing_label_reports_and_continues() -> None:
    _, events = run(["    GOTO 400", "    TYPE NEXT", "    X=1", "    IF X GOTO 500", "    TYPE AFTER"])
    errs = errors(events)
    assert [(e.step, "400" in e.message) for e in errs[:1]] == [(1, True)]
    assert errs[1].step == 4 and "500" in errs[1].message
    assert typed(events) == ["NEXT", "AFTER"]


def test_undeclared_variables() -> None:
    program = [
        "    TYPE NOPE=",                                # error, next step
        "    IF NOPE .EQ. 1 THEN", "    TYPE IN IF", "    ELSE", "    TYPE IN ELSE", "    END",  # past END
        "    WHILE NOPE .LT. 3 DO", "    TYPE IN WHILE", "    END",   # ignored
        "    X=NOPE+1",                                  # error, next step
        "    DEPART NOPE",                               # error, next step
        "    TYPE END",
    ]
    interpreter, events = run(program)
    errs = errors(events)
    assert [e.step for e in errs] == [1, 2, 7, 10, 11]
    assert all("NOPE" in e.message and "NOT DECLARED" in e.message for e in errs)
    assert typed(events) == ["END"]
    assert "X" not in interpreter.variables


def test_division_by_zero_is_an_error_and_goes_on() -> None:
    _, events = run(["    Z=0", "    X=1/Z", "    TYPE OK"])
    assert "DIVISION BY ZERO" in errors(events)[0].message and typed(events) == ["OK"]


def test_call_and_return() -> None:
    _, events = run(["    TYPE MAIN 1", "    CALL SUB", "    TYPE MAIN 2", "    CALL SUB2", "    TYPE MAIN 3"],
                    SUB=["    TYPE SUB", "    RETURN", "    TYPE NEVER"],
                    SUB2=["    TYPE SUB2 FALLS OFF ITS END"])
    assert typed(events) == ["MAIN 1", "SUB", "MAIN 2", "SUB2 FALLS OFF ITS END", "MAIN 3"]
    assert [e.program for e in events if isinstance(e, Step)] == ["MAIN", "MAIN", "SUB", "SUB", "MAIN", "MAIN", "SUB2", "MAIN"]


def test_call_depth_limit() -> None:
    _, events = run(["    CALL REC", "    TYPE NEVER"], REC=["    TYPE DEEPER", "    CALL REC"])
    errs = errors(events)
    assert len(errs) == 1 and f"MORE THAN {MAX_CALL_DEPTH} NESTED CALLS" in errs[0].message
    assert errs[0].program == "REC" and errs[0].step == 2
    assert typed(events) == ["DEEPER"] * MAX_CALL_DEPTH  # 20 nested calls run; the 21st is refused


def test_call_of_a_missing_program_stops() -> None:
    _, events = run(["    CALL NOSUCH", "    TYPE NEVER"])
    assert "NOSUCH" in errors(events)[0].message and typed(events) == []


def test_stop_and_halt_end_a_pass_and_loops_restart() -> None:
    interpreter = make({"MAIN": ["    N=N+1", "    HALT end of pass", "    TYPE NEVER"]}, variables={"N": 0.0})
    events = list(interpreter.execute("MAIN", 3))
    assert interpreter.variables["N"] == 3.0
    assert typed(events) == ["end of pass"] * 3
    assert interpreter.loops_done == 3


def test_return_in_the_main_program_ends_the_pass() -> None:
    _, events = run(["    TYPE A", "    RETURN", "    TYPE B"], loops=2)
    assert typed(events) == ["A", "A"]


def test_execute_negative_loops_runs_1000_passes() -> None:
    interpreter = make({"MAIN": ["    N=N+1"]}, variables={"N": 0.0})
    list(interpreter.command("EXEC MAIN,-1"))
    assert interpreter.variables["N"] == FOREVER_LOOPS


def test_arithmetic_loop_of_100000_passes() -> None:
    interpreter = make({"MAIN": ["    I=0", "    S=0", "    WHILE I .LT. 100000 DO", "    I=I+1",
                                 "    S=S+I", "    END"]})
    interpreter.limits = RunLimits(lines=0)  # 400 000 scrolled steps: past the default 100 000 lines
    count = 0
    for event in interpreter.execute("MAIN"):
        count += 1
    assert interpreter.variables["S"] == 100000 * 100001 / 2
    assert count > 400_000


def test_structure_errors_stop_the_run_before_it_starts() -> None:
    sim = FakeSim()
    _, events = run(["    READY", "    IF X THEN", "    READY"], sim=sim)
    assert not sim.calls
    assert errors(events)[0].step == 2 and "IF without END" in errors(events)[0].message


def test_a_bad_step_stops_the_program_at_run_time() -> None:
    # issue 14: a step that fails the syntax check stops the program with its located error
    _, events = run(["    JUMP", "    TYPE NEXT"])
    assert errors(events)[0].step == 1 and "JUMP" in errors(events)[0].message
    assert typed(events) == []
    assert not any(isinstance(e, Message) and "COMPLETED" in e.text for e in events)


def test_refused_motion_stops_the_program_at_that_step() -> None:
    sim = FakeSim()
    sim.refuse.add("appro")
    interpreter, events = run(["    X=1", "    MOVE A", "    APPRO B, 50", "    X=2", "    MOVE A"], sim=sim)
    errs = errors(events)
    assert len(errs) == 1 and errs[0].program == "MAIN" and errs[0].step == 3
    assert "BEYOND ITS STOP" in errs[0].message
    assert interpreter.variables["X"] == 1.0 and not interpreter.running
    assert "A" in sim.locations


def test_undefined_location_stops_the_program() -> None:
    _, events = run(["    MOVE NOWHERE", "    TYPE NEVER"])
    assert errors(events)[0].step == 1 and "NOWHERE" in errors(events)[0].message
    assert typed(events) == []


# -- abort, pause, typed commands ---------------------------------------------------------


def test_abort_stops_after_the_current_step() -> None:
    interpreter = make({"MAIN": ["10  X=X+1", "    GOTO 10"]}, variables={"X": 0.0})
    seen = []
    for event in interpreter.execute("MAIN"):
        seen.append(event)
        if isinstance(event, Step) and interpreter.variables["X"] >= 5:
            interpreter.abort()
    assert isinstance(seen[-1], Error) and seen[-1].message == "ABORTED"
    assert interpreter.variables["X"] == 5.0  # kept
    assert not interpreter.running


def test_pause_and_proceed() -> None:
    interpreter = make({"MAIN": ["    X=1", "    PAUSE look at this", "    TYPE X="]})
    run_events = interpreter.execute("MAIN")
    seen = []
    for event in run_events:
        seen.append(event)
        if isinstance(event, Pause):
            break
    assert seen[-1] == Pause("MAIN", 2, "look at this")
    assert interpreter.paused and interpreter.running
    # while paused, the user types commands
    assert list(interpreter.command("X=42")) == []
    assert [e for e in interpreter.command("EXEC MAIN") if isinstance(e, Error)][0].message.startswith("A PROGRAM")
    assert list(interpreter.command("PROCEED")) == []
    assert not interpreter.paused
    rest = list(run_events)
    assert typed(rest) == ["X = 42"]
    assert [e.message for e in interpreter.command("PROCEED") if isinstance(e, Error)] == ["NO PROGRAM IS PAUSED"]


def test_abort_while_paused() -> None:
    interpreter = make({"MAIN": ["    PAUSE", "    TYPE NEVER"]})
    run_events = interpreter.execute("MAIN")
    assert isinstance(next(run_events), Step) and isinstance(next(run_events), Pause)
    interpreter.abort()
    rest = list(run_events)
    assert typed(rest) == [] and rest[-1].message == "ABORTED"


def test_typed_commands() -> None:
    sim = FakeSim()
    interpreter = make({"MAIN": ["    TYPE RUN"]}, sim=sim)
    assert list(interpreter.command("COL=1")) == [] and interpreter.variables["COL"] == 1.0
    assert typed(list(interpreter.command("TYPE COL="))) == ["COL = 1"]
    assert list(interpreter.command("LE")) == [] and sim.calls[-1] == ("indicator", "LEFTY")
    assert any(isinstance(e, Motion) for e in interpreter.command("    MOVE A"))
    assert "ONLY BE USED IN A PROGRAM" in errors(list(interpreter.command("GOTO 10")))[0].message
    assert "ambiguous" in errors(list(interpreter.command("D")))[0].message
    assert "CTRL-C" in errors(list(interpreter.command("ABORT")))[0].message
    assert "NOT DECLARED" in errors(list(interpreter.command("TYPE NOPE=")))[0].message
    sim.refuse.add("move")
    refused = errors(list(interpreter.command("MOVE A")))
    assert refused[0].program == "" and "BEYOND" in refused[0].message  # typed: it just reports
    assert typed(list(interpreter.command("EXECUTE MAIN, 2"))) == ["RUN", "RUN"]
    assert list(interpreter.command("LISTF")) == [Monitor("LISTF", "")]
    assert list(interpreter.command("LISTP CONV1")) == [Monitor("LISTP", "CONV1")]
    assert isinstance(list(interpreter.command("STATUS"))[0], Status)
    assert list(interpreter.command("; just a comment")) == []


def test_help() -> None:
    interpreter = make()
    menu = list(interpreter.command("HELP"))[0]
    assert isinstance(menu, Help) and menu.topic == "" and menu.lines[0] == "HELP MENU"
    topic = list(interpreter.command("HELP EXEC"))[0]
    assert topic.topic == "EXECUTE" and any("1000" in line for line in topic.lines)
    assert "NO HELP" in list(interpreter.command("HELP XYZZY"))[0].lines[0]


def test_events_are_json() -> None:
    _, events = run(["    X=1", "    TYPE X=", "    STATUS", "    DELAY 1"])
    for event in events:
        assert json.loads(json.dumps(event.to_json()))["event"] == event.event


# -- the thesis's programs -------------------------------------------------------------------


def test_conv1_calls_conv2_and_col_follows_the_control_flow() -> None:
    sim = FakeSim()
    for name in "ABCFHLM":
        sim.locations.setdefault(name, Location((0.0, 0.0, 0.0), (0.0, 0.0, 0.0)))
    interpreter = Interpreter(sim, lambda name: read_program(PROGRAMS / f"{name}.DAT"), {})
    events = list(interpreter.command("EXEC CONV1"))
    assert not errors(events)
    # 100 COL=COL+1 -> 2; IF COL.EQ.2 GOTO 300; WHILE COL<ROW: COL -> 3; after DO..UNTIL COL=ROW
    assert typed(events) == ["COL = 2", "ROW = 3", "COL = 3", "ROW = 3", "COL = 3"]
    assert interpreter.variables == {"COL": 3.0, "ROW": 3.0}
    shown = [(e.program, e.step) for e in events if isinstance(e, Step)]
    assert ("CONV1", 21) not in shown and ("CONV1", 22) not in shown  # ELSE branch skipped
    assert ("CONV2", 12) in shown  # CONV2's RETURN
    assert shown.count(("CONV1", 25)) == 2  # WHILE tested twice
    assert shown[-1] == ("CONV1", 55)  # RETURN in the main program ends the pass


def test_process_runs_on_the_real_simulator() -> None:
    from valterm.core.files.locations import read_locations
    from valterm.core.files.setup import read_setup
    from valterm.core.simulator import Simulator

    sim = Simulator(read_setup(REPO / "cells" / "PROCESS.SET"))
    sim.locations.update(read_locations(PROGRAMS / "PROCESS.LOC"))
    interpreter = Interpreter(sim, lambda name: read_program(PROGRAMS / f"{name}.DAT"))
    events = list(interpreter.command("EXEC PROCESS,1"))
    assert not errors(events)
    assert typed(events) == ["PICK UP THE FIRST PART", "PROCESS THE FIRST PART",
                             "PICK UP THE SECOND PART", "PROCESS THE SECOND PART"]
    assert sum(isinstance(e, Delay) for e in events) == 2


# -- valterm run ------------------------------------------------------------------------------


def test_cli_run_transcript(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from valterm.cli import main

    # CONV1 calls CONV2 and runs to its end (tests/test_case_studies.py): exit 0, transcript whole
    assert main(["--workspace", str(tmp_path / "ws"), "run", "CONV1", "--cell", "CONV", "--loc", "CONV"]) == 0
    out = capsys.readouterr().out
    assert "CONV1      19  IF COL.EQ.2, THEN" in out
    assert "CONV2       2  OPENI 100" in out
    assert "COL = 3" in out and "IT IS POSSIBLE TO GRASP THIS PART" in out
    assert "\nWHERE\n" in out and "JT 1" in out and "VARIABLES  COL=3  ROW=3" in out


def test_cli_run_json(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from valterm.cli import main

    assert main(["--workspace", str(tmp_path / "ws"), "run", "PROCESS", "--json"]) == 0
    lines = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert lines[0]["event"] == "step" and lines[0]["text"] == "READY"
    assert {"pose", "motion", "type", "delay", "grasp", "release"} <= {line["event"] for line in lines}
    assert lines[-1]["event"] == "end" and lines[-1]["where"]["joints"] == [0.0, -90.0, 90.0, 0.0, 0.0, 0.0]


def test_cli_run_errors(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from valterm.cli import main

    bad = tmp_path / "BAD.DAT"
    bad.write_text("    X=1\n    MOVE NOWHERE\n    X=2\n")
    ws = ["--workspace", str(tmp_path / "ws")]
    assert main([*ws, "run", str(bad)]) == 1
    out = capsys.readouterr().out
    assert "*** BAD STEP 2:" in out and "NOWHERE" in out and "VARIABLES  X=1" in out
    assert main([*ws, "run", "NOSUCH"]) == 1
    assert "NOSUCH.DAT" in capsys.readouterr().err
    broken = tmp_path / "BROKEN.SET"
    broken.write_text("2\nMM\nW\n1,8\n")
    assert main([*ws, "run", "PROCESS", "--cell", str(broken)]) == 1
    assert "BROKEN.SET:" in capsys.readouterr().err
