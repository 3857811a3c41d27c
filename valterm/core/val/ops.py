"""The executable form of a VAL-II program: one small typed op per step.

Pass 1 (``compiler.analyse``) decodes every step once; a builder per instruction
(``builders.BUILDERS``) turns each decoded step into one of these ops, so pass 2 never
decodes text again.  Every op knows its ``Step`` event, the index of the next op and
``error``, where an undeclared variable sends control (past END for IF and WHILE,
sections 6.4.7-8).

The run loop (``Interpreter``) executes the plain ops in place, fast (``Assign``,
``Branch``, ``Jump``: no events, no call of their own); an ``Action`` yields events from
its generator and returns the next op's index; a ``Control`` op changes the pass itself
(CALL, RETURN, STOP, PAUSE) through ``Run``.  A dialect adds instructions by adding
builders that return these ops (or new ``Control`` subclasses).
"""

from __future__ import annotations

from collections.abc import Callable, Generator
from dataclasses import dataclass, field
from typing import final

from valterm.core.errors import ValtermError
from valterm.core.events import Error, Event, Pause, Step, TypeOut
from valterm.core.val.compiler import Analysis
from valterm.core.val.expr import Fn

Events = Generator[Event, None, int]  # an op's events; its return value is the next op's index
MAX_CALL_DEPTH = 20  # nested CALLs before "CALL DEPTH" stops the program (every dialect's)


class ProgramError(ValtermError):
    """An error of a running program, located by program and step (0 and "" when typed)."""

    def __init__(self, message: str, program: str = "", step: int = 0) -> None:
        super().__init__(message)
        self.message = message
        self.program = program
        self.step = step

    def located(self) -> str:
        return f"{self.program} step {self.step}: {self.message}" if self.program else self.message


class UndefinedVariable(ProgramError, KeyError):
    """A variable read before it was given a value: ``VariableStore`` raises it for the name
    (a KeyError too, as a missing key of the variables is)."""

    def __init__(self, name: str, program: str = "", step: int = 0) -> None:
        super().__init__(f"VARIABLE {name} IS NOT DECLARED", program, step)
        self.name = name

    def __str__(self) -> str:  # the message, not KeyError's quoted key
        return self.message


class RunStop(ProgramError):
    """Something that ends the whole run (the message says what), e.g. a missing subroutine."""


@dataclass(frozen=True, slots=True)
class Op:
    step: Step
    next: int
    error: int


@final  # the run loop tells the plain ops by their exact type
@dataclass(frozen=True, slots=True)
class Assign(Op):
    """VAR = expr (section 6.7)."""

    name: str
    value: Fn


@final  # the run loop tells the plain ops by their exact type
@dataclass(frozen=True, slots=True)
class Branch(Op):
    """A condition choosing the next op: IF, WHILE, UNTIL, IF ... GOTO."""

    condition: Fn
    if_true: int
    if_false: int


@final  # the run loop tells the plain ops by their exact type
@dataclass(frozen=True, slots=True)
class Jump(Op):
    """Control goes to ``next``: GOTO, ELSE, END, DO (``next`` is the target)."""


@dataclass(frozen=True, slots=True)
class Action(Op):
    """Anything that yields events (motions, TYPE, WHERE, ...): ``pc = yield from run()``."""

    run: Callable[[], Events] = field(repr=False)


@dataclass
class CompiledProgram:
    name: str
    analysis: Analysis
    code: list[Op]
    first: int = 0
    # each op's Step event, by op index: the run loop yields ``steps[pc]``, read the same way
    # whatever the op's type (``op.step`` is read from a different class each step: slower)
    steps: list[Step] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        self.steps = [op.step for op in self.code]


@dataclass
class Run:
    """One execution pass: the program being run, the CALL frames to return to."""

    program: CompiledProgram
    frames: list[tuple[CompiledProgram, int]] = field(default_factory=list)
    ended: bool = False  # the pass ends normally (STOP, RETURN in the main program)
    failed: bool = False  # the pass is stopped by an error
    # what to do on leaving each frame (V+: restore the caller's variables), parallel to frames
    on_leave: list[Callable[[], None] | None] = field(default_factory=list)

    def enter(self, program: CompiledProgram, return_to: int,
              on_leave: Callable[[], None] | None = None) -> int:
        self.frames.append((self.program, return_to))
        self.on_leave.append(on_leave)
        self.program = program
        return 0

    def leave(self) -> int:
        """Back to the caller (its op after the CALL); the pass ends in the main program."""
        if not self.frames:
            self.ended = True
            return 0
        self.program, pc = self.frames.pop()
        restore = self.on_leave.pop() if self.on_leave else None
        if restore is not None:
            restore()
        return pc


class Control(Op):
    """An op that changes the pass itself; ``control`` yields events and returns the next pc."""

    __slots__ = ()

    def control(self, run: Run, call: Callable[[str], CompiledProgram]) -> Events:
        raise NotImplementedError


@dataclass(frozen=True, slots=True)
class Call(Control):
    """CALL program: every dialect's (a dialect's CALL with arguments extends ``control``)."""

    program: str
    max_depth: int = MAX_CALL_DEPTH

    def control(self, run: Run, call: Callable[[str], CompiledProgram]) -> Events:
        sub = yield from self.called(run, call, self.program)
        return run.enter(sub, self.next)

    def called(self, run: Run, call: Callable[[str], CompiledProgram], program: str
               ) -> Generator[Event, None, CompiledProgram]:
        """The program CALLed, compiled and ready to enter; the run stops (RunStop) past the
        CALL depth, when it does not exist, or when pass 1 finds it cannot run (its errors
        said first)."""
        caller = run.program.name
        if len(run.frames) >= self.max_depth:
            raise RunStop(f"CALL {program}: MORE THAN {self.max_depth} NESTED CALLS", caller, self.step.step)
        try:
            sub = call(program)
        except RunStop as stop:
            raise RunStop(f"CALL {program}: {stop.message}", caller, self.step.step) from None
        if not sub.analysis.structure_ok:
            for diagnostic in sub.analysis.fatal:
                yield Error(sub.name, diagnostic.step, diagnostic.message)
            raise RunStop(f"CALL {program}: THE PROGRAM CANNOT RUN", caller, self.step.step)
        return sub


@dataclass(frozen=True, slots=True)
class Return(Control):
    def control(self, run: Run, call: Callable[[str], CompiledProgram]) -> Events:
        return run.leave()
        yield  # a generator


@dataclass(frozen=True, slots=True)
class Stop(Control):
    """STOP / HALT [text]: the pass ends (the text is typed first)."""

    text: str = ""

    def control(self, run: Run, call: Callable[[str], CompiledProgram]) -> Events:
        if self.text:
            yield TypeOut(self.text)
        run.ended = True
        return 0


@dataclass(frozen=True, slots=True)
class PauseOp(Control):
    """PAUSE [text]: yields ``Pause``; the app pulling again is PROCEED."""

    text: str = ""
    on_pause: Callable[[bool], None] = field(default=lambda paused: None, repr=False)

    def control(self, run: Run, call: Callable[[str], CompiledProgram]) -> Events:
        self.on_pause(True)
        yield Pause(run.program.name, self.step.step, self.text)
        self.on_pause(False)
        return self.next
