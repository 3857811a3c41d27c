"""The I/O panel: the robot controller's binary signals, simulated (V+ numbering).

Outputs are 1..512 (set by ``SIGNAL n`` / ``SIGNAL -n``), inputs 1001..1512 (set by the
user from the keyboard, or scripted with ``run --inputs FILE``), internal (software) signals
2001..2512 (set by programs, the keyboard or a script, read like inputs). ``SIG(n)`` is TRUE (-1, as in V+) when
signal n is on; ``SIG(-n)`` when it is off.

An inputs script has one change a line: ``TIME SIGNAL VALUE`` (seconds since the run
started, an input or software signal number, 1/0 or ON/OFF); blank and ``#`` lines are skipped.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from valterm.core.errors import ValtermError
from valterm.core.files._text import numbered_lines, read_text
from valterm.core.files.errors import FileFormatError

OUTPUTS = range(1, 513)
INPUTS = range(1001, 1513)
INTERNAL = range(2001, 2513)
TRUE, FALSE = -1.0, 0.0  # V+ truth values
SETTABLE = "inputs are 1001-1512, software signals 2001-2512"  # what the keyboard and a script set


class SignalError(ValtermError):
    """A signal number outside the panel, or one a program may not set."""


def _kind(number: int) -> str:
    for name, numbers in (("output", OUTPUTS), ("input", INPUTS), ("internal", INTERNAL)):
        if number in numbers:
            return name
    raise SignalError(f"there is no signal {number} (outputs 1-512, inputs 1001-1512, internal 2001-2512)")


@dataclass(frozen=True)
class InputChange:
    """One line of an inputs script: at ``time`` seconds, input ``signal`` becomes ``on``."""

    time: float
    signal: int
    on: bool


@dataclass
class SignalPanel:
    """Which signals are on. Everything starts off."""

    on: set[int] = field(default_factory=set)

    def set_by_program(self, signed: int) -> int:
        """``SIGNAL n`` turns output/internal n on, ``SIGNAL -n`` off; returns n."""
        number = abs(int(signed))
        if _kind(number) == "input":
            raise SignalError(f"signal {number} is an input: a program cannot set it")
        self._set(number, signed > 0)
        return number

    def set_input(self, number: int, on: bool) -> None:
        """The keyboard or an inputs script sets input or software signal ``number``."""
        if number not in INPUTS and number not in INTERNAL:
            raise SignalError(f"signal {number} is not an input or a software signal ({SETTABLE})")
        self._set(number, on)

    def sig(self, signed: int) -> float:
        """``SIG(n)``: TRUE when n is on (SIG(-n): when it is off)."""
        number = abs(int(signed))
        _kind(number)
        state = number in self.on
        return TRUE if state == (signed > 0) else FALSE

    def _set(self, number: int, on: bool) -> None:
        if on:
            self.on.add(number)
        else:
            self.on.discard(number)

    def outputs_on(self) -> list[int]:
        return sorted(n for n in self.on if n in OUTPUTS)

    def inputs_on(self) -> list[int]:
        return sorted(n for n in self.on if n in INPUTS)


def parse_inputs(text: str, where: str | Path) -> list[InputChange]:
    """An inputs script, in time order (FileFormatError, located, for a bad line)."""
    changes = []
    for number, line in numbered_lines(text):
        words = line.split("#", 1)[0].split()
        if not words:
            continue
        if len(words) != 3:
            raise FileFormatError(where, number, "expected TIME SIGNAL VALUE, e.g. 1.5 1001 1")
        try:
            time, signal = float(words[0]), int(words[1])
        except ValueError:
            raise FileFormatError(where, number, "TIME is seconds and SIGNAL a whole number") from None
        value = words[2].upper()
        if value not in ("1", "0", "ON", "OFF") or not 0.0 <= time < 1e9:
            raise FileFormatError(where, number, "VALUE is 1, 0, ON or OFF and TIME a number of seconds >= 0")
        if signal not in INPUTS and signal not in INTERNAL:
            raise FileFormatError(where, number, f"signal {signal} is not an input or a software "
                                                 f"signal ({SETTABLE})")
        changes.append(InputChange(time, signal, value in ("1", "ON")))
    return sorted(changes, key=lambda change: change.time)


def read_inputs(path: str | Path) -> list[InputChange]:
    return parse_inputs(read_text(path, "inputs"), path)
