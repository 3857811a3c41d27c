"""The program debugger: BPT, XSTEP, SSTEP, WATCH, TRACE (and AUTOCONFIG), typed at the prompt.

Names follow the Unimation/Adept monitor.  The debugger attaches to the interpreter's
``hook`` (called before each program step) and ``pass_end`` only while it has something to
do, so a program runs at full speed otherwise.

A breakpoint or the end of a single step pauses the program *before* a step with a
``Breakpoint`` event, a kind of ``Pause``: whoever pulls the events stops pulling, the user
types commands, PROCEED (or XSTEP / SSTEP) lets it go on.  The hook only runs before a step,
so what a step did (the variables it assigned: WATCH, TRACE) is seen before the next one, or
when the pass ends.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING

from valterm.core.errors import ValtermError
from valterm.core.events import Breakpoint, Error, Event, Message, Step, Trace, Watch
from valterm.core.text.transcript import watched_value
from valterm.core.val.ops import Assign, CompiledProgram, Op, ProgramError
from valterm.core.val.parser import Statement

if TYPE_CHECKING:
    from valterm.core.val.interpreter import Interpreter

__all__ = ["DEBUG_COMMANDS", "DebugError", "Debugger"]

_NAME = re.compile(r"[A-Z][A-Z0-9]{0,8}")
_BREAKPOINT = re.compile(r"(-?)\s*([A-Z][A-Z0-9]*)(?:\.DAT)?\s*,\s*(\d+)")


class DebugError(ValtermError):
    """A debugger command that cannot be carried out; the message says why."""


class Debugger:
    """The breakpoints, watched variables, TRACE and the pending single step of one interpreter."""

    def __init__(self, interpreter: Interpreter) -> None:
        self.interpreter = interpreter
        self.breakpoints: set[tuple[str, int]] = set()
        self.watches: dict[str, float | None] = {}  # name -> the value last seen (None: undeclared)
        self.trace = False
        self.paused_at: Step | None = None  # the step a breakpoint or single step paused before
        self._step = ""  # "XSTEP" / "SSTEP": a single step is pending
        self._step_depth: int | None = None  # the CALL depth of the step being stepped, once started
        self._previous: Op | None = None  # the step that ran last (its WATCH / TRACE not yet told)
        self._before: dict[str, float] = {}  # the variables before it (TRACE)

    # -- state ------------------------------------------------------------------------
    @property
    def active(self) -> bool:
        return bool(self.breakpoints or self.watches or self.trace or self._step)

    def _attach(self) -> None:
        """Hook into the run loop only while there is something to do."""
        if self.active:
            self.interpreter.hook, self.interpreter.pass_end = self.before_step, self.pass_end
        else:
            self.interpreter.hook = self.interpreter.pass_end = None
            self._previous = None

    def watched(self) -> list[tuple[str, float | None]]:
        """The watched variables and their present values (None: not declared)."""
        V = self.interpreter.variables
        return [(name, V.get(name)) for name in self.watches]

    def listing(self, program: str, step: int, around: int = 4) -> list[tuple[int, str, bool]]:
        """The steps of `program` around `step` (where it is paused): number, text, is it `step`.

        The program as the running EXECUTE decoded it; empty if it cannot be read.
        """
        try:
            steps = self.interpreter.compile(program).analysis.program.steps
        except ProgramError:
            return []
        first, last = max(1, step - around), min(len(steps), step + around)
        lines = []
        for number in range(first, last + 1):
            line = steps[number - 1]
            label = "" if line.label is None else str(line.label)
            lines.append((number, f"{label:<4}{line.text.strip()}", number == step))
        return lines

    def run_ended(self) -> None:
        """The program is over: a pending single step is forgotten."""
        self._step, self._step_depth, self._previous, self.paused_at = "", None, None, None
        self._attach()

    # -- the hook -----------------------------------------------------------------------
    def before_step(self, program: CompiledProgram, op: Op) -> Iterator[Event]:
        """Before each step: tell what the last step did, then stop here if asked to."""
        if self._previous is None:  # a run starts: what was typed since is not the step's doing
            yield from self._watch_changes("", 0)
        yield from self._told()
        reason = self._stop_reason(op)
        if reason:
            self._step, self._step_depth = "", None
            self._attach()
            step = op.step
            self.paused_at = step
            yield from self.interpreter.pause(Breakpoint(step.program, step.step, step.text, reason))
            self.paused_at = None
        if self._step and self._step_depth is None:
            self._step_depth = self.interpreter.call_depth  # this is the step XSTEP / SSTEP runs
        self._previous = op
        if self.trace:
            self._before = dict(self.interpreter.variables)

    def pass_end(self) -> Iterator[Event]:
        yield from self._told()

    def _stop_reason(self, op: Op) -> str:
        if self._step:
            if self._step_depth is None:
                return ""  # the step to execute: it runs even if it has a breakpoint
            if self._step == "XSTEP" or self.interpreter.call_depth <= self._step_depth:
                return self._step
        if (op.step.program, op.step.step) in self.breakpoints:
            return "BPT"
        return ""

    def _told(self) -> Iterator[Event]:
        """WATCH and TRACE for the step that ran last."""
        op, self._previous = self._previous, None
        if op is None:
            return
        step = op.step
        yield from self._watch_changes(step.program, step.step)
        if self.trace:
            V, before = self.interpreter.variables, self._before
            names = [name for name, value in V.items() if before.get(name) != value]
            if isinstance(op, Assign) and op.name in V and op.name not in names:
                names.insert(0, op.name)  # X=X assigns X too
            yield Trace(step.program, step.step, step.text, tuple((n, float(V[n])) for n in names))

    def _watch_changes(self, program: str, step: int) -> Iterator[Event]:
        V = self.interpreter.variables
        for name, old in self.watches.items():
            new = V.get(name)
            if new != old:
                self.watches[name] = new
                yield Watch(name, old, None if new is None else float(new), program, step)

    def typed_changes(self) -> Iterator[Event]:
        """Variables typed while a program was paused: WATCH tells them (program "", step 0)."""
        yield from self._watch_changes("", 0)
        if self.trace and self._previous is not None:
            self._before = dict(self.interpreter.variables)

    # -- the commands -------------------------------------------------------------------
    def bpt(self, text: str) -> Iterator[Event]:
        """BPT lists; BPT name,step sets; BPT -name,step clears."""
        if not text:
            if not self.breakpoints:
                yield Message("NO BREAKPOINTS")
                return
            yield Message("BREAKPOINTS: " + "  ".join(f"{p},{s}" for p, s in sorted(self.breakpoints)))
            return
        match = _BREAKPOINT.fullmatch(text)
        if match is None:
            raise DebugError(f"BPT {text}: EXPECTED BPT <PROGRAM>,<STEP> OR BPT -<PROGRAM>,<STEP>")
        clear, program, step = match.group(1) == "-", match.group(2), int(match.group(3))
        if clear:
            if (program, step) not in self.breakpoints:
                raise DebugError(f"NO BREAKPOINT AT {program} STEP {step}")
            self.breakpoints.discard((program, step))
            yield Message(f"BREAKPOINT AT {program} STEP {step} CLEARED")
        else:
            self._check_step(program, step)
            self.breakpoints.add((program, step))
            yield Message(f"BREAKPOINT SET AT {program} STEP {step}")
        self._attach()

    def _check_step(self, name: str, step: int) -> None:
        """The program exists and `step` is one that runs (not a comment)."""
        interpreter = self.interpreter
        try:
            program = interpreter.load_program(name)
        except (OSError, ValtermError):
            raise DebugError(f"PROGRAM {name} DOES NOT EXIST") from None
        steps = {op.step.step for op in interpreter.compile_program(program).code}
        if step not in steps:
            last = len(program.steps)
            why = f"IT HAS {last} STEPS" if step > last or step < 1 else "A COMMENT OR BLANK STEP"
            raise DebugError(f"{name} STEP {step} CANNOT HAVE A BREAKPOINT ({why})")

    def single_step(self, kind: str, text: str) -> Iterator[Event]:
        """XSTEP / SSTEP [name[,step]]: one step of the paused program, or start one."""
        interpreter = self.interpreter
        if not text:
            if not interpreter.paused:
                raise DebugError(f"NO PROGRAM IS PAUSED ({kind} <PROGRAM> STARTS ONE)")
            yield from self.typed_changes()
            self._step, self._step_depth = kind, None
            self._attach()
            interpreter.proceed()
            return
        name, _, step_text = text.partition(",")
        name = name.strip().removesuffix(".DAT")
        if not _NAME.fullmatch(name) or not (step_text.strip() or "0").isdigit():
            raise DebugError(f"{kind} {text}: EXPECTED {kind} <PROGRAM>,<STEP>")
        if interpreter.running:
            raise DebugError(f"A PROGRAM ({interpreter.program}) IS ALREADY RUNNING")
        self._step, self._step_depth = kind, None
        self._attach()
        yield from interpreter.execute(name, 1, int(step_text.strip() or "0"))
        if not interpreter.running:  # it could not start (or it ended): no step is pending
            self.run_ended()

    def proceed(self) -> Iterator[Event]:
        if not self.interpreter.paused:
            raise DebugError("NO PROGRAM IS PAUSED")
        yield from self.typed_changes()
        self.interpreter.proceed()

    def watch(self, text: str) -> Iterator[Event]:
        """WATCH lists; WATCH var watches; WATCH -var stops."""
        if not text:
            if not self.watches:
                yield Message("NO VARIABLES ARE WATCHED")
                return
            yield Message("WATCHED: " + "  ".join(f"{n}={watched_value(v)}" for n, v in self.watches.items()))
            return
        clear = text.startswith("-")
        name = text.removeprefix("-").strip()
        if not _NAME.fullmatch(name):
            raise DebugError(f"WATCH {text}: {name or 'NOTHING'} IS NOT A VARIABLE NAME")
        if clear:
            if self.watches.pop(name, False) is False:
                raise DebugError(f"{name} IS NOT WATCHED")
            yield Message(f"{name} NO LONGER WATCHED")
        else:
            value = self.interpreter.variables.get(name)
            self.watches[name] = None if value is None else float(value)
            yield Message(f"WATCHING {name} = {watched_value(self.watches[name])}")
        self._attach()

    def set_trace(self, text: str) -> Iterator[Event]:
        if text in ("ON", "OFF"):
            self.trace = text == "ON"
            self._attach()
        elif text:
            raise DebugError(f"TRACE {text}: EXPECTED TRACE ON OR TRACE OFF")
        yield Message(f"TRACE {'ON' if self.trace else 'OFF'}")




def _autoconfig(interpreter: Interpreter, text: str) -> Iterator[Event]:
    """AUTOCONFIG ON|OFF: an unreachable target tries the other configurations (thesis §8.1)."""
    sim = interpreter.sim
    if not hasattr(sim, "autoconfig"):
        raise DebugError("THIS SIMULATOR HAS NO AUTOMATIC CONFIGURATION CHANGE")
    if text in ("ON", "OFF"):
        sim.autoconfig = text == "ON"
    elif text:
        raise DebugError(f"AUTOCONFIG {text}: EXPECTED AUTOCONFIG ON OR AUTOCONFIG OFF")
    yield Message(f"AUTOCONFIG {'ON' if sim.autoconfig else 'OFF'}")


MonitorCommand = Callable[["Interpreter", Statement], Iterator[Event]]  # interpreter.MonitorCommand (no import circle)


def _command(run: Callable[[Interpreter, str], Iterator[Event]]) -> MonitorCommand:
    """A monitor command taking the rest of the line; a DebugError is its error message."""
    def handler(interpreter: Interpreter, st: Statement) -> Iterator[Event]:
        text = " ".join(str(st.args[0] or "").upper().split()) if st.args else ""
        try:
            yield from run(interpreter, text)
        except DebugError as error:
            yield Error("", 0, str(error))
    return handler


DEBUG_COMMANDS: dict[str, MonitorCommand] = {
    "BPT": _command(lambda i, text: i.debugger.bpt(text)),
    "XSTEP": _command(lambda i, text: i.debugger.single_step("XSTEP", text)),
    "SSTEP": _command(lambda i, text: i.debugger.single_step("SSTEP", text)),
    "PROCEED": _command(lambda i, text: i.debugger.proceed()),
    "WATCH": _command(lambda i, text: i.debugger.watch(text)),
    "TRACE": _command(lambda i, text: i.debugger.set_trace(text)),
    "AUTOCONFIG": _command(_autoconfig),
}
