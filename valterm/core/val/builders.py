"""What every dialect's builders share: a decoded ``Statement`` -> a typed op.

``Build`` is what a builder knows (the step, the program's ops, the variables, the
simulator, the machine); ``Builder`` its type. A dialect's statement table maps each
command to its builder (``dialects/val1985/builders.py``, ``dialects/vplus/builders.py``);
``STRUCTURE`` holds the builders of the block structure and CALL that every VAL dialect
shares (GOTO, IF ... GOTO, ELSE, END, DO, CALL, RETURN, STOP, PAUSE).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

from valterm.core.events import Error, Status, Step
from valterm.core.val.compiler import Analysis
from valterm.core.val.expr import Expr, Values
from valterm.core.val.machine import Machine
from valterm.core.val.ops import (
    Action,
    Branch,
    Call,
    Events,
    Jump,
    Op,
    PauseOp,
    ProgramError,
    Return,
    Stop,
)
from valterm.core.val.parser import Statement
from valterm.core.val.protocol import Simulator


@dataclass(frozen=True)
class Build:
    """What a builder knows: the step, where the ops of the program are, the machine."""

    step: Step
    index: int  # the step's index in the program (0-based)
    analysis: Analysis | None  # None for a typed command
    op_index: Sequence[int]  # step index -> op index (one past the end included)
    variables: dict[str, float]
    sim: Simulator
    status: Callable[[], Status]
    set_paused: Callable[[bool], None]
    machine: Machine | None = None  # the V+ controller state (signals, strings, ...)

    @property
    def next(self) -> int:
        return self.op_index[self.index + 1]

    def target_of(self, label: int) -> int | None:
        if self.analysis is None or label not in self.analysis.labels:
            return None
        return self.op_index[self.analysis.labels[label]]

    def after(self, step_index: int) -> int:
        """The op following step `step_index` (past the END of a structure)."""
        return self.op_index[step_index + 1]

    def partner(self) -> int:
        assert self.analysis is not None  # control structures are refused as typed commands
        return self.analysis.partner[self.index]

    def missing_label(self, label: int) -> Error:
        return Error(self.step.program, self.step.step,
                     f"GOTO {label}: NO STEP WITH LABEL {label} (CONTINUING WITH THE NEXT STEP)")

    def action(self, run: Callable[[], Events], error: int | None = None) -> Action:
        return Action(self.step, self.next, self.next if error is None else error, run)

    def jump(self, target: int) -> Jump:
        return Jump(self.step, target, self.next)

    def branch(self, condition: Expr, if_true: int, if_false: int, error: int | None = None) -> Branch:
        return Branch(self.step, self.next, self.next if error is None else error,
                      condition.function(), if_true, if_false)


Builder = Callable[[Build, Statement], Op]


def format_value(value: float) -> str:
    value = float(value)
    if value.is_integer() and abs(value) < 1e15:
        return str(int(value))
    return f"{value:.6g}"


def getter(expr: Expr | None, default: float | None = None) -> Callable[[Values], float | None]:
    """A fast evaluator: constants are folded, an omitted argument gives the default."""
    if expr is None:
        return lambda V: default
    return expr.function()


def number(fn: Callable[[Values], float | None], variables: Values) -> float:
    """One argument's value (an undeclared variable is the store's UndefinedVariable)."""
    value = fn(variables)
    return 0.0 if value is None else float(value)


def numbers(fns: Sequence[Callable[[Values], float | None]], variables: Values) -> list[float | None]:
    return [fn(variables) for fn in fns]


def failed(c: Build, reason: str) -> Action:
    """A step that cannot run (it failed the syntax check): the program stops there."""
    def run() -> Events:
        raise ProgramError(reason)
        yield
    return c.action(run)



# -- the block structure and CALL: every dialect's --------------------------------------

def if_goto(c: Build, st: Statement) -> Op:
    condition, label = st.args
    target = c.target_of(label)
    if target is not None:
        return c.branch(condition, target, c.next)
    check = getter(condition)

    def missing() -> Events:
        if number(check, c.variables):
            yield c.missing_label(label)
        return c.next
    return c.action(missing)


def else_jump(c: Build, st: Statement) -> Op:
    assert c.analysis is not None
    opener = next(i for i, e in c.analysis.else_of.items() if e == c.index)
    return c.jump(c.after(c.analysis.partner[opener]))


def end_block(c: Build, st: Statement) -> Op:
    assert c.analysis is not None
    opener = c.analysis.partner.get(c.index)
    if opener is not None:
        statement = c.analysis.statements[opener]
        if statement is not None and statement.command == "WHILE":
            return c.jump(c.op_index[opener])
    return c.jump(c.next)


def do_jump(c: Build, st: Statement) -> Op:
    return c.jump(c.next)


def goto(c: Build, st: Statement) -> Op:
    label = st.args[0]
    target = c.target_of(label)
    if target is not None:
        return c.jump(target)

    def missing() -> Events:
        yield c.missing_label(label)
        return c.next
    return c.action(missing)


def call(c: Build, st: Statement) -> Op:
    return Call(c.step, c.next, c.next, st.args[0])


def return_op(c: Build, st: Statement) -> Op:
    return Return(c.step, c.next, c.next)


def stop(c: Build, st: Statement) -> Op:
    return Stop(c.step, c.next, c.next, st.args[0] or "")


def pause(c: Build, st: Statement) -> Op:
    return PauseOp(c.step, c.next, c.next, st.args[0] or "", c.set_paused)


STRUCTURE: dict[str, Builder] = {
    "ELSE": else_jump, "END": end_block, "ENDIF": end_block, "DO": do_jump, "GOTO": goto,
    "CALL": call, "RETURN": return_op, "STOP": stop, "HALT": stop, "PAUSE": pause,
}
"""The builders of the block structure and CALL that every VAL dialect shares."""


def build(c: Build, st: Statement, builders: Mapping[str, Builder]) -> Op:
    """The op of one decoded statement (an error op for a command that cannot be run here)."""
    builder = builders.get(st.command)
    if builder is None:
        return failed(c, f"{st.command} cannot be used here")
    return builder(c, st)
