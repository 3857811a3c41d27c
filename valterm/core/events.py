"""What the simulator core yields as it works: one small dataclass per kind of happening.

The interpreter and the motion code yield these instead of drawing or printing, so the
Textual app, the headless ``valterm run`` and the tests all drive the same code.
``to_json()`` gives the objects of ``valterm run --json``.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, is_dataclass
from functools import lru_cache
from typing import Any, TypeAlias, cast

from valterm.core.numbers import two_decimals

# A value json.dumps writes: what ``to_json()`` gives for ``valterm run --json``.
Json: TypeAlias = "str | int | float | bool | list[Json] | tuple[Json, ...] | dict[str, Json] | None"


@dataclass(frozen=True)
class Event:
    """One happening of the simulator core; ``event`` is its kind in ``run --json``."""

    event = "event"

    def to_json(self) -> dict[str, Json]:
        """``{"event": kind, field: value, ...}``, as ``dataclasses.asdict`` gives the fields
        (nested dataclasses, lists, tuples and dicts as plain values) without its deep copy
        of every value: a ``run --json`` writes one per step (issue 25)."""
        out: dict[str, Json] = {"event": self.event}
        for name in _field_names(type(self)):
            value = getattr(self, name)
            out[name] = value if type(value) in _SCALARS else _plain(value)
        return out

    def json_line(self) -> str:
        """The line ``valterm run --json`` writes for this event: ``json.dumps`` of ``to_json``
        and its newline (as a file's ``readline`` gives a line: one write a line, issue 25)."""
        import json  # with ``run --json``'s first line, not at the app's start (issue 25)

        return json.dumps(self.to_json()) + "\n"


@lru_cache(maxsize=4096)
def _step_line(program: str, step: int, text: str) -> str:
    import json

    return json.dumps({"event": "step", "program": program, "step": step, "text": text}) + "\n"


_SCALARS = frozenset({str, int, float, bool, type(None)})
_FIELDS: dict[type, tuple[str, ...]] = {}


def _field_names(kind: type) -> tuple[str, ...]:
    names = _FIELDS.get(kind)
    if names is None:
        names = _FIELDS[kind] = tuple(f.name for f in fields(kind) if f.init)  # Step.json and .line are none
    return names


def _plain(value: object) -> Json:
    """A field's value as ``asdict`` gives it (a new list, tuple or dict; a dataclass as a dict)."""
    if type(value) in _SCALARS:
        return value  # type: ignore[return-value]
    if is_dataclass(value) and not isinstance(value, type):
        return {name: _plain(getattr(value, name)) for name in _field_names(type(value))}
    if isinstance(value, tuple) and hasattr(value, "_fields"):    # a named tuple, as asdict keeps it
        kind: Any = type(value)
        return cast(Json, kind(*[_plain(v) for v in value]))
    if isinstance(value, (list, tuple)):
        return type(value)(_plain(v) for v in value)
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    return value  # type: ignore[return-value]


@dataclass(frozen=True)
class Step(Event):
    """A program step about to execute (scrolled on the screen as in 1985)."""

    program: str
    step: int
    text: str
    event = "step"
    # its line of ``valterm run --json`` once json_line() has made it ("" before): a loop
    # repeats its steps, and run's loop reads it here, a plain attribute a statement (issue 25;
    # a factory, not a default: a class attribute of that name would keep the read unspecialised)
    json: str = field(default_factory=str, init=False, repr=False, compare=False)
    # its transcript line and newline once core/text/transcript.py has made it ("" before): the
    # same kept line for the text transcript (issue 40), made by the one renderer, not here
    line: str = field(default_factory=str, init=False, repr=False, compare=False)

    def json_line(self) -> str:
        if not self.json:
            object.__setattr__(self, "json", _step_line(self.program, self.step, self.text))
        return self.json


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


@dataclass(frozen=True, kw_only=True)
class Located(Event):
    """Where a program was when something happened to the clamp: the program and step
    (filled in by the interpreter; "" and 0 for a typed command or the pendant) and the
    clamp's position (the tool point, world mm; () when not known)."""

    program: str = ""
    step: int = 0
    clamp: tuple[float, ...] = ()

    @property
    def located(self) -> str:
        """` (PICK STEP 5, CLAMP AT 465.00 -45.00 -245.00)`, or "" when not in a program."""
        if not self.program:
            return ""
        at = " ".join(map(two_decimals, self.clamp))
        return f" ({self.program} STEP {self.step}, CLAMP AT {at})" if at else f" ({self.program} STEP {self.step})"


@dataclass(frozen=True)
class Grasp(Located):
    """The clamp closed on part ``part`` (CLOSE, CLOSEI, GRASP): it is carried from now on."""

    part: int
    event = "grasp"


@dataclass(frozen=True)
class Release(Event):
    """The clamp let part ``part`` go where it is (``position``: its reference point, world mm)."""

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
class Contact(Located):
    """A finding of the collision check about two parties (a link or a part each)."""

    a: str
    b: str
    text: str = ""


@dataclass(frozen=True)
class Near(Contact):
    """The coarse check: something is inside another's grown box (`CLAMP IS NEAR PART 10`)."""

    event = "near"


@dataclass(frozen=True)
class Collision(Contact):
    """The fine check found an edge through a face (`10 COLLIDES WITH 7`)."""

    event = "collision"


@dataclass(frozen=True)
class Error(Event):
    """A run-time error, located by program and step (program "" for a typed command)."""

    program: str
    step: int
    message: str
    event = "error"

    @property
    def where(self) -> str:
        """`PROG STEP 3: `, `PROG: ` for a whole-program error (step 0), "" for a typed command."""
        if not self.program:
            return ""
        return f"{self.program} STEP {self.step}: " if self.step else f"{self.program}: "


@dataclass(frozen=True)
class LimitReached(Error):
    """The run stopped at one of its limits (``valterm.core.val.limits``): ``limit`` is
    steps, seconds or lines, ``flag`` the command-line option that changes it."""

    limit: str = "steps"
    flag: str = ""
    event = "limit"


@dataclass(frozen=True)
class Where(Event):
    """The WHERE readout (Fig. 2-8)."""

    xyz: tuple[float, float, float]
    oat: tuple[float, float, float]
    joints: tuple[float, ...]
    config: dict[str, str] = field(default_factory=dict)
    clamp: str = "OPENED"
    ypr: tuple[float, float, float] | None = None  # V+'s yaw pitch roll: the readout shows these
    event = "where"

    def to_json(self) -> dict[str, Json]:
        data = super().to_json()
        if self.ypr is None:
            del data["ypr"]  # a 1985 readout is as it was
        return data


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

    where: dict[str, Json]
    variables: dict[str, float]
    cycle_time_s: float = 0.0  # the real robot's time for the whole run
    signals_on: tuple[int, ...] = ()  # the I/O panel's signals on at the end (V+)
    # every part of the cell at the end: {"part": n, "position": [x, y, z], "held": bool}
    # (position: the part's reference point, its first vertex, as the setup file gives it)
    parts: tuple[dict[str, Json], ...] = ()
    robot: str = "PUMA 600"  # the robot the run moved (core/arms.py), as in the status event
    robot_key: str = "PUMA"
    event = "end"


@dataclass(frozen=True)
class Delay(Event):
    """DELAY s: the app waits ``seconds`` in real time; headless runs skip or scale it."""

    seconds: float
    event = "delay"


@dataclass(frozen=True)
class Signal(Event):
    """A binary signal of the I/O panel changed (V+ SIGNAL, a scripted or keyed input)."""

    number: int
    on: bool
    time: float = 0.0  # the robot's estimated seconds since the run started
    event = "signal"

    @property
    def text(self) -> str:
        return f"SIGNAL {self.number} {'ON' if self.on else 'OFF'}"


@dataclass(frozen=True)
class Status(Event):
    """STATUS (section 6.8.4): the speed, the program and its loops done and remaining."""

    speed: float
    program: str
    loops_done: int
    loops_left: int
    cycle_time_s: float = 0.0  # the real robot's time since the last EXECUTE (core/cycletime.py)
    rules: str = "1985"  # the joint-state rules in force (core/rules.py, SPEC §3a)
    robot: str = "PUMA 600"  # the robot moved, as its file names it (core/arms.py)
    robot_key: str = "PUMA"  # as --robot names it: PUMA, the thesis's own model, or a robot file's
    event = "status"

    @property
    def robot_text(self) -> str:
        """Which robot the verdicts are for, when it is not the thesis's ("" when it is)."""
        if self.robot_key == "PUMA":
            return ""
        return f"ROBOT {self.robot} (--ROBOT {self.robot_key}: ITS OWN DH MODEL, NOT THE THESIS'S)"

    @property
    def rules_text(self) -> str:
        """Which rules the verdicts follow: the thesis's or the real controller's."""
        if self.rules == "controller":
            return "RULES CONTROLLER (A REAL PUMA: JOINTS WIND, THE ARM KEEPS ITS CONFIGURATION)"
        return "RULES 1985 (THE THESIS: ANGLES A FUNCTION OF THE POSE, INDICATORS CHECKED)"

    @property
    def text(self) -> str:
        program = self.program or "(NONE)"
        return (f"SPEED {self.speed:g}  PROGRAM {program}  "
                f"LOOPS COMPLETED {self.loops_done}  REMAINING {self.loops_left}")

    @property
    def cycle_text(self) -> str:
        """The last EXECUTE's robot time: so far while it runs (loops remain), else in all."""
        so_far = " SO FAR" if self.loops_left else ""
        return f"CYCLE TIME {self.cycle_time_s:.2f} S{so_far} (ESTIMATE FOR THE REAL PUMA)"

    def to_json(self) -> dict[str, Json]:
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


@dataclass(frozen=True)
class Breakpoint(Pause):
    """The debugger paused a program before step ``step``: a breakpoint (BPT) or the end of a
    single step (XSTEP, SSTEP).  A ``Pause``: the app stops pulling; PROCEED goes on."""

    reason: str = "BPT"  # BPT | XSTEP | SSTEP
    event = "breakpoint"


@dataclass(frozen=True)
class Watch(Event):
    """WATCH: a watched variable changed (``old`` None: it was not declared) at a step
    (program "" and step 0: typed while the program was paused)."""

    variable: str
    old: float | None
    new: float | None
    program: str
    step: int
    event = "watch"


@dataclass(frozen=True)
class Trace(Event):
    """TRACE ON: a step that was executed, with the variables it assigned and their values."""

    program: str
    step: int
    text: str
    assigned: tuple[tuple[str, float], ...] = ()
    event = "trace"
