"""What the V+ builders share: the controller, and a step's numbers, locations and
conditions compiled against it; ``Reacting``, a step after which a REACT program may run.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from valterm.core.events import Message
from valterm.core.transform import Transform
from valterm.core.val.builders import Build
from valterm.core.val.dialects.vplus.expr import (
    compile_location,
    compile_number,
    compile_precision,
)
from valterm.core.val.expr import ExprError, Fn, Values
from valterm.core.val.machine import Machine
from valterm.core.val.ops import (
    CompiledProgram,
    Control,
    Events,
    Op,
    ProgramError,
    Run,
    RunStop,
)


def controller_of(c: Build) -> Machine:
    machine = c.machine
    if machine is None:
        raise ProgramError("V+ STATEMENTS NEED THE V+ CONTROLLER")
    return machine


def number_of(c: Build, text: str) -> Fn:
    return compile_number(text, controller_of(c)).function()


def location_of(c: Build, text: str) -> Callable[[Values], Transform]:
    return compile_location(text, controller_of(c))


def store_location(c: Build, name: str, transform: Transform) -> None:
    c.sim.locations[name] = transform.location()


def _no_events() -> Events:
    return 0
    yield


@dataclass(frozen=True, slots=True)
class Reacting(Control):
    """A V+ step during which signals may change (motions, WAIT, DELAY, SIGNAL): after it, a
    triggered REACT program is CALLed, returning to the next step (V+ reaction semantics,
    checked between steps rather than mid-motion)."""

    body: Callable[[], Events] = field(default=_no_events, repr=False)
    machine: Machine | None = field(default=None, repr=False)

    def control(self, run: Run, call: Callable[[str], CompiledProgram]) -> Events:
        pc = yield from self.body()
        if self.machine is None or not self.machine.pending:
            return pc
        signed, program = self.machine.pending.pop(0)
        yield Message(f"REACT {signed}: CALL {program}")
        try:
            sub = call(program)
        except RunStop as stop:
            raise RunStop(f"REACT {signed}: {stop.message}", run.program.name, self.step.step) from None
        return run.enter(sub, pc)


def reacting(c: Build, body: Callable[[], Events]) -> Op:
    return Reacting(c.step, c.next, c.next, body, controller_of(c))


def condition_of(c: Build, text: str) -> Fn:
    fn = number_of(c, text)
    return lambda V: bool(fn(V))


def precision_of(c: Build, text: str) -> Callable[[Values], tuple[float, ...]] | None:
    """A precision point's joints (#name, #PPOINT(...)); None for a compound like #p:TRANS(...)."""
    try:
        return compile_precision(text, controller_of(c))
    except ExprError:
        return None

