"""Events as the lines a terminal shows: the scrolled steps, TYPE output, messages, WHERE.

The one renderer of events to text: the app's VAL-II mode and menus, ``valterm run`` and the
tests all print a session through ``event_lines``, so they print the same lines. Poses,
motions and the clamp's redraws have no line; HELP and the monitor commands (LISTP, EDIT,
...) are carried out by the edge that shows them, and are rendered here only as text.
"""

from __future__ import annotations

import textwrap
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import Protocol, TextIO

from valterm.core.events import (
    Breakpoint,
    Contact,
    Error,
    Event,
    Help,
    LimitReached,
    Message,
    Monitor,
    Near,
    Pause,
    Release,
    Signal,
    Status,
    Step,
    Trace,
    TypeOut,
    Watch,
    Where,
)
from valterm.core.numbers import angle_text, two_decimals

LABEL = 8  # Fig. 2-8: the indicator column
COLUMN = 9  # Fig. 2-8: each number right-aligned in nine columns


def _row(label: str, cells: Sequence[str]) -> str:
    return label.ljust(LABEL) + "".join(cell.rjust(COLUMN) for cell in cells)


number = two_decimals  # a readout number: two decimals, never -0.00


def where_lines(where: Where) -> list[str]:
    """The WHERE readout of Fig. 2-8: clamp, XW YW ZW O A T, the indicators, JT 1 .. JT 6
    (a V+ readout: X Y Z yaw pitch roll)."""
    config = where.config
    heads, angles = ("XW", "YW", "ZW", "O", "A", "T"), where.oat
    if where.ypr is not None:
        heads, angles = ("X", "Y", "Z", "YAW", "PITCH", "ROLL"), where.ypr
    return [
        _row(where.clamp, heads),
        _row(config.get("arm", ""), [*map(number, where.xyz), *map(angle_text, angles)]),
        _row(config.get("elbow", ""), [f"JT {i}" for i in range(1, 7)]),
        _row(config.get("wrist", ""), [number(v) for v in where.joints]),
    ]


def step_line(step: Step) -> str:
    """A step as it scrolls (§6.4.9): the program, the step number, the statement."""
    return f"{step.program:<9} {step.step:>3}  {step.text}"


def error_line(error: Error) -> str:
    """A run-time error located by program and step, upper case as on the VS11; a run limit
    also names the option that changes it (as typed: lower case)."""
    line = f"*** {error.where}{error.message}".upper()
    if isinstance(error, LimitReached) and error.flag:
        return f"{line} (raise it with {error.flag})"
    return line


def finding_line(event: Contact) -> str:
    """A collision check's finding (Fig. C-12): the core's own text when it has one; in a
    program, where it was found (program, step, the clamp's position)."""
    if event.text:
        return event.text + event.located
    verb = "IS NEAR" if isinstance(event, Near) else "COLLIDES WITH"
    return f"{event.a} {verb} {event.b}".upper() + event.located


def figure_lines(event: Contact, numbers: Mapping[str, int]) -> list[str]:
    """A finding as the 1985 screen printed it (Fig. C-12 a-d), ``numbers`` the robot's
    bodies numbered base to fingers (``collision.world.bodies``): the hand near a part is
    ``CLAMP IS NEAR PART 10``; another body n near part k is ``PART k IS NEAR PART n``; body n
    through part k is ``k COLLIDES WITH n``, after its near miss (the coarse check comes
    first). Carried parts and the arm against itself keep their words."""
    link, part = event.a, event.b
    if link not in numbers or not part.isdigit():
        return [finding_line(event)]
    n = numbers[link]
    hand = link in ("CLAMP", "FINGER", "FINGERS")
    near = f"CLAMP IS NEAR PART {part}" if hand else f"PART {part} IS NEAR PART {n}"
    if isinstance(event, Near):
        return [near + event.located]
    return [near + event.located, f"{part} COLLIDES WITH {n}" + event.located]


def breakpoint_line(event: Breakpoint) -> str:
    """Where the debugger paused: before a breakpoint's step, or after a single step."""
    what = "BREAKPOINT" if event.reason == "BPT" else f"{event.reason}: PAUSED"
    return f"{what} BEFORE {event.program} STEP {event.step}: {event.text.strip()}"


def watched_value(value: float | None) -> str:
    """A variable's value as WATCH shows it (UNDEFINED: not declared)."""
    from valterm.core.val.builders import format_value

    return "UNDEFINED" if value is None else format_value(value)


def watch_line(event: Watch) -> str:
    """WATCH: a variable's change, old -> new, and the step that made it."""
    where = f"{event.program} STEP {event.step}" if event.program else "TYPED"
    return f"WATCH {event.variable}: {watched_value(event.old)} -> {watched_value(event.new)} ({where})"


def trace_line(event: Trace) -> str:
    """TRACE ON: an executed step again, with the values of the variables it assigned."""
    values = "  ".join(f"{name}={watched_value(value)}" for name, value in event.assigned)
    line = f"TRACE {event.program:<9} {event.step:>3}  {event.text.strip()}"
    return f"{line}   [{values}]" if values else line


def event_lines(event: Event) -> list[str]:
    """What a transcript shows for one event (nothing for poses, motions, DELAY, the clamp)."""
    if isinstance(event, Step):
        return [step_line(event)]
    if isinstance(event, (TypeOut, Message)):
        return event.text.splitlines() or [""]
    if isinstance(event, Error):
        return [error_line(event)]
    if isinstance(event, Where):
        return where_lines(event)
    if isinstance(event, Status):
        robot = [event.robot_text] if event.robot_text else []  # the thesis's robot goes unsaid
        return [event.text, event.rules_text, *robot, event.cycle_text]
    if isinstance(event, Signal):
        return [event.text]
    if isinstance(event, Breakpoint):  # before Pause: it is one
        return [breakpoint_line(event)]
    if isinstance(event, Watch):
        return [watch_line(event)]
    if isinstance(event, Trace):
        return [trace_line(event)]
    if isinstance(event, Pause):
        return [f"PAUSE {event.text}".rstrip()]
    if isinstance(event, Contact):
        return [finding_line(event)]
    if isinstance(event, Release):
        return [f"PART {event.part} RELEASED"]
    if isinstance(event, Help):
        return list(event.lines)
    if isinstance(event, Monitor):
        return [f"{event.command} {event.argument}".rstrip()]
    return []  # PoseEvent, Motion, Hand, Grasp (its message says it), Delay, End


HEADLESS_PROCEED = "(headless: PROCEED)"  # a run with no one to type PROCEED goes on by itself

BLOCK = 1024  # pieces (lines) a write(): about 64 KB of JSON steps, a pipe's buffer


class Stream(Protocol):
    """What Blocks write to: standard output, a file, a test's counting stream."""

    def write(self, text: str, /) -> object: ...

    def flush(self) -> object: ...


class Blocks:
    """A transcript's text written to a stream in blocks: one ``write`` of BLOCK pieces, whatever
    the stream's own buffering (with ``PYTHONUNBUFFERED=1`` standard output makes a system call
    of every write: one a line, issue 40). ``watched`` (a person at a terminal): each piece is
    written and flushed at once, as it scrolls. ``flush()`` sends what is gathered."""

    def __init__(self, stream: Stream, watched: bool = False) -> None:
        self.stream = stream
        self.watched = watched
        self.pieces = 1 if watched else BLOCK
        self.pending: list[str] = []

    def write(self, text: str) -> None:
        self.pending.append(text)
        if len(self.pending) >= self.pieces:
            self.send()

    def send(self) -> None:
        """Write what is gathered (flushed too when a person is watching)."""
        if self.pending:
            self.stream.write("".join(self.pending))
            self.pending.clear()
            if self.watched:
                self.stream.flush()

    def flush(self) -> None:
        self.send()
        self.stream.flush()


def blocks_for(stream: TextIO) -> Blocks:
    """Blocks for a stream: watched when it is a terminal, gathered otherwise (a file, a pipe)."""
    try:
        watched = stream.isatty()
    except (OSError, ValueError):  # a closed or detached stream: no one is watching it
        watched = False
    return Blocks(stream, watched)


def write_events(events: Iterable[Event], out: Blocks, as_json: bool = False) -> int:
    """Write a run's events as ``valterm run`` prints them: their JSON lines, or the transcript's
    lines, in ``out``'s blocks (each line at once to a person watching); what is gathered is
    written when the events end, or stop with an exception. Returns how many of them were errors
    (the run's exit status).

    ``valterm bench`` times this very loop (issues 25, 40). A step, one a statement, is told by
    its exact type and its line read from it; the rarer events go the general way."""
    pending, pieces, send = out.pending, out.pieces, out.send
    add = pending.append
    errors = 0
    try:
        for event in events:
            if type(event) is Step:
                if as_json:
                    add(event.json or event.json_line())
                else:
                    add(event.line or _kept_line(event))
            else:
                errors += _add_lines(event, add, as_json)
            if len(pending) >= pieces:
                send()
    finally:
        send()
    return errors


def _kept_line(step: Step) -> str:
    """A step's transcript line, kept on it: a loop repeats its steps (as Step.json)."""
    object.__setattr__(step, "line", step_line(step) + "\n")
    return step.line


def _add_lines(event: Event, add: Callable[[str], object], as_json: bool) -> int:
    """An event's JSON line or transcript lines (a pause goes on by itself); 1 if an error."""
    if as_json:
        add(event.json_line())
    else:
        for line in event_lines(event):
            add(line + "\n")
        if isinstance(event, Pause):
            add(HEADLESS_PROCEED + "\n")
    return 1 if isinstance(event, Error) else 0


def wrap_line(line: str, width: int, indent: str = "") -> list[str]:
    """A line as the rows of a text ``width`` columns wide: broken at spaces where it can be (a
    word longer than the room left is cut at the edge, never at a hyphen), never cropped; the
    spaces at a break go, every other character stays, in order. A line that fits is returned
    as it is; the rows after the first start with ``indent`` (a menu's hanging indent) when
    it leaves them room. The one wrapping of the transcript, the menus and the listings."""
    if len(line) <= width and "\t" not in line:
        return [line]
    width = max(width, 1)
    indent = indent if len(indent) < width // 2 else ""
    return textwrap.wrap(line, width, subsequent_indent=indent, break_on_hyphens=False) or [""]
