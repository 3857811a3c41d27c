"""Events as the lines a terminal shows: the scrolled steps, TYPE output, messages, WHERE.

Shared by ``valterm run`` and anything else that prints a VAL-II session as text.
"""

from __future__ import annotations

from valterm.core.events import (
    Breakpoint,
    Collision,
    Error,
    Event,
    Grasp,
    Help,
    Message,
    Monitor,
    Near,
    Pause,
    Release,
    Status,
    Step,
    Trace,
    TypeOut,
    Watch,
    Where,
)


def where_lines(where: Where) -> list[str]:
    """The WHERE readout of Fig. 2-8: clamp, position and O A T, then the joint angles."""
    config = where.config or {}
    row = "{:<7}" + "{:>9}" * 6
    return [
        row.format(where.clamp, "XW", "YW", "ZW", "O", "A", "T"),
        row.format(config.get("arm", ""), *(f"{v:.2f}" for v in (*where.xyz, *where.oat))),
        row.format(config.get("elbow", ""), "JT1", "JT2", "JT3", "JT4", "JT5", "JT6"),
        row.format(config.get("wrist", ""), *(f"{v:.2f}" for v in where.joints)),
    ]


def step_line(step: Step) -> str:
    return f"{step.program:<9} {step.step:>3}  {step.text}"


def error_line(error: Error) -> str:
    if error.program:
        return f"*** {error.program} step {error.step}: {error.message}"
    return f"*** {error.message}"


def breakpoint_line(event: Breakpoint) -> str:
    """Where the debugger paused: before a breakpoint's step, or after a single step."""
    what = "BREAKPOINT" if event.reason == "BPT" else f"{event.reason}: PAUSED"
    return f"{what} BEFORE {event.program} step {event.step}: {event.text.strip()}"


def _number(value: float | None) -> str:
    from valterm.core.val.builders import format_value

    return "UNDEFINED" if value is None else format_value(value)


def watch_line(event: Watch) -> str:
    where = f"{event.program} step {event.step}" if event.program else "TYPED"
    return f"WATCH {event.variable}: {_number(event.old)} -> {_number(event.new)} ({where})"


def trace_line(event: Trace) -> str:
    values = "  ".join(f"{name}={_number(value)}" for name, value in event.assigned)
    line = f"TRACE {event.program:<9} {event.step:>3}  {event.text.strip()}"
    return f"{line}   [{values}]" if values else line


def event_lines(event: Event) -> list[str]:
    """What a transcript shows for one event (nothing for poses and motions)."""
    if isinstance(event, Step):
        return [step_line(event)]
    if isinstance(event, TypeOut):
        return [event.text]
    if isinstance(event, Message):
        return [event.text]
    if isinstance(event, Error):
        return [error_line(event)]
    if isinstance(event, Where):
        return where_lines(event)
    if isinstance(event, Status):
        return [event.text, event.cycle_text]
    if isinstance(event, Breakpoint):  # before Pause: it is one
        return [breakpoint_line(event)]
    if isinstance(event, Watch):
        return [watch_line(event)]
    if isinstance(event, Trace):
        return [trace_line(event)]
    if isinstance(event, Pause):
        return [f"PAUSE {event.text}".rstrip()]
    if isinstance(event, (Near, Collision)):
        return [event.text or f"{event.a} / {event.b}"]
    if isinstance(event, Grasp):
        return []  # the simulator's message says it (IT IS POSSIBLE TO GRASP THIS PART)
    if isinstance(event, Release):
        return [f"PART {event.part} RELEASED"]
    if isinstance(event, Help):
        return list(event.lines)
    if isinstance(event, Monitor):
        return [f"{event.command} {event.argument}".rstrip()]
    return []
