"""Events as the lines a terminal shows: the scrolled steps, TYPE output, messages, WHERE.

Shared by ``valterm run`` and anything else that prints a VAL-II session as text.
"""

from __future__ import annotations

from valterm.core.events import (
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
    Signal,
    Status,
    Step,
    TypeOut,
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
    """`*** PROG step 3: REASON` in the thesis's upper case (as the app shows it)."""
    message = error.message.upper()
    if error.program and error.step:
        return f"*** {error.program} step {error.step}: {message}"
    if error.program:  # a whole-program error (it cannot start, a missing subroutine)
        return f"*** {error.program}: {message}"
    return f"*** {message}"


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
    if isinstance(event, (Status, Signal)):
        return [event.text]
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
