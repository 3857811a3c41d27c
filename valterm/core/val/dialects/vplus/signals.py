"""V+ signals and waits: SIGNAL, BITS, WAIT, WAIT.EVENT, REACT/REACTI/IGNORE.
"""

from __future__ import annotations

import re
from collections.abc import Callable

from valterm.core.errors import ValtermError
from valterm.core.events import Delay
from valterm.core.val import builders as shared
from valterm.core.val.builders import Build, Builder
from valterm.core.val.dialects.vplus.compiled import (
    condition_of,
    controller_of,
    number_of,
    reacting,
)
from valterm.core.val.dialects.vplus.expr import (
    NAME,
)
from valterm.core.val.machine import TICK, Machine
from valterm.core.val.ops import (
    Events,
    Op,
    ProgramError,
)
from valterm.core.val.parser import (
    Statement,
)

WAIT_POLL = 0.1  # seconds between two looks at a WAIT condition (simulated time)
MAJOR_CYCLE = TICK  # seconds: V+'s trajectory cycle, the time a WAIT with no condition lets pass
NEVER_AFTER = 1e9  # seconds: a WAIT with no run limit looks no further (the clock's own horizon)
_N = NAME

def _signal(c: Build, st: Statement) -> Op:
    numbers = [number_of(c, t) for t in st.args]
    machine = controller_of(c)

    def run() -> Events:
        for number in numbers:
            value = number(c.variables)
            if value != int(value) or value == 0:
                raise ProgramError(f"SIGNAL {shared.format_value(value)}: NOT A SIGNAL NUMBER")
            try:
                yield machine.set_signal(int(value))
            except ValtermError as error:
                raise ProgramError(str(error).upper()) from None
        return c.next
    return reacting(c, run)


def _bits(c: Build, st: Statement) -> Op:
    """BITS first, count = value: signals first .. first+count-1 set to value's bits (the
    lowest bit to the first signal)."""
    first, value = number_of(c, st.args[0]), number_of(c, st.args[-1])
    count = number_of(c, st.args[1]) if len(st.args) == 3 else (lambda V: 1.0)
    machine = controller_of(c)

    def run() -> Events:
        start, bits, number = int(first(c.variables)), int(value(c.variables)), int(count(c.variables))
        if not 1 <= number <= 32:
            raise ProgramError(f"BITS: {number} SIGNALS (1 TO 32)")
        for offset in range(number):
            signal = start + offset
            try:
                yield machine.set_signal(signal if bits >> offset & 1 else -signal)
            except ValtermError as error:
                raise ProgramError(str(error).upper()) from None
        return c.next
    return reacting(c, run)


def _wait(c: Build, st: Statement) -> Op:
    """WAIT cond: simulated time passes until cond is true (a TIMER reaches a value, a
    scripted input changes); with neither possible the program stops and says so."""
    machine = controller_of(c)
    if st.args[0] is None:  # WAIT alone: until the next major cycle (a polling loop's pause)
        def cycle() -> Events:
            yield from machine.observe(iter([Delay(MAJOR_CYCLE)]))
            return c.next
        return reacting(c, cycle)
    condition = condition_of(c, st.args[0])
    text = st.args[0]

    def holds() -> bool:
        return bool(condition(c.variables))

    def run() -> Events:
        started = machine.time
        while not holds():
            coming = machine.next_input_time()
            if coming is None and machine.waits_for_keyboard():
                # the app waits in real time (the user may set an input), a TIMER to the microsecond
                when = first_true(machine, holds, machine.time + WAIT_POLL)
                yield Delay(WAIT_POLL if when is None else when - machine.time)
                yield from machine.apply_inputs()
                started = machine.time  # no time limit: the user ends it (an input, or CTRL-C)
                continue
            if coming is None and machine.keyboard:
                return c.next  # CTRL-C: the run stops after this step
            limit = min(machine.deadline, started + NEVER_AFTER)  # the run's limit of robot time
            until = limit if coming is None else min(coming, limit)
            when = first_true(machine, holds, until)
            if when is not None:  # the clock makes it true before any input changes
                yield from machine.wait(when - machine.time)
            elif coming is None and first_true(machine, holds, NEVER_AFTER, NEVER_AFTER) is None:
                raise ProgramError(f"WAIT {text}: IT NEVER BECOMES TRUE (NO MORE INPUTS ARE SCRIPTED)")
            elif coming is None or coming > limit:
                yield from machine.wait(max(0.0, limit - machine.time))  # the robot waited up to the limit
                raise ProgramError(f"WAIT {text}: STILL FALSE AT THE LIMIT: {machine.deadline_said}")
            else:
                yield from machine.wait(coming - machine.time)  # the input changes now
            if machine.pending:  # a REACT program runs first, then this WAIT looks again
                return c.op_index[c.index]
        return c.next
    return reacting(c, run)


def first_true(machine: Machine, condition: Callable[[], bool], until: float,
               poll: float = WAIT_POLL) -> float | None:
    """The first time (to a microsecond) up to ``until`` at which ``condition`` holds, the
    inputs as they are now; None if it never does. The controller looks at a WAIT's
    condition continually: polls ``poll`` apart find it, halving the last one pins it."""
    clock, now = machine.clock, machine.clock.seconds
    try:
        low = now
        while low < until:
            high = min(low + poll, until)
            clock.seconds = high
            if condition():
                while high - low > 1e-6:
                    clock.seconds = middle = (low + high) / 2
                    low, high = (low, middle) if condition() else (middle, high)
                return high
            low = high
        return None
    finally:
        clock.seconds = now


def _wait_event(c: Build, st: Statement) -> Op:
    seconds = number_of(c, st.args[0])
    machine = controller_of(c)

    def run() -> Events:
        value = max(0.0, float(seconds(c.variables)))
        yield Delay(value)  # the interpreter adds its time to the clock
        yield from machine.apply_inputs()
        return c.next
    return reacting(c, run)


def _react(c: Build, st: Statement) -> Op:
    """REACT/REACTI n, program: armed here; run by the next motion, WAIT or SIGNAL that sees it."""
    signal = number_of(c, st.args[0])
    machine = controller_of(c)
    program = st.args[1].upper() if len(st.args) > 1 else ""
    if st.command != "IGNORE" and not re.fullmatch(_N, program):
        return shared.failed(c, f"{st.command}: EXPECTED {st.command} <signal>, <program>")

    def run() -> Events:
        number = int(signal(c.variables))
        try:
            if st.command == "IGNORE":
                machine.ignore(number)
            else:
                machine.react(number, program)
        except ValtermError as error:
            raise ProgramError(str(error).upper()) from None
        return c.next
        yield
    return c.action(run)


SIGNALS: dict[str, Builder] = {
    "SIGNAL": _signal, "BITS": _bits, "WAIT": _wait, "WAIT.EVENT": _wait_event,
    "REACT": _react, "REACTI": _react, "IGNORE": _react,
}
