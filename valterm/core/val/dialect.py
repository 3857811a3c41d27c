"""What a dialect of VAL is to the shared core: its grammar (how pass 1 decodes a step),
its statement table (a builder per command) and the few ways its controller differs.

The core (``compiler``, ``builders``, ``ops``, ``interpreter``, ``checker``) asks the
dialect, never its name; each dialect is a package under ``valterm.core.val.dialects`` whose
``DIALECT`` is one of these (docs/ARCHITECTURE.md, "Adding a dialect").
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

from valterm.core.events import Where
from valterm.core.val.builders import Builder
from valterm.core.val.compiler import Grammar


@dataclass(frozen=True)
class Dialect:
    grammar: Grammar  # how pass 1 decodes a step, finds the block a bad step opens
    title: str  # what a program was checked against, as CHECK says it: "1985 (COMMAND.DAT)"
    builders: Mapping[str, Builder]  # the statement table: command -> builder
    # the controller stops a program at a step that fails (V+); the 1985 simulator reports
    # the error and goes on with the next step
    stops_at_error: bool = False
    missing_program: str = "{name}.DAT"  # where a CALLed program was looked for, as CHECK's warning says it
    signals_in_status: bool = False  # STATUS typed at the prompt types the I/O panel's line too
    data_sections: bool = False  # its programs come from files with data sections (.LOCATIONS, .REALS)
    rules: str = "1985"  # the joint-state rules its programs run under by default (core/rules.py, SPEC §3a)
    # WHERE's readout in the dialect's convention (V+: yaw pitch roll); the thesis's O A T as it is
    readout: Callable[[Where], Where] | None = None

    @property
    def name(self) -> str:
        return self.grammar.name
