"""What the simulator core yields as it works: one small dataclass per kind of happening.

The interpreter and the motion code yield these instead of drawing or printing, so the
Textual app, the headless ``valterm run`` and the tests all drive the same code.
``to_json()`` gives the objects of ``valterm run --json``.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Any


@dataclass(frozen=True)
class Event:
    event = "event"

    def to_json(self) -> dict[str, Any]:
        return {"event": self.event, **asdict(self)}


@dataclass(frozen=True)
class Step(Event):
    """A program step about to execute (scrolled on the screen as in 1985)."""

    program: str
    step: int
    text: str
    event = "step"


@dataclass(frozen=True)
class TypeOut(Event):
    """TYPE output and other lines a program prints."""

    text: str
    event = "type"


@dataclass(frozen=True)
class Message(Event):
    """A simulator message: warnings, notices (`IT IS POSSIBLE TO GRASP THIS PART`)."""

    text: str
    level: str = "info"  # info | warning
    event = "message"


@dataclass(frozen=True)
class PoseEvent(Event):
    """One intermediate (or final) pose of a motion: draw the model here."""

    joints: tuple[float, ...]
    index: int
    steps: int
    # announced with every pose, so a player can pace the motion and show where it goes
    seconds: float = 0.0  # the whole motion's real time (core/cycletime.py), as Motion's
    goal: tuple[float, ...] = ()  # the motion's last pose (joints)
    event = "pose"


@dataclass(frozen=True)
class Motion(Event):
    """A finished motion: its kind, its number of steps and the final joints."""

    kind: str  # joint | straight
    steps: int
    joints: tuple[float, ...]
    seconds: float = 0.0  # the real robot's time for it (core/cycletime.py)
    event = "motion"


@dataclass(frozen=True)
class Grasp(Event):
    part: int
    event = "grasp"


@dataclass(frozen=True)
class Release(Event):
    part: int
    position: tuple[float, float, float]
    event = "release"


@dataclass(frozen=True)
class Hand(Event):
    """The clamp opened or closed (redraw the fingers at ``gap`` mm)."""

    closed: bool
    gap: float
    event = "hand"


@dataclass(frozen=True)
class Near(Event):
    """The coarse check: something is inside another's grown box (`CLAMP IS NEAR PART 10`)."""

    a: str
    b: str
    text: str = ""
    event = "near"


@dataclass(frozen=True)
class Collision(Event):
    """The fine check found an edge through a face (`10 COLLIDES WITH 7`)."""

    a: str
    b: str
    text: str = ""
    event = "collision"


@dataclass(frozen=True)
class Error(Event):
    """A run-time error, located by program and step (program "" for a typed command)."""

    program: str
    step: int
    message: str
    event = "error"


@dataclass(frozen=True)
class Where(Event):
    """The WHERE readout (Fig. 2-8)."""

    xyz: tuple[float, float, float]
    oat: tuple[float, float, float]
    joints: tuple[float, ...]
    config: dict[str, str] = field(default_factory=dict)
    clamp: str = "OPENED"
    event = "where"


@dataclass(frozen=True)
class Pause(Event):
    """PAUSE: the program waits for PROCEED."""

    program: str
    step: int
    text: str = ""
    event = "pause"


@dataclass(frozen=True)
class End(Event):
    """The end of a run: the final WHERE and the variables."""

    where: dict[str, Any]
    variables: dict[str, float]
    cycle_time_s: float = 0.0  # the real robot's time for the whole run
    event = "end"


@dataclass(frozen=True)
class Delay(Event):
    """DELAY s: the app waits ``seconds`` in real time; headless runs skip or scale it."""

    seconds: float
    event = "delay"


@dataclass(frozen=True)
class Status(Event):
    """STATUS (section 6.8.4): the speed, the program and its loops done and remaining."""

    speed: float
    program: str
    loops_done: int
    loops_left: int
    event = "status"

    @property
    def text(self) -> str:
        program = self.program or "(NONE)"
        return (f"SPEED {self.speed:g}  PROGRAM {program}  "
                f"LOOPS COMPLETED {self.loops_done}  REMAINING {self.loops_left}")

    def to_json(self) -> dict[str, Any]:
        return {**super().to_json(), "text": self.text}


@dataclass(frozen=True)
class Help(Event):
    """HELP: the HELP MENU (topic "") or one topic of HELPER.DAT, as lines to show."""

    topic: str
    lines: tuple[str, ...]
    event = "help"


@dataclass(frozen=True)
class Monitor(Event):
    """A monitor command the app carries out itself (LISTP, LISTF, LISTL, EDIT, POINT)."""

    command: str
    argument: str = ""
    event = "monitor"
