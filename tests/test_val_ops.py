"""The interpreter's typed ops, numbers that are not finite, and no code generation in the core."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from test_val_interpreter import FakeSim, make

from valterm.core.errors import ValtermError
from valterm.core.events import Error, Event, Message, Step, TypeOut
from valterm.core.kinematics import CONFIG_WORDS, Config, indicator_kind
from valterm.core.val.dialects.val1985.builders import BUILDERS
from valterm.core.val.checker import check_program
from valterm.core.val.expr import (
    ExprError,
    NumberTooLarge,
    compile_condition,
    compile_expr,
)
from valterm.core.val.interpreter import (
    Interpreter,
    ProgramError,
    RunStop,
    UndefinedVariable,
    program_from_lines,
)
from valterm.core.val.ops import (
    Action,
    Assign,
    Branch,
    Call,
    Jump,
    PauseOp,
    Return,
    Stop,
)

CORE = Path(__file__).resolve().parent.parent / "valterm" / "core"


def compiled(lines: list[str]) -> list[type]:
    interpreter = make({"MAIN": lines})
    return [type(op) for op in interpreter.compile("MAIN").code]


def test_each_step_becomes_a_typed_op() -> None:
    kinds = compiled([
        "    I=0", "    WHILE I .LT. 3 DO", "    I=I+1", "    END", "    IF I .EQ. 3 THEN",
        "    MOVE A", "    ELSE", "    CALL SUB", "    END", "10  GOTO 10", "    RETURN",
        "    PAUSE WAIT", "    STOP", "; a comment gets no op",
    ])
    assert kinds == [Assign, Branch, Assign, Jump, Branch, Action, Jump, Call, Jump, Jump, Return,
                     PauseOp, Stop]


def test_branch_targets_follow_the_structure() -> None:
    interpreter = make({"MAIN": ["    I=0", "    WHILE I .LT. 3 DO", "    I=I+1", "    END", "    TYPE DONE"]})
    code = interpreter.compile("MAIN").code
    loop, end = code[1], code[3]
    assert isinstance(loop, Branch) and (loop.if_true, loop.if_false, loop.error) == (2, 4, 4)
    assert isinstance(end, Jump) and end.next == 1  # END of a WHILE goes back to it
    assert isinstance(code[2], Assign) and code[2].name == "I" and code[2].value({"I": 4.0}) == 5.0


def test_every_1985_command_that_runs_has_a_builder() -> None:
    for word in ("MOVE", "MOVES", "APPRO", "APPROS", "DEPART", "DEPARTS", "DRAW", "READY", "OPEN",
                 "OPENI", "CLOSE", "CLOSEI", "GRASP", "SPEED", "DELAY", "TYPE", "SET", "HERE", "CALL",
                 "GOTO", "IF", "RETURN", "STOP", "PAUSE", *CONFIG_WORDS):
        assert word in BUILDERS, word


def test_a_dialect_adds_an_instruction_and_a_step_hook_sees_every_step() -> None:
    def beep(c, st):  # a builder of a new instruction, as a dialect would add it
        def run():
            yield TypeOut("BEEP")
            return c.next
        return c.action(run)

    seen: list[tuple[str, int]] = []

    def hook(program, op) -> list[Event]:
        seen.append((program.name, op.step.step))
        return []

    interpreter = make({"MAIN": ["    TYPE HELLO", "    DELAY 0"]})
    interpreter.builders["DELAY"] = beep
    interpreter.hook = hook
    events = list(interpreter.execute("MAIN"))
    assert [e.text for e in events if isinstance(e, TypeOut)] == ["HELLO", "BEEP"]
    assert seen == [("MAIN", 1), ("MAIN", 2)]


def test_a_hook_set_or_removed_while_running_and_ctrl_c_in_it_count_from_the_next_step() -> None:
    """The loop looks at one flag a step (issue 25): setting the hook, removing it and CTRL-C raise it."""
    seen: list[int] = []

    def hook(program, op) -> list[Event]:
        seen.append(op.step.step)
        if op.step.step == 4:
            interpreter.hook = None
        return []

    interpreter = make({"MAIN": ["    X=1", "    X=2", "    X=3", "    X=4", "    X=5", "    X=6"]})
    run = interpreter.execute("MAIN")
    assert next(run) == Step("MAIN", 1, "X=1")
    interpreter.hook = hook  # as the debugger sets a breakpoint while the program is paused
    assert [e.step for e in run if isinstance(e, Step)] == [2, 3, 4, 5, 6]
    assert seen == [2, 3, 4] and interpreter.hook is None

    def aborting(program, op) -> list[Event]:
        interpreter.abort()  # CTRL-C while the hook holds the program
        return []

    interpreter.hook = aborting
    events = list(interpreter.execute("MAIN"))
    assert [type(e).__name__ for e in events] == ["Error"] and events[0].step == 1
    interpreter.hook = None
    assert sum(isinstance(e, Step) for e in interpreter.execute("MAIN")) == 6  # nothing left raised


# -- numbers that are not finite (issue 16) -------------------------------------------------

@pytest.mark.parametrize("text", ["1E400", "1e400", "1E300*1E300", "-1E400"])
def test_non_finite_constants_are_refused(text: str) -> None:
    with pytest.raises(NumberTooLarge, match="NUMBER TOO LARGE"):
        compile_expr(text)
    with pytest.raises(ExprError):
        compile_condition(f"X .LT. {text}")


def test_x_equals_1e400_is_a_located_error_not_a_traceback() -> None:
    program = program_from_lines("BIG", ["    X = 1e400", "    TYPE X="])
    report = check_program(program)
    assert [(d.program, d.step) for d in report.errors] == [("BIG", 1)]
    assert "NUMBER TOO LARGE" in report.errors[0].message
    interpreter = Interpreter(FakeSim(), lambda name: program, {})
    events = list(interpreter.execute("BIG"))
    failures = [e for e in events if isinstance(e, Error)]
    assert failures[0].program == "BIG" and failures[0].step == 1
    assert "NUMBER TOO LARGE" in failures[0].message
    assert "X" not in interpreter.variables


def test_an_overflow_at_run_time_keeps_the_variable_finite() -> None:
    interpreter = make({"MAIN": ["    X = 1E200", "    X = X*X", "    TYPE X="]})
    events = list(interpreter.execute("MAIN"))
    failures = [e for e in events if isinstance(e, Error)]
    assert [(e.program, e.step) for e in failures] == [("MAIN", 2)]
    assert failures[0].message.startswith("NUMBER TOO LARGE")
    assert interpreter.variables["X"] == 1e200
    assert any(isinstance(e, TypeOut) and e.text == "X = 1e+200" for e in events)


def test_typed_overflow_is_refused() -> None:
    interpreter = make(variables={"X": 1e200})
    events = list(interpreter.command("Y = X*X"))
    assert [e.message for e in events if isinstance(e, Error)] == ["NUMBER TOO LARGE: Y WOULD BE inf"]
    assert "Y" not in interpreter.variables


# -- errors and configuration words --------------------------------------------------------

def test_interpreter_errors_are_valterm_errors_with_program_and_step() -> None:
    for cls in (ProgramError, RunStop, UndefinedVariable):
        assert issubclass(cls, ValtermError)
    error = RunStop("CALL X: MORE THAN 20 NESTED CALLS", "MAIN", 4)
    assert (error.program, error.step) == ("MAIN", 4)
    assert error.located() == "MAIN step 4: CALL X: MORE THAN 20 NESTED CALLS"
    assert UndefinedVariable("ROW").message == "VARIABLE ROW IS NOT DECLARED"


def test_configuration_words_are_listed_once() -> None:
    assert CONFIG_WORDS == ("RIGHTY", "LEFTY", "ABOVE", "BELOW", "NOFLIP", "FLIP")
    assert [indicator_kind(w) for w in ("LE", "RIGHTY", "AB", "BELOW", "NOF", "FLIP")] == [
        "arm", "arm", "elbow", "elbow", "wrist", "wrist"]
    assert Config.parse("LEFTY,BELOW,FLIP") == Config(-1, -1, -1)
    for path in (CORE / "simulator.py", CORE / "val" / "interpreter.py", CORE / "val" / "builders.py"):
        assert '"NOFLIP"' not in path.read_text(), path


def test_the_indicator_words_reach_the_simulator() -> None:
    sim = FakeSim()
    make({"MAIN": ["    LEFTY", "    BELOW", "    FLIP"]}, sim=sim)
    interpreter = make({"MAIN": ["    LEFTY", "    BELOW", "    FLIP"]}, sim=sim)
    list(interpreter.execute("MAIN"))
    assert sim.calls == [("indicator", "LEFTY"), ("indicator", "BELOW"), ("indicator", "FLIP")]


def test_no_exec_or_eval_in_the_core() -> None:
    pattern = re.compile(r"(?<![\w.])(?<!def )(exec|eval|compile)\s*\(")  # the built-ins, not methods
    offenders = [f"{path.relative_to(CORE)}:{number}"
                 for path in sorted(CORE.rglob("*.py"))
                 for number, line in enumerate(path.read_text().splitlines(), start=1)
                 if pattern.search(line.split("#", 1)[0])]
    assert offenders == []


def test_a_long_loop_still_completes_with_messages() -> None:
    interpreter = make({"MAIN": ["    I=0", "    WHILE I .LT. 500 DO", "    I=I+1", "    END"]})
    events = list(interpreter.execute("MAIN"))
    assert sum(isinstance(e, Step) for e in events) == 1 + 501 + 500 * 2
    assert isinstance(events[-1], Message) and "COMPLETED" in events[-1].text


def test_the_real_simulator_and_the_tests_stand_in_fit_the_protocol() -> None:
    from valterm.core.simulator import Simulator
    from valterm.core.val import protocol

    assert isinstance(Simulator(), protocol.Simulator)
    assert isinstance(FakeSim(), protocol.Simulator)
    assert not isinstance(object(), protocol.Simulator)
