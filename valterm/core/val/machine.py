"""What a V+ program sees besides its real variables: the controller's state.

The 1985 simulator kept only numbers (CHECK.DAT) and locations. V+ programs also read
and set binary signals (an I/O panel, ``valterm.core.signals``), strings, precision points
(six joint angles), timers, system switches and parameters, and a TOOL transformation.
One ``Machine`` per interpreter holds them; V+ expressions and builders reach it through
the closures they are compiled with.

Time: the machine's clock is the interpreter's one clock of the robot's estimated time
(``CycleClock``). The interpreter adds each event's time as the event passes it (motions,
the hand, DELAY); the machine adds only what passes with no event (a scripted WAIT's poll)
and changes scripted inputs (``run --inputs``) when the clock passes their time.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Generator, Iterator
from dataclasses import dataclass, field

import numpy as np

from valterm.core.cycletime import CycleClock
from valterm.core.events import Event, Signal, TypeOut
from valterm.core.files.vplus import VplusData
from valterm.core.kinematics import Location, rotation_to_oat
from valterm.core.signals import InputChange, SignalPanel
from valterm.core.transform import Transform, inverse
from valterm.core.val.ops import ProgramError
from valterm.core.val.protocol import Simulator

JOINTS = 6
TICK = 0.016  # seconds: one tick of the controller's system clock, its 16 ms major cycle (TPS 62.5)
OUT_OF_REACH = -1.0  # INRANGE of a location no joint values reach (beyond the arm's reach)


class MachineError(ProgramError):
    """A V+ run-time error about the controller's state (an undefined string or point)."""


@dataclass
class Machine:
    """Signals, strings, precision points, timers, switches, parameters and the TOOL."""

    sim: Simulator
    signals: SignalPanel = field(default_factory=SignalPanel)
    strings: dict[str, str] = field(default_factory=dict)
    precision: dict[str, tuple[float, ...]] = field(default_factory=dict)
    timers: dict[int, float] = field(default_factory=dict)
    switches: dict[str, bool] = field(default_factory=dict)
    parameters: dict[str, float] = field(default_factory=dict)  # HAND.TIME is the clock's
    inputs: list[InputChange] = field(default_factory=list)  # scripted, in time order
    tool: Transform | None = None
    clock: CycleClock = field(default_factory=CycleClock)
    reactions: dict[int, str] = field(default_factory=dict)  # REACT: signed signal -> program
    pending: list[tuple[int, str]] = field(default_factory=list)  # reactions triggered, not yet run
    # The app's keyboard sets inputs while a program runs: a WAIT no scripted input can end
    # then waits for the user (in real time, Delay polls) until this says the run is stopping.
    keyboard: bool = False
    stopping: Callable[[], bool] = field(default=lambda: False, repr=False)
    typed: str = ""  # TYPE ..., /S: the line typed so far, its end not yet typed
    # The run's limit of robot time (limits.py): a WAIT goes no further, and says which limit.
    deadline: float = float("inf")
    deadline_said: str = "NO RUN LIMIT"

    @property
    def time(self) -> float:
        return self.clock.seconds

    def load_data(self, data: VplusData, variables: dict[str, float]) -> None:
        """A V+ file's data sections, as the controller's LOAD defines them: its locations
        (a location already defined, e.g. by a .LOC file, is kept), precision points,
        strings and reals."""
        for name, location in data.locations.items():
            self.sim.locations.setdefault(name, location)
        self.precision.update(data.precision)
        self.strings.update(data.strings)
        variables.update(data.reals)

    def observe(self, events: Iterator[Event]) -> Iterator[Event]:
        """Pass events on (the interpreter times them), then apply the inputs now due."""
        yield from events
        yield from self.apply_inputs()

    def timed(self, events: Generator[Event, None, int]) -> Generator[Event, None, int]:
        """An op's events passed on, then the inputs now due; returns what the op returns."""
        next_pc = yield from events
        yield from self.apply_inputs()
        return int(next_pc)

    def wait(self, seconds: float) -> Iterator[Event]:
        """Time passes with nothing moving and no event (a scripted WAIT's poll)."""
        self.clock.seconds += seconds
        yield from self.apply_inputs()

    def parameter(self, name: str) -> float:
        if name == "HAND.TIME":
            return self.clock.hand_time
        try:
            return self.parameters[name]
        except KeyError:
            raise MachineError(f"PARAMETER {name} IS NOT DEFINED") from None

    def set_parameter(self, name: str, value: float) -> None:
        """PARAMETER name = value; HAND.TIME is the time the cycle clock gives the hand."""
        if name == "HAND.TIME":
            self.clock.hand_time = value
        else:
            self.parameters[name] = value

    def apply_inputs(self) -> Iterator[Event]:
        while self.inputs and self.inputs[0].time <= self.time + 1e-9:
            change = self.inputs.pop(0)
            self.signals.set_input(change.signal, change.on)
            self._triggered(change.signal)
            yield Signal(change.signal, change.on, round(self.time, 3))

    def key_input(self, number: int, on: bool) -> Signal:
        """The user sets input ``number`` from the keyboard (SignalError if it is not an input);
        an armed REACT sees it at the program's next motion, WAIT, DELAY or SIGNAL."""
        self.signals.set_input(number, on)
        self._triggered(number)
        return Signal(number, on, round(self.time, 3))

    def waits_for_keyboard(self) -> bool:
        """A WAIT that no scripted input can end waits for the user's keyboard instead."""
        return self.keyboard and not self.stopping()

    def next_input_time(self) -> float | None:
        return self.inputs[0].time if self.inputs else None

    def set_signal(self, signed: int) -> Signal:
        number = self.signals.set_by_program(signed)
        self._triggered(number)
        return Signal(number, signed > 0, round(self.time, 3))

    def react(self, signed: int, program: str) -> None:
        """REACT n, program: when signal n comes on (-n: goes off), CALL the program once."""
        self.signals.sig(signed)  # a signal that does not exist is refused here
        self.reactions = {s: p for s, p in self.reactions.items() if abs(s) != abs(signed)}
        self.reactions[signed] = program

    def ignore(self, signed: int) -> None:
        self.signals.sig(signed)
        self.reactions = {s: p for s, p in self.reactions.items() if abs(s) != abs(signed)}

    def _triggered(self, number: int) -> None:
        for signed, program in list(self.reactions.items()):
            if abs(signed) == number and self.signals.sig(signed):
                del self.reactions[signed]  # a reaction happens once; REACT again to re-arm it
                self.pending.append((signed, program))

    def sig(self, *signed: float) -> float:
        """SIG(a, b, ...): TRUE when all are (SIG(-n): n is off)."""
        return -1.0 if all(self.signals.sig(int(n)) for n in signed) else 0.0

    def timer(self, number: float) -> float:
        """TIMER(n): seconds since TIMER n was set; TIMER(0) the system clock's seconds,
        TIMER(-1) its ticks (TICK each), TIMER(-2) its whole milliseconds."""
        timer = int(number)
        if timer > 0:
            return self.time - self.timers.get(timer, 0.0)
        if timer == 0:
            return self.time
        if timer == -1:
            return float(math.floor(self.time / TICK + 1e-9))
        if timer == -2:
            return float(math.floor(self.time * 1000.0 + 1e-6))
        raise MachineError(f"TIMER({timer}): NOT A TIMER (1 AND UP, OR 0, -1, -2)")

    def set_timer(self, number: float, value: float) -> None:
        """TIMER n = value; timer 0 and the special timers are the system clock's: read only."""
        timer = int(number)
        if timer <= 0:
            raise MachineError(f"TIMER {timer} IS THE SYSTEM CLOCK'S: IT CANNOT BE SET (TIMERS 1 AND UP CAN)")
        self.timers[timer] = self.time - value

    def inrange(self, target: Transform) -> float:
        """INRANGE(l): 0 when the tool can reach l in the configuration a motion would use;
        else bit n (value 2^(n-1)) for each joint n l needs beyond its stop, or OUT_OF_REACH."""
        beyond = self.sim.in_range(self.through_tool(target).location())
        if beyond is None:
            return OUT_OF_REACH
        return float(sum(1 << (joint - 1) for joint in beyond))

    def string(self, name: str) -> str:
        try:
            return self.strings[name]
        except KeyError:
            raise MachineError(f"STRING {name} IS NOT DEFINED") from None

    def location(self, name: str) -> Transform:
        """A named transformation (``#name``: the precision point's tool pose)."""
        if name.startswith("#"):
            return Transform.of(self.point_location(name))
        return Transform.of(self.sim.location(name))

    def point(self, name: str) -> tuple[float, ...]:
        try:
            return self.precision[name]
        except KeyError:
            raise MachineError(f"PRECISION POINT {name} IS NOT DEFINED") from None

    def point_location(self, name: str) -> Location:
        return self.pose_location(self.point(name))

    def pose_location(self, joints: tuple[float, ...]) -> Location:
        """The tool's location at six joint angles (the robot's own frame)."""
        pose = self.sim.arm.fk(list(joints))
        x, y, z = (float(v) for v in pose.xyz)
        return Location((x, y, z), rotation_to_oat(np.asarray(pose.rotation)))

    def through_tool(self, target: Transform) -> Transform:
        """Where the 1985 tool point must go so that the TOOL point reaches ``target``."""
        return target if self.tool is None else target @ inverse(self.tool)


def typed_rest(machine: Machine) -> Generator[Event, None, int]:
    """The line a TYPE ..., /S left open, typed when the run ends (nothing typed is lost)."""
    if machine.typed:
        yield TypeOut(machine.typed)
        machine.typed = ""
    return 0


def signal_line(machine: Machine) -> str:
    """The I/O panel as STATUS types it: the signals that are on."""
    outputs = " ".join(str(n) for n in machine.signals.outputs_on()) or "NONE"
    inputs = " ".join(str(n) for n in machine.signals.inputs_on()) or "NONE"
    return f"SIGNALS ON: OUTPUTS {outputs}  INPUTS {inputs}"
