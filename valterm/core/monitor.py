"""The VAL-II prompt without a screen: command lines in, transcript lines out.

``LineMonitor`` drives a session's interpreter as the app's VAL-II mode does (EXECUTE,
PAUSE / PROCEED, the debugger's BPT, XSTEP, SSTEP, WATCH, TRACE) but writes each event as
the lines of the one transcript renderer (``valterm.core.text.transcript``).  Motions are not
paced and DELAY is not waited: the robot's time is the cycle time STATUS shows.
``valterm monitor`` reads standard input into it; nothing here reads a terminal.

CHECK.DAT is written once per batch of lines (``keep()``: when the input waits, and at its
end), not after every typed assignment: 20 000 piped ``ROW=...`` lines write it once.
"""

from __future__ import annotations

from collections.abc import Callable, Generator
from typing import TYPE_CHECKING

from valterm.core.errors import ValtermError
from valterm.core.events import Error, Event, Monitor, Pause
from valterm.core.numbers import two_decimals
from valterm.core.session import Session
from valterm.core.text.transcript import event_lines

if TYPE_CHECKING:        # the app's VAL-II mode lists programs before it runs one (issue 25: start time)
    from valterm.core.val.interpreter import Interpreter

__all__ = ["LineMonitor", "listing_lines"]

Events = Generator[Event, None, None]


class LineMonitor:
    """One VAL-II prompt: ``line(text)`` carries out a typed line, ``end()`` ends the input.

    ``failed`` is True once any command or program reported an error.
    """

    def __init__(self, session: Session, write: Callable[[str], None]) -> None:
        self.session = session
        self.interpreter: Interpreter = session.interpreter
        self.write = write
        self.failed = False
        self._run: Events | None = None  # the events of a paused program
        self._pulling: Events | None = None  # the events being pulled now
        self.interpreter.keep_batched = True

    def keep(self) -> None:
        """The end of a batch of lines: CHECK.DAT gets the variables changed since the last one."""
        if self.interpreter.unkept:
            try:
                self.interpreter.keep()
            except (OSError, ValtermError) as error:  # a full disk, a damaged CHECK.DAT: say so, go on
                self.show(Error("", 0, f"VARIABLES NOT KEPT: {error}"))

    @property
    def paused(self) -> bool:
        """A program is paused (PAUSE, a breakpoint, a single step): lines go to the prompt."""
        return self._run is not None

    @property
    def running(self) -> bool:
        """A program's events are being pulled (CTRL-C aborts it)."""
        return self._pulling is not None

    def line(self, text: str) -> None:
        """One line typed at the prompt."""
        if not text.strip():
            return
        events = self.interpreter.command(text)
        if self._run is None:
            self._pull(events)
            return
        was_paused = self.interpreter.paused
        self._show_all(events)  # a command typed while paused (its motions jump to the end)
        if was_paused and not self.interpreter.paused:  # PROCEED, XSTEP, SSTEP
            run, self._run = self._run, None
            self._pull(run)

    def abort(self) -> None:
        """CTRL-C: the running or paused program stops after the step being simulated."""
        self.interpreter.abort()
        if self._run is not None and self._pulling is None:
            run, self._run = self._run, None
            self.interpreter.proceed()
            self._pull(run)

    def end(self) -> int:
        """The end of the input: a paused program is aborted, the variables kept; 0, or 1 if
        anything failed."""
        if self._run is not None:
            self.abort()
        self.keep()
        return 1 if self.failed else 0

    def interrupted(self) -> None:
        """A second CTRL-C broke off the pulling: the program ends here, the prompt stays."""
        events, self._pulling = self._pulling, None
        if events is not None:
            events.close()
            self.show(Error(self.interpreter.program, 0, "ABORTED"))
        elif self._run is not None:
            self.abort()

    # -- events ---------------------------------------------------------------------------
    def _pull(self, events: Events) -> None:
        """Pull events until they end or the program pauses (then keep them for PROCEED)."""
        self._pulling = events
        for event in events:
            self.show(event)
            if isinstance(event, Pause) and self.interpreter.paused:
                self._run = events
                break
        self._pulling = None

    def _show_all(self, events: Events) -> None:
        for event in events:
            self.show(event)

    def show(self, event: Event) -> None:
        if isinstance(event, Error):
            self.failed = True
        if isinstance(event, Monitor):
            self._monitor(event)
            return
        for text in event_lines(event):
            self.write(text)

    def _monitor(self, event: Monitor) -> None:
        """LISTP, LISTF, LISTL here; EDIT and POINT need the app's screens."""
        try:
            lines = listing_lines(self.session, event.command, event.argument.strip())
        except (OSError, ValtermError) as error:  # a missing or damaged file: say so, go on
            self.show(Error("", 0, str(error)))
            return
        if lines is not None:
            for text in lines:
                self.write(text)
        elif event.command == "POINT":
            self.show(Error("", 0, "POINT NEEDS THE APP: HERE, SET OR A .LOC FILE (--loc) DEFINE LOCATIONS"))
        else:
            self.show(Error("", 0, f"{event.command} NEEDS THE APP: EDIT THE FILES OF THE WORKSPACE"))


def listing_lines(session: Session, command: str, argument: str) -> list[str] | None:
    """LISTF, LISTL, LISTP as lines (None for another command); OSError / ValtermError
    for a missing or damaged file."""
    workspace = session.workspace
    if command == "LISTF":
        return ["PROGRAMS: " + "  ".join(workspace.list_programs())]
    if command == "LISTL":
        lines = ["LOCATION FILES: " + "  ".join(workspace.list_locations())]
        for name, location in session.simulator.locations.items():  # two decimals, as WHERE shows them
            lines.append(f"POINT {name}, " + ", ".join(map(two_decimals, (*location.xyz, *location.oat))))
        return lines
    if command == "LISTP":
        program = workspace.read_program(argument)
        lines = [f"PROGRAM {program.name}"]
        for number, step in enumerate(program.steps, start=1):
            label = "" if step.label is None else str(step.label)
            lines.append(f"{number:>4}. {label:<4}{step.text}")
        return lines
    return None
