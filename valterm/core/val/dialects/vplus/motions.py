"""V+ motions and the hand: locations or precision points as targets, MOVET's hand.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from valterm.core.events import Delay
from valterm.core.kinematics import Location
from valterm.core.val.builders import Build, Builder
from valterm.core.val.dialects.val1985 import builders as b85
from valterm.core.val.dialects.vplus.compiled import (
    controller_of,
    location_of,
    number_of,
    precision_of,
    reacting,
)
from valterm.core.val.dialects.vplus.expr import (
    compile_number,
)
from valterm.core.val.dialects.vplus.statements import HAND
from valterm.core.val.ops import (
    Action,
    Events,
    Op,
    ProgramError,
)
from valterm.core.val.parser import (
    Statement,
)

# -- motions, the hand, settings -----------------------------------------------------------

@dataclass(frozen=True)
class Joints:
    """A precision point's six joint angles as a motion's target."""

    angles: tuple[float, ...]


def _target(c: Build, text: str) -> Callable[[], Location | Joints]:
    """A motion's target: a precision point's joints, or the location the 1985 tool must reach."""
    machine = controller_of(c)
    if text.startswith("#"):
        joints = precision_of(c, text)
        if joints is not None:
            return lambda: Joints(joints(c.variables))
    where = location_of(c, text)
    return lambda: machine.through_tool(where(c.variables)).location()


def _go(c: Build, target: Location | Joints, straight: bool) -> Events:
    machine = controller_of(c)
    if isinstance(target, Joints):
        if straight:
            yield from machine.observe(c.sim.move(_point(c, target), straight=True))
        else:
            yield from machine.observe(c.sim.move_joints(target.angles))
    else:
        yield from machine.observe(c.sim.move(target, straight=straight))
    return 0


def _point(c: Build, joints: Joints) -> Location:
    """Where the tool is at a precision point (for straight motions and APPRO)."""
    return controller_of(c).pose_location(joints.angles)


def _move(c: Build, st: Statement) -> Op:
    straight = st.command in ("MOVES", "MOVEST")
    target = _target(c, st.args[0])
    hand = number_of(c, st.args[1]) if st.args[1] else None
    machine = controller_of(c)

    def run() -> Events:
        yield from _go(c, target(), straight)
        if hand is not None:
            action = c.sim.open if hand(c.variables) else c.sim.close
            yield from machine.observe(action(immediate=False))
        return c.next
    return reacting(c, run)


def _appro(c: Build, st: Statement) -> Op:
    straight = st.command == "APPROS"
    target = _target(c, st.args[0])
    distance = number_of(c, st.args[1])
    machine = controller_of(c)

    def run() -> Events:
        goal = target()
        where = _point(c, goal) if isinstance(goal, Joints) else goal
        yield from machine.observe(c.sim.appro(where, float(distance(c.variables)), straight=straight))
        return c.next
    return reacting(c, run)


def _depart(c: Build, st: Statement) -> Op:
    distance = number_of(c, st.args[0])
    machine = controller_of(c)

    def run() -> Events:
        yield from machine.observe(c.sim.depart(float(distance(c.variables)), straight=st.command == "DEPARTS"))
        return c.next
    return reacting(c, run)


def _hand(c: Build, st: Statement) -> Op:
    machine = controller_of(c)
    closing = st.command.startswith(("CLOSE", "RELAX")) and not st.command.startswith("RELAX")
    action = c.sim.close if closing else c.sim.open
    immediate = st.command.endswith("I")

    def run() -> Events:
        yield from machine.observe(action(immediate=immediate))
        return c.next
    return reacting(c, run)


def _delay(c: Build, st: Statement) -> Op:
    seconds = number_of(c, st.args[0])
    machine = controller_of(c)

    def run() -> Events:
        value = float(seconds(c.variables))
        if value > 0:
            yield from machine.observe(iter([Delay(value)]))
        return c.next
    return reacting(c, run)


def _select(c: Build, st: Statement) -> Op:
    """SELECT ROBOT = n: the simulator has one robot, robot 1."""
    robot = number_of(c, st.args[0])

    def run() -> Events:
        number = float(robot(c.variables))
        if number != 1:
            raise ProgramError(f"SELECT ROBOT = {number:g}: THE SIMULATOR HAS ONE ROBOT, ROBOT 1")
        return c.next
        yield
    return c.action(run)


def _with_numbers(c: Build, st: Statement) -> Op:
    """DRIVE, DRAW, BASE: the 1985 builders on the V+ values."""
    machine = controller_of(c)
    values = tuple(None if t is None else compile_number(t, machine) for t in st.args)
    built = b85.BUILDERS[st.command](c, Statement(st.command, values, st.text))
    assert isinstance(built, Action)
    inner = built.run

    def run() -> Events:
        return (yield from machine.timed(inner()))
    return reacting(c, run)


MOTIONS: dict[str, Builder] = {
    "MOVE": _move, "MOVES": _move, "MOVET": _move, "MOVEST": _move, "APPRO": _appro, "APPROS": _appro,
    "DEPART": _depart, "DEPARTS": _depart, **{word: _hand for word in HAND}, "DELAY": _delay,
    "DRIVE": _with_numbers, "DRAW": _with_numbers, "BASE": _with_numbers, "SELECT": _select,
}
