"""The simulated robot and its cell: state plus actions that yield events.

Every action that moves anything is a generator of ``valterm.core.events`` objects (each pose of
a motion, each grasp, release and collision message). A refused motion raises
``MotionRefused`` before yielding any pose, so nothing moves. The interpreter, the app and
the tests all drive this one class.

Frames: locations, WHERE and the cell are world coordinates (WCS). ``BASE`` moves the
robot's base frame relative to the cell; the kinematics work in the robot's own frame.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Generator, Iterable, Iterator, Sequence
from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np

from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.cell.workcell import WorkCell
from valterm.core.cycletime import joint_motion_seconds, robot_timing, straight_motion_seconds
from valterm.core.errors import ValtermError
from valterm.core.events import Collision, Event, Grasp, Hand, Message, Motion, Near, PoseEvent, Release, Where
from valterm.core.kinematics import Config, IKError, Location, indicator_kind, rotation_to_oat, shown_angle
from valterm.core.motion import (
    OUT_OF_REACH_REASON,
    PENDANT_INCREMENT,
    PENDANT_STEP,
    MotionRefused,
    approach_point,
    check_joint_goal,
    clamp_speed,
    fit_precision_point,
    joint_goal,
    joint_increment,
    joint_path,
    pendant_straight,
    straight_increment,
    straight_path,
)
from valterm.core.robot import THESIS_ROBOT, RobotModel, load_model, load_robot_model
from valterm.core.rules import CONTROLLER, RULES_1985, check_rules

if TYPE_CHECKING:  # the collision checks load with the first check, not at every start (issue 25)
    from valterm.core.collision.frames import RobotScene
    from valterm.core.collision.glance import Items, Spans
    from valterm.core.collision.moments import PathFigures
    from valterm.core.collision.world import Finding

GRASP_MESSAGE = "IT IS POSSIBLE TO GRASP THIS PART"
# how close a taught location's joint angles must put the tool to its pose to be its goal:
# 0.01 mm and about 0.03 degrees (a .LOC file's 2 decimals, with room for the sum of three)
TAUGHT_MM = 0.01
TAUGHT_ROTATION = 5e-4


@lru_cache(maxsize=1)
def default_model() -> RobotModel:
    return load_model()


@lru_cache(maxsize=4)
def robot_model(name: str | None = None) -> RobotModel:
    """The drawn robot --robot names (RobotFileError for none), read once per name."""
    if name is None or name.strip().upper() == THESIS_ROBOT:
        return default_model()
    return load_robot_model(name.strip().upper())


def _rounded(values: Iterable[float]) -> tuple[float, float, float]:
    """Three coordinates rounded to 6 places, as the events carry them."""
    x, y, z = (round(float(v), 6) for v in values)
    return x, y, z


def _changes(before: Config, after: Config) -> str:
    """``LEFTY TO RIGHTY, ABOVE TO BELOW``: the indicators that differ."""
    return ", ".join(f"{a} TO {b}" for a, b in zip(before.words, after.words) if a != b)


def _words_to_type(have: Config, want: Config) -> str:
    """The configuration commands that turn ``have`` into ``want`` (``LEFTY`` or ``LEFTY, BELOW``)."""
    return ", ".join(b for a, b in zip(have.words, want.words) if a != b)


def _goal_name(target: str | Location) -> str:
    """How a refusal names a motion's goal: ``location A``."""
    return f"location {target.upper()}" if isinstance(target, str) else "the location"


class ConfigMismatch(MotionRefused):
    """1985 rules (§6.2.1): a location taught in a configuration other than the user's
    indicators; the message says so and names both, and the words that would take it."""

    def __init__(self, name: str | None, taught: Config, indicators: Config) -> None:
        self.name, self.taught, self.indicators = name, taught, indicators
        what, again = (name, name) if name else ("the location", "it")
        super().__init__(f"configuration mismatch: {what} was taught {' '.join(taught.words)}, the indicators "
                         f"are {' '.join(indicators.words)} (type {_words_to_type(indicators, taught)}, "
                         f"or teach {again} again)")


class UndefinedLocation(ValtermError, KeyError):
    def __init__(self, name: str) -> None:
        super().__init__(name)
        self.name = name

    def __str__(self) -> str:
        return f"location {self.name} is not defined"


class Simulator:
    """The robot, its clamp and the work cell, with the VAL-II state that goes with them."""

    def __init__(self, cell: WorkCell | None = None, model: RobotModel | None = None,
                 robot: str | None = None) -> None:
        self.model = model or robot_model(robot)
        self.geometry = self.model.geometry
        # the robot chosen once (--robot): everything kinematic goes through it (core/arms.py)
        self.arm = self.model.arm
        # the cycle-time figures of the robot's own file (core/cycletime.py)
        self.timing = robot_timing(None if self.arm.key == THESIS_ROBOT else self.arm.key)
        self.cell = cell if cell is not None else WorkCell()
        # the joint state: written here alone, through the rules (``_settled``, ``stand_at``);
        # everyone else reads the ``joints`` tuple
        self._joints: tuple[float, ...] = tuple(float(v) for v in self.arm.ready)
        self.config = Config(1, 1, 1)  # the user's indicators: RIGHTY ABOVE NOFLIP
        # the joint-state rules (SPEC §3a, core/rules.py): the thesis's or the real controller's
        self.rules = RULES_1985
        # controller rules: the indicators asked for since the last motion (kind -> +1/-1)
        self._asked: dict[str, int] = {}
        self.speed = 100.0
        self.tool_mm_per_s: float | None = None  # V+ SPEED n MMPS: straight lines' tool speed
        self._speed_after: tuple[float, float | None] | None = None  # SPEED without ALWAYS: then this
        self.clamp_closed = False
        self.gap = self.model.open_gap
        self.carried: int | None = None
        self._carried_local: np.ndarray | None = None
        self.locations: dict[str, Location] = {}
        # the locations as last read from or written to a .LOC file (what STOREL clears)
        self.stored_locations: dict[str, Location] = {}
        # the robot's own frame in the cell: its mount (the thesis's robot: the cell's frame)
        self.base = self.arm.mount.copy()
        # the base as built when it is the cell's frame: link frames skip the product (_frames_at)
        self._home_base = self.base if np.array_equal(self.base, np.eye(4)) else np.eye(4)
        self.base_offsets = (0.0, 0.0, 0.0, 0.0)
        self.collision_checks = False
        self.stop_on_collision = False
        self.autoconfig = False  # AUTOCONFIG ON: try the other configurations (§8.1)
        self.pendant_increment = PENDANT_INCREMENT  # signed: N flips it
        self._findings: set[Finding] = set()     # the last step's (a finding is said as it starts)
        self._findings_list: tuple[list[Finding], set[Finding]] | None = None   # the list ``_findings`` was made of
        self._checker: RobotScene | None = None
        self._checker_gap: float | None = None

    @property
    def joints(self) -> tuple[float, ...]:
        """The joint angles now, degrees (read-only: motions, ``stand_at`` and the rules set them)."""
        return self._joints

    def stand_at(self, joints: Sequence[float]) -> None:
        """The arm at ``joints`` without a motion (a picture, a bench, a test's start): the stops
        checked and the angles settled by the rules in force; a carried part follows."""
        goal = [float(v) for v in joints]
        if self.rules == CONTROLLER:
            check_joint_goal(goal, self.arm)
        else:  # 1985: an angle typed as the figures show it (JT2 172.08) is its equivalent inside
            goal = fit_precision_point(goal, self.joints, self.arm)
        self._joints = tuple(self._settled(goal))
        self._follow_clamp()

    # -- readouts ------------------------------------------------------------
    def robot_polyhedra(self) -> list[Polyhedron]:
        return self.model.place(self.joints, self.gap, self.base)

    def tool_pose(self, point: int = 1, joints: Sequence[float] | None = None) -> tuple[np.ndarray, np.ndarray]:
        """World position of option 1/2/3 and the tool rotation (at ``joints``, else where the arm is)."""
        pose = self.arm.fk(self.joints if joints is None else joints, point)
        return self.base[:3, :3] @ pose.xyz + self.base[:3, 3], self.base[:3, :3] @ pose.rotation

    def where(self, point: int = 1) -> Where:
        xyz, rotation = self.tool_pose(point)
        return Where(
            xyz=_rounded(xyz),
            oat=_rounded(rotation_to_oat(rotation)),
            joints=tuple(round(j, 6) for j in self.shown_joints()),
            config=self.arm.indicators(self.joints).as_dict(),
            clamp="CLOSED" if self.clamp_closed else "OPENED",
        )

    def shown_joints(self) -> list[float]:
        """The joints as WHERE shows them (SPEC §3a): under the 1985 rules in (-180, 180] as
        the thesis's figures are (the angle held may be its equivalent inside the stops:
        JT2 -187.92 is shown 172.08); under the controller's, the angles the joints hold."""
        if self.rules == CONTROLLER:
            return list(self.joints)
        return [shown_angle(j) for j in self.joints]

    def here_location(self) -> Location:
        """Where the tool is, with the arm's configuration and joint angles (what HERE keeps)."""
        xyz, rotation = self.tool_pose()
        x, y, z = (float(v) for v in xyz)
        return Location((x, y, z), rotation_to_oat(rotation), self.arm.indicators(self.joints),
                        tuple(self.joints))

    def unsaved_locations(self) -> list[str]:
        """Names of the locations defined or changed since the last .LOC read or STOREL."""
        return sorted(name for name, location in self.locations.items()
                      if self.stored_locations.get(name) != location)

    def mark_locations_stored(self, names: Iterable[str] | None = None) -> None:
        """The locations (all, or those named) are now as a .LOC file holds them."""
        for name in self.locations if names is None else names:
            if name in self.locations:
                self.stored_locations[name] = self.locations[name]

    # -- settings ------------------------------------------------------------
    def set_speed(self, percent: float) -> float:
        self.speed = clamp_speed(percent)
        self.tool_mm_per_s = None
        return self.speed

    def _straight_percent(self) -> float:
        """The SPEED a straight line's steps are drawn at: SPEED n MMPS as a share of the robot's."""
        if self.tool_mm_per_s is None:
            return self.speed
        return clamp_speed(100.0 * self.tool_mm_per_s / self.timing.tool_speed)

    def set_program_speed(self, value: float, mm_per_s: bool, always: bool) -> float:
        """V+ SPEED: ``value`` percent, or (``mm_per_s``) the tool tip's speed on straight lines,
        held at the robot's; without ALWAYS for the next motion only. Returns what is in force."""
        if always:
            self._speed_after = None
        elif self._speed_after is None:
            self._speed_after = (self.speed, self.tool_mm_per_s)
        if not mm_per_s:
            return self.set_speed(value)
        self.tool_mm_per_s = min(max(value, 1e-3), self.timing.tool_speed)
        return self.tool_mm_per_s

    def set_rules(self, name: str) -> str:
        """The joint-state rules: ``1985`` or ``controller`` (RefusedValue otherwise)."""
        self.rules = check_rules(name)
        self._asked.clear()
        if self.rules == RULES_1985:
            self._joints = tuple(self._settled(self._joints))
        return self.rules

    def set_indicator(self, word: str) -> None:
        """LEFTY, RIGHTY, ABOVE, BELOW, FLIP or NOFLIP (any unique prefix)."""
        arm, elbow, wrist = self.config
        parsed = Config.parse(word)
        kind = indicator_kind(word)
        self.config = Config(
            parsed.arm if kind == "arm" else arm,
            parsed.elbow if kind == "elbow" else elbow,
            parsed.wrist if kind == "wrist" else wrist,
        )
        self._asked[kind] = getattr(parsed, kind)

    def set_base(self, dx: float | None = None, dy: float | None = None, dz: float | None = None,
                 rz: float | None = None) -> Iterator[Event]:
        """BASE dx,dy,dz,rz: the robot's base frame relative to the cell (omitted = 0)."""
        x, y, z, turn = (0.0 if v is None else float(v) for v in (dx, dy, dz, rz))
        self.base_offsets = (x, y, z, turn)
        c, s = math.cos(math.radians(turn)), math.sin(math.radians(turn))
        base = np.eye(4)
        base[:3, :3] = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
        base[:3, 3] = (x, y, z)
        self.base = base @ self.arm.mount
        yield PoseEvent(tuple(self.joints), 1, 1)

    # -- locations -----------------------------------------------------------
    def location(self, name: str) -> Location:
        try:
            return self.locations[name.upper()]
        except KeyError:
            raise UndefinedLocation(name.upper()) from None

    def here(self, name: str) -> Location:
        location = self.here_location()
        self.locations[name.upper()] = location
        return location

    def set_location(self, name: str, source: str) -> Location:
        location = self.location(source)  # its configuration and joints go with it (§6.1.4)
        self.locations[name.upper()] = location
        return location

    def shift(self, name: str, dx: float, dy: float, dz: float) -> Location:
        shifted = self.location(name).shifted(dx, dy, dz)
        self.locations[name.upper()] = shifted
        return shifted

    def _resolve(self, target: str | Location) -> tuple[np.ndarray, np.ndarray, Location]:
        """A location in the robot's own frame (undoing BASE), and the location itself."""
        location = self.location(target) if isinstance(target, str) else target
        inv = self.base[:3, :3].T
        xyz = inv @ (np.asarray(location.xyz, dtype=float) - self.base[:3, 3])
        return xyz, inv @ location.rotation, location

    def in_range(self, location: Location) -> tuple[int, ...] | None:
        """V+ INRANGE: the joints a motion to ``location`` would need beyond their stops (in
        the configuration the motion would use; a joint may turn by a whole 360), or None
        when no joint values reach it."""
        xyz, rotation, _ = self._resolve(location)
        config = (self._asked_over(location.config or self.arm.indicators(self.joints))
                  if self.rules == CONTROLLER else self.config)
        try:
            angles = self.arm.ik(xyz, rotation, config, self.joints, enforce_stops=False)
        except IKError:
            return None
        return tuple(joint for joint, (angle, (low, high)) in enumerate(zip(angles, self.arm.stops), start=1)
                     if not any(low - 1e-9 <= angle + turn <= high + 1e-9 for turn in (-360.0, 0.0, 360.0)))

    # -- motions ---------------------------------------------------------------
    def move(self, target: str | Location, straight: bool = False, *, name: str | None = None) -> Iterator[Event]:
        """MOVE / MOVES; ``name`` names a location given by value (D_DEFINE reading a file)."""
        xyz, rotation, location = self._resolve(target)
        config = yield from self._config_for(name or target, location)
        taught = None if straight else self._taught_goal(location, config, xyz, rotation)
        yield from self._go(xyz, rotation, straight, config, _goal_name(target), taught)

    def _taught_goal(self, location: Location, config: Config, xyz: np.ndarray,
                     rotation: np.ndarray) -> list[float] | None:
        """1985 rules: the joint angles HERE kept with a location (§6.1.1) are its goal when
        they still make its pose: a .LOC file's 2 decimals move the pose by 0.005, and near a
        singular wrist solving that pose again could turn JT4 and JT6 far apart."""
        if self.rules == CONTROLLER or location.joints is None or location.config != config:
            return None
        try:
            joints = self.arm.canonical_joints(location.joints)
        except ValtermError:
            return None
        pose = self.arm.fk(joints, 1)
        if (np.abs(pose.xyz - xyz).max() > TAUGHT_MM
                or np.abs(pose.rotation - rotation).max() > TAUGHT_ROTATION):
            return None
        return joints

    def appro(self, target: str | Location, distance: float, straight: bool = False) -> Iterator[Event]:
        xyz, rotation, location = self._resolve(target)
        config = yield from self._config_for(target, location)
        yield from self._go(approach_point(xyz, rotation, distance), rotation, straight, config,
                            f"the approach to {_goal_name(target)}")

    def depart(self, distance: float, straight: bool = False) -> Iterator[Event]:
        here = self.arm.fk(self.joints, 1)
        yield from self._go(approach_point(here.xyz, here.rotation, distance), here.rotation, straight,
                            self._config_for_here())

    def draw(self, dx: float, dy: float, dz: float) -> Iterator[Event]:
        here = self.arm.fk(self.joints, 1)
        offset = self.base[:3, :3].T @ np.array([dx, dy, dz], dtype=float)
        yield from self._go(here.xyz + offset, here.rotation, True, self._config_for_here())

    def drive(self, joint: int, degrees: float, speed: float = 100.0) -> Iterator[Event]:
        if not 1 <= joint <= 6:
            raise MotionRefused(f"there is no joint {joint}", 0)
        goal = list(self.joints)
        goal[joint - 1] += degrees
        check_joint_goal(goal, self.arm)
        increment = joint_increment(self.speed * clamp_speed(speed) / 100.0)
        yield from self._play(joint_path(self.joints, goal, increment), "joint")

    def move_joints(self, goal: Sequence[float]) -> Iterator[Event]:
        """A joint-coordinated motion to six joint angles (a V+ precision point, #name).

        Controller rules: a precision point is its joints (SPEC §3a), each angle exactly as given,
        refused naming the joint when one is beyond its stop. 1985 rules: each joint to its
        equivalent inside the stops nearest where it is."""
        if self.rules == CONTROLLER:
            fitted = [float(v) for v in goal]
            check_joint_goal(fitted, self.arm)
        else:
            fitted = fit_precision_point(goal, self.joints, self.arm)
        yield from self._play(joint_path(self.joints, fitted, joint_increment(self.speed)), "joint")

    def ready(self) -> Iterator[Event]:
        """READY: the arm straight up; the user's indicators become RIGHTY ABOVE NOFLIP (§6.2.6),
        and a change of them is said."""
        if self.config != Config(1, 1, 1):
            changes = _changes(self.config, Config(1, 1, 1))
            yield Message(f"READY: CONFIGURATION INDICATORS {changes}", "warning")
        self.config = Config(1, 1, 1)
        self._asked.clear()
        yield from self._play(joint_path(self.joints, self.arm.ready, joint_increment(self.speed)), "joint")

    # -- configurations (SPEC §3a) -------------------------------------------------
    def _config_for(self, target: str | Location, location: Location) -> Generator[Event, None, Config]:
        """The configuration a motion to ``location`` is solved in.

        1985 rules: the user's indicators; a location that keeps a configuration other than
        theirs is refused naming both (§6.2.1), or with AUTOCONFIG ON taken and announced.
        Controller rules: what was asked since the last motion, else the location's own
        configuration, else the arm's present one (a real PUMA keeps its configuration).
        """
        stored = location.config
        if self.rules == CONTROLLER:
            return self._asked_over(stored or self.arm.indicators(self.joints))
        if stored is None or stored == self.config:
            return self.config
        name = target.upper() if isinstance(target, str) else None
        if not self.autoconfig:
            raise ConfigMismatch(name, stored, self.config)
        self.config = stored
        yield Message(f"AUTOCONFIG: USING {stored} (THE CONFIGURATION OF {name or 'THE LOCATION'})", "warning")
        return stored

    def _config_for_here(self) -> Config:
        """DEPART, DRAW, ALIGN: the user's indicators (1985), the arm's own (controller)."""
        if self.rules == CONTROLLER:
            return self._asked_over(self.arm.indicators(self.joints))
        return self.config

    def _asked_over(self, config: Config) -> Config:
        arm, elbow, wrist = config
        asked = self._asked
        return Config(asked.get("arm", arm), asked.get("elbow", elbow), asked.get("wrist", wrist))

    def _settled(self, joints: Sequence[float]) -> list[float]:
        """The joint state after a pose: the 1985 rules' angles, or the controller's wound ones."""
        values = [float(v) for v in joints]
        if self.rules == CONTROLLER:
            return values
        return self.arm.canonical_joints(values)

    def align(self) -> Iterator[Event]:
        """Turn the tool so its Z axis lies along the nearest world axis (joint-coordinated)."""
        here = self.arm.fk(self.joints, 1)
        a = here.rotation[:, 2]
        axis = np.zeros(3)
        i = int(np.argmax(np.abs(a)))
        axis[i] = math.copysign(1.0, a[i])
        o = here.rotation[:, 1] - np.dot(here.rotation[:, 1], axis) * axis
        if np.linalg.norm(o) < 1e-9:
            o = np.roll(axis, 1)
        o /= np.linalg.norm(o)
        rotation = np.column_stack([np.cross(o, axis), o, axis])
        yield from self._go(here.xyz, rotation, False, self._config_for_here())

    def _go(self, xyz: np.ndarray, rotation: np.ndarray, straight: bool, config: Config,
            goal: str = "the goal", taught: list[float] | None = None) -> Iterator[Event]:
        try:
            if straight:
                path = straight_path(self.joints, xyz, rotation, config, straight_increment(self._straight_percent()),
                                     self.arm, self.rules)
            else:
                joints = taught if taught is not None else (yield from self._joint_goal(xyz, rotation, config))
                path = joint_path(self.joints, joints, joint_increment(self.speed))
        except MotionRefused as refused:
            raise self._on_this_robot(refused, goal) from None
        yield from self._play(path, "straight" if straight else "joint")

    def _on_this_robot(self, refused: MotionRefused, goal: str) -> MotionRefused:
        """A refusal on a robot file's robot names the robot and the goal: its reach and stops
        are not the thesis's (the thesis's robot keeps its 1985 wording)."""
        if self.arm.key == THESIS_ROBOT:
            return refused
        robot = self.arm.name
        if refused.reason == OUT_OF_REACH_REASON:
            reason = f"{goal} is out of reach of the {robot}"
        elif refused.joint and "beyond its stop" in refused.reason:
            reason = f"{goal} is beyond the {robot}'s stops: {refused.reason}"
        else:
            reason = f"{goal} on the {robot}: {refused.reason}"
        return MotionRefused(reason, refused.joint, refused.step)

    def _joint_goal(self, xyz: np.ndarray, rotation: np.ndarray, config: Config) -> Generator[Event, None, list[float]]:
        """The goal in the user's configuration; with AUTOCONFIG ON, else the nearest other one.

        Automatic configuration change is the thesis's future work (§8.1): the configuration
        used becomes the user's, and is announced.
        """
        try:
            return joint_goal(xyz, rotation, config, self.joints, self.arm)
        except MotionRefused:
            if not self.autoconfig:
                raise
            found = self._other_configurations(xyz, rotation, config)
            if not found:
                raise
        _distance, other, goal = min(found, key=lambda option: option[0])
        self.config = other
        yield Message(f"AUTOCONFIG: USING {other}", "warning")
        return goal

    def _other_configurations(self, xyz: np.ndarray, rotation: np.ndarray,
                              tried: Config) -> list[tuple[float, Config, list[float]]]:
        found = []
        for arm, elbow, wrist in itertools.product((1, -1), repeat=3):
            config = Config(arm, elbow, wrist)
            if config == tried:
                continue
            try:
                goal = joint_goal(xyz, rotation, config, self.joints, self.arm)
            except MotionRefused:
                continue
            found.append((float(np.abs(np.subtract(goal, self.joints)).max()), config, goal))
        return found

    def _play(self, path: np.ndarray, kind: str) -> Iterator[Event]:
        """Show every pose of a computed path; the path was checked before the first pose.

        The joint state after each pose follows the rules (``_settled``); a motion that leaves
        the arm in another configuration says so (never a silent flip). With collision checks
        on, the path's poses and steps are checked together at the first pose checked
        (``_PathChecks``) and each pose's findings said as it is shown."""
        steps = len(path)
        seconds = self._motion_seconds(path, kind)
        if self._speed_after is not None:  # a V+ SPEED without ALWAYS was for this motion only
            (self.speed, self.tool_mm_per_s), self._speed_after = self._speed_after, None
        before = self.arm.indicators(self.joints)
        goal = tuple(self._settled(path[-1])) if steps else ()
        self._asked.clear()
        checks: _PathChecks | None = None
        try:
            for index, pose in enumerate(path, start=1):
                previous = self.joints
                self._joints = tuple(self._settled(pose) if checks is None else checks.settled(index, pose))
                self._follow_clamp()
                yield PoseEvent(tuple(self.joints), index, steps, round(seconds, 6), goal)
                if not self.collision_checks:
                    if checks is not None:
                        checks.dropped()          # a pause in the checks: pose by pose after it
                    continue
                if checks is None:
                    checks = _PathChecks(self, previous, path[index:], index)
                found = checks.findings(previous)
                if not found and not self._findings:
                    continue                      # nothing now nor at the pose before (most poses)
                for finding in self._said(found):
                    yield finding
                    if self.stop_on_collision and isinstance(finding, Collision):
                        # the robot stops where the collision was found (off by default, as in 1985)
                        raise MotionRefused(f"stopped on collision: {finding.text}", 0, index)
        finally:
            if checks is not None:
                checks.dropped()
        after = self.arm.indicators(self.joints)
        if after != before:
            yield Message(f"ARM CONFIGURATION CHANGED: {_changes(before, after)}", "warning")
        yield Motion(kind, steps, tuple(round(j, 6) for j in self.joints), round(seconds, 6))

    def _motion_seconds(self, path: np.ndarray, kind: str) -> float:
        """The real robot's time for this path (the cycle-time estimate)."""
        if not len(path):
            return 0.0
        start = np.asarray(self.joints, dtype=float)
        if kind != "straight":
            return joint_motion_seconds(start, path[-1], self.speed, self.timing)
        before, after = self.arm.fk(list(start), 1), self.arm.fk(list(path[-1]), 1)
        length = float(np.linalg.norm(after.xyz - before.xyz))
        cos = (np.trace(before.rotation.T @ after.rotation) - 1.0) / 2.0
        turn = math.degrees(math.acos(max(-1.0, min(1.0, float(cos)))))
        return straight_motion_seconds(length, turn, self.speed, self.timing, self.tool_mm_per_s)

    # -- pendant (Chapter 3) ---------------------------------------------------
    def pendant_joint(self, joint: int) -> Iterator[Event]:
        goal = list(self.joints)
        goal[joint - 1] += self.pendant_increment
        check_joint_goal(goal, self.arm)
        yield from self._play(np.array([goal]), "joint")

    def pendant_world(self, axis: int) -> Iterator[Event]:
        step = PENDANT_STEP * self.pendant_increment / PENDANT_INCREMENT
        displacement = self.base[:3, :3].T @ np.eye(3)[axis] * step
        path = pendant_straight(self.joints, displacement, self.pendant_increment, self.arm, self.rules)
        yield from self._play(path, "straight")

    def pendant_tool(self, axis: int) -> Iterator[Event]:
        step = PENDANT_STEP * self.pendant_increment / PENDANT_INCREMENT
        displacement = self.arm.fk(self.joints, 1).rotation[:, axis] * step
        path = pendant_straight(self.joints, displacement, self.pendant_increment, self.arm, self.rules)
        yield from self._play(path, "straight")

    def change_pendant_increment(self, key: str) -> float:
        """N flips the sign of the pendant increment. Under the controller rules I doubles and D
        halves it; under the 1985 rules I adds the default 8 degrees and D takes 8 off (halving
        below 16): the steps that reproduce Fig. C-12 a-d (docs/MOTION.md)."""
        size, sign = abs(self.pendant_increment), math.copysign(1.0, self.pendant_increment)
        stepped = self.rules == RULES_1985
        if key == "I":
            size = size + PENDANT_INCREMENT if stepped else size * 2.0
        elif key == "D":
            size = size - PENDANT_INCREMENT if stepped and size >= 2 * PENDANT_INCREMENT else size / 2.0
        elif key == "N":
            sign = -sign
        self.pendant_increment = sign * size
        return self.pendant_increment

    # -- the hand (§6.3, §2.5) --------------------------------------------------
    def led_part(self) -> int | None:
        """The lowest-numbered part the LED sensor segment intersects (not the carried one)."""
        from valterm.core.collision.grasp import led_hits

        p0, p1 = self.model.led_segment(self.joints, self.gap, self.base)
        numbers = [n for n in range(1, len(self.cell.objects) + 1) if n != self.carried]
        hit = led_hits(p0, p1, [self.cell.objects[n - 1] for n in numbers])
        return None if hit is None else numbers[hit - 1]

    def grasp_possible(self) -> bool:
        return not self.clamp_closed and self.led_part() is not None

    def close(self, immediate: bool = False) -> Iterator[Event]:
        """CLOSE/CLOSEI: latch the lowest-numbered part across the LED; nothing when already closed."""
        if self.clamp_closed:
            return
        part = self.led_part()
        self.clamp_closed = True
        self.gap = self.model.closed_gap
        if part is not None:
            frame = self.model.clamp_frame(self.joints, self.base)
            local = (self.cell.objects[part - 1].vertices - frame[:3, 3]) @ frame[:3, :3]
            # the fingers stop on the part: its width across the gap
            self.gap = max(self.model.closed_gap, min(self.model.open_gap, float(np.ptp(local[:, 1]))))
            self.carried = part
            self._carried_local = local
            yield Message(GRASP_MESSAGE)
            yield Grasp(part)
        yield Hand(closed=True, gap=self.gap)

    def open(self, immediate: bool = False) -> Iterator[Event]:
        """OPEN/OPENI: release a carried part where it is."""
        self.clamp_closed = False
        self.gap = self.model.open_gap
        if self.carried is not None:
            part = self.carried
            self.carried = None
            self._carried_local = None
            corner = self.cell.objects[part - 1].reference
            yield Release(part, _rounded(corner))
        yield Hand(closed=False, gap=self.gap)

    def _follow_clamp(self, joints: Sequence[float] | None = None) -> None:
        """The carried part placed in the clamp at ``joints`` (where the arm is, by default): the
        collision checks place it at the poses they look at, and back, without moving the arm."""
        if self.carried is None or self._carried_local is None:
            return
        frame = self.model.clamp_frame(self.joints if joints is None else joints, self.base)
        part = self.cell.objects[self.carried - 1]
        part.vertices = self._carried_local @ frame[:3, :3].T + frame[:3, 3]

    # -- the work cell -----------------------------------------------------------
    def move_part(self, number: int, translation: Sequence[float] = (0.0, 0.0, 0.0),
                  axis: int | None = None, degrees: float = 0.0) -> Polyhedron:
        """Manipulation mode: translate a part, or turn it about its centre on a world axis."""
        part = self.cell.object(number)
        vertices = part.vertices + np.asarray(translation, dtype=float)
        if axis is not None and degrees:
            centre = vertices.mean(axis=0)
            c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
            u, v = [(1, 2), (2, 0), (0, 1)][axis]
            turn = np.eye(3)
            turn[u, u], turn[u, v], turn[v, u], turn[v, v] = c, -s, s, c
            vertices = (vertices - centre) @ turn.T + centre
        part.vertices = vertices
        return part

    def _collision_scene(self) -> RobotScene:
        """The collision check fed by link frames, its link shapes set for the clamp gap."""
        if self._checker is None:
            from valterm.core.collision.frames import RobotScene

            self._checker = RobotScene(self.model.names, self.model.frames.tolist(),
                                       thesis_axes=self.arm.key == THESIS_ROBOT)
        if self._checker_gap != self.gap:
            self._checker.set_shapes(self.model.shapes(self.gap))
            self._checker_gap = self.gap
        return self._checker

    def _frames_at(self, joints: Sequence[float]) -> np.ndarray:
        """Link frames in world coordinates."""
        # the base frame as built (identity, no BASE given): skip a product that changes nothing
        return self.model.link_frames(joints, None if self.base is self._home_base else self.base)

    def _frames_batch(self, joints: np.ndarray) -> np.ndarray:
        """``_frames_at`` of (n, 6) poses at once (the base frame as built: no product). Up to
        six poses of the thesis's arm one by one: the same numbers, bit for bit (the batch's
        are those of one pose at a time), without the batch's fixed cost (some 30 numpy calls)."""
        if 0 < len(joints) <= 6 and self.base is self._home_base and self.arm.key == THESIS_ROBOT:
            return np.stack([self._frames_at(pose) for pose in joints.tolist()])
        return self.model.link_frames_batch(joints, None if self.base is self._home_base else self.base)

    def check_collisions(self, previous: Sequence[float] | None = None,
                         at: Sequence[float] | None = None) -> Iterator[Event]:
        """The thesis's coarse and fine checks at this pose; each finding is said as it starts.

        With ``previous`` (the pose before, on the same path) the step between is checked too
        (issue 13: a thin part straddled by two consecutive poses is reported), where a part
        is near enough to be reached (issue 25). With ``at``, that pose is checked instead of
        the arm's (a value: the arm does not move; a carried part is looked at there).
        """
        if at is None:
            yield from self._said(self._findings_here(previous, self.joints))
            return
        try:
            self._follow_clamp(at)
            found = self._findings_here(previous, at)
        finally:
            self._follow_clamp()
        yield from self._said(found)

    def findings_now(self) -> list[Near | Collision]:
        """The collision checks' findings of the last step checked, the pose and the way to
        it (none with the checks off), as events: each is said once, as it starts, so a
        motion may not say one of these again."""
        if not self.collision_checks:
            return []
        found = sorted(self._findings, key=lambda f: str((f.kind, f.a, f.b)))
        return [finding.event() for finding in self._in_order(found)]

    def _findings_here(self, previous: Sequence[float] | None, here: Sequence[float]) -> list[Finding]:
        """The findings of the pose ``here`` and (with ``previous``) of the step to it, in order."""
        scene = self._collision_scene()
        carried = () if self.carried is None else (self.carried,)
        objects = self.cell.objects
        frames = self._frames_at(here)
        findings = scene.check(frames, objects, carried, self.speed)
        if previous is None:
            scene.swept(frames, (), objects, now=self._pose_key(here))   # the boxes a step starts from
        else:
            findings = self._swept(scene, previous, here, frames, carried) + findings
        return findings

    def _said(self, findings: list[Finding]) -> Iterator[Event]:
        """Each finding not said at the pose before (nor already at this one), as an event."""
        before, last = self._findings, self._findings_list
        # a crowded cell's poses mostly find the very findings (kept objects) the pose before did:
        # the lists compared by identity first, no finding hashed
        if last is not None and last[1] is before and last[0] == findings:
            return
        now = set(findings)
        # only the new ones put in order (most poses say again what the pose before said): the
        # order sorts, so those it keeps come in the order they would among all
        # (the set difference first: a set keeps its members' hashes)
        new = ([f for f in findings if f not in before] if now - before else []) if before else findings
        said: set[Finding] = set()
        for finding in self._in_order(new) if new else ():
            if finding not in said:
                said.add(finding)
                yield finding.event()
        self._findings, self._findings_list = now, (findings.copy(), now)

    def _in_order(self, findings: list[Finding]) -> list[Finding]:
        """The 1985 rules say a step's findings in Fig. C-12's order (the hand first); the
        controller rules in the order the checks found them."""
        if self.rules != RULES_1985:
            return findings
        from valterm.core.collision.world import figure_order

        return figure_order(findings, self.model.names)

    def _pose_key(self, joints: Sequence[float]) -> tuple[object, ...]:
        """What names a pose for the swept check: the joints and the base frame."""
        return (*joints, self.base.tobytes())

    def _swept(self, scene: RobotScene, previous: Sequence[float], here: Sequence[float], frames: np.ndarray,
               carried: tuple[int, ...]) -> list[Finding]:
        """Collisions between ``previous`` and the pose ``here``: at the moments ``RobotScene.swept``
        names, the pairs it finds there at risk (nothing when no part can be reached and no link
        turns against another past its width): parts and the arm against itself."""
        # the way the joints turned: under the 1985 rules 179 -> -179 is a turn of 2 degrees
        # (six Python floats: cheaper than numpy for the most steps, which need no moment)
        turns = [(float(b) - float(a) + 180.0) % 360.0 - 180.0 for a, b in zip(previous, here)]
        since, now = self._pose_key(previous), self._pose_key(here)
        moments, rows = scene.swept(frames, list(map(math.radians, turns)), self.cell.objects, since, now)
        if scene.glancing is not None and self.carried is None and not scene.glancing.measured:
            scene.clear_glancing(frames[None], lambda: self._frames_at(previous), since, now)
        if not len(moments) and scene.glancing is None:
            return []
        q0 = np.asarray(previous, dtype=float)[None]
        step = np.zeros(len(moments), dtype=np.intp)
        return self._at_moments(scene, q0, q0 + np.asarray(turns), (step, moments, rows))[0]

    def _at_moments(self, scene: RobotScene, q0: np.ndarray, q1: np.ndarray,
                    moments: tuple[np.ndarray, np.ndarray, np.ndarray], rounds: bool = False) -> list[list[Finding]]:
        """The collisions at the moments (each one's step, its fraction of the step, its row of
        pairs: ``RobotScene.swept``'s) of the steps from poses ``q0`` to ``q1`` (steps, 6), step
        by step; then, where the swept check left pairs that could meet between its moments
        (``RobotScene.glancing``), at the moments ``glance.between`` finds for them from how far
        apart the moments before found them (a corner clipped between two of them)."""
        from valterm.core.collision.glance import between, between_poses, ends, spans

        # with a part carried the pairs' distances are only their boxes' gaps, and the moments
        # between come one by one: 9x the cost of a grasping program (PROCESS graded at 0.9 s
        # a student, not 0.1), so a carried part's steps keep the width-spaced moments alone
        glancing = scene.glancing if self.carried is None else None
        if glancing is not None and glancing.measured and not len(moments[0]):    # the poses only
            return self._found_at(scene, q0, q1, between_poses(glancing), rounds, None)
        at, pair = np.nonzero(moments[2])
        known: Items = (moments[0], moments[1], at, pair)
        clear = None if glancing is None else np.zeros(len(known[2]))
        frames: list[np.ndarray] = []
        found = self._found_at(scene, q0, q1, known, rounds, clear, moments[2], frames)
        if glancing is None or clear is None:
            return found
        # the poses too, as far apart as their boxes, measured where that may clear a span
        at_ends, apart = ends(glancing)
        known, clear = _joined(known, at_ends), np.concatenate([clear, apart])
        found_spans = spans(glancing, known)
        # the poses' items measured already (``RobotScene.clear_glancing``), the moments' not (the
        # moments' link frames as the check of them had them)
        if glancing.measured:
            self._measured(scene, q0, q1, found_spans, known, clear, (len(at), frames[0] if frames else None))
        else:
            self._measured(scene, q0, q1, found_spans, known, clear, (len(clear), None))
        more = between(found_spans, clear)
        # a step says a pair once (in rounds where collisions are likely, as the first moments)
        for step, said in enumerate(self._found_at(scene, q0, q1, more, rounds, None)):
            found[step] += [f for f in said if f not in found[step]]
        return found

    def _measured(self, scene: RobotScene, q0: np.ndarray, q1: np.ndarray, found: Spans, known: Items,
                  clear: np.ndarray, upto: tuple[int, np.ndarray | None]) -> None:
        """How far apart the ``known`` items before ``upto[0]`` that end a span ``between`` would
        look in are (``glance.doubtful``), measured by the link's face planes
        (``RobotScene.apart_at``) where it was by their boxes, into ``clear`` (how far apart
        each was found). ``upto[1]``: the link frames at those items' moments, if known."""
        from valterm.core.collision.glance import doubtful

        step_of, t, at, p = known  # nothing carried here (``_at_moments`` looks between only then)
        count, kept = upto
        items = np.flatnonzero(doubtful(found, clear)[:count] & (clear[:count] >= 0.0))
        if not len(items):
            return
        used, moment = np.unique(at.take(items), return_inverse=True)
        frames = kept.take(used, axis=0) if kept is not None else self._frames_batch(
            q0[step_of[used]] + (q1[step_of[used]] - q0[step_of[used]]) * t[used][:, None])
        clear[items] = np.maximum(clear.take(items), scene.apart_at(frames, moment, p.take(items), True))

    def _found_at(self, scene: RobotScene, q0: np.ndarray, q1: np.ndarray, items: Items, rounds: bool,
                  clear: np.ndarray | None, rows: np.ndarray | None = None,
                  keep: list[np.ndarray] | None = None) -> list[list[Finding]]:
        """``_at_moments``' check of the moments and (moment, pair) items given: the link frames
        of every moment at once, then the pairs at risk checked at the moments where their
        boxes can meet (``RobotScene.meeting``; nowhere else can the fine test find one).
        ``rounds``: where collisions are likely, a pair found at one moment of a step is not
        looked for at its later ones (``RobotScene.collisions_at``). ``clear``: how far apart
        each item was found at least (``collisions_at``'s; left 0 with a part carried). ``rows``:
        the items as rows of pairs (the swept check's moments); without them a moment has few
        items, each a link and a part (``collisions_of``). ``keep``: told the moments' link frames."""
        step_of, t, at, p = items
        found: list[list[Finding]] = [[] for _ in q0]
        if not len(step_of):
            return found
        joints = q0[step_of] + (q1[step_of] - q0[step_of]) * t[:, None]
        frames = self._frames_batch(joints)
        if keep is not None:
            keep.append(frames)
        held = None
        if self.carried is not None and self._carried_local is not None:
            clamp = frames[:, 6]
            held = self._carried_local @ clamp[:, :3, :3].transpose(0, 2, 1) + clamp[:, None, :3, 3]
        steps = step_of if rounds else None
        if rows is None:
            batch = scene.collisions_of(frames, at, p, steps, clear, True)
        else:
            batch = scene.collisions_at(frames, rows, steps, clear)
        if batch is not None:                   # every moment's pairs at once (no part carried)
            for k, said in enumerate(batch):
                if said:
                    found[int(step_of[k])] += said
            return found
        if rows is None:
            rows = np.zeros((len(step_of), int(p.max(initial=0)) + 1), dtype=bool)
            rows[at, p] = True
        moved = False
        try:
            for k in np.flatnonzero(scene.meeting(frames, rows, held)).tolist():
                self._follow_clamp(joints[k])
                moved = True
                found[int(step_of[k])] += scene.collisions_between(frames[k], self.cell.objects,
                                                                   np.flatnonzero(rows[k]), self.speed)
        finally:
            if moved:
                self._follow_clamp()
        return found


def _joined(a: Items, b: Items) -> Items:
    """Two sets of moments and items as one (``b``'s moments after ``a``'s)."""
    return (np.concatenate([a[0], b[0]]), np.concatenate([a[1], b[1]]), np.concatenate([a[2], b[2] + len(a[0])]),
            np.concatenate([a[3], b[3]]))


class _PathChecks:
    """A path's collision checks worked out together at its first checked pose: the link
    frames of every pose in one batch, the pose checks, every step's swept decision at once
    (``RobotScene.swept_path``) and every moment's link frames at once; ``findings`` hands
    each pose's out as the pose is shown (the steps' findings first, as ``check_collisions``).

    What it assumes: nothing but the path moves the arm or the cell while it plays (the
    simulator's motions are generators played to the end or dropped). When the checks are
    paused (``dropped``) the pose it reached is kept as the next step's start and the rest
    is checked pose by pose."""

    def __init__(self, sim: Simulator, start: Sequence[float], path: np.ndarray, first: int) -> None:
        """The path's poses from the one the simulator has just shown (its joints now, settled)
        on, ``path`` the rest; ``start`` the pose before it, ``first`` its index in the motion."""
        self.sim, self.first = sim, first
        self.scene = sim._collision_scene()
        self.next = 0
        self.live = True
        here = sim.joints
        self.poses: list[list[float]] = [list(here)]
        try:
            for pose in path:
                self.poses.append(sim._settled(pose))
        except ValtermError:
            pass                          # the motion stops there when it gets there
        frames = sim._frames_batch(np.asarray(self.poses))
        self.found: list[list[Finding]] = []
        self.figures: PathFigures | None = None
        self.collides = False          # a pose checked alone collides (``keep_path``'s: ``figures.collided``)
        try:
            self._poses_checked(sim, start, frames)
            self._steps(sim, np.asarray([start, *self.poses], dtype=float), frames)
        finally:
            sim._follow_clamp()

    def _poses_checked(self, sim: Simulator, start: Sequence[float], frames: np.ndarray) -> None:
        """Every pose's check, together (``RobotScene.keep_path``) but for the few it leaves to the
        fine test, checked alone. The first pose is checked alone first when the scene is not set
        up for the cell as it is (``RobotScene.path_ready``: the first motion, a part moved or
        carried), and every pose when the poses cannot be checked together."""
        scene, carried, objects = self.scene, () if sim.carried is None else (sim.carried,), sim.cell.objects
        keys = [sim._pose_key(j) for j in self.poses]
        told: list[list[Finding] | None] | None = None
        if self.poses and scene.path_ready(objects, carried):
            self.figures = scene.path_figures(len(self.poses), sim._pose_key(start))
            told = None if self.figures is None else scene.keep_path(self.figures, frames, keys, sim.speed)
        for k, (joints, at) in enumerate(zip(self.poses, frames)):
            found = None if told is None else told[k]
            if found is None:
                sim._follow_clamp(joints)
                found = scene.check(at, objects, carried, sim.speed)
                self.collides = self.collides or any(f.kind == "collides" for f in found)
                if told is None:                      # pose by pose, or the first pose setting up
                    if k == 0:
                        self.figures = scene.path_figures(len(self.poses), sim._pose_key(start))
                    if self.figures is not None:
                        scene.keep_pose(self.figures, at, keys[k])
                    if k == 0 and self.figures is not None:
                        rest = scene.keep_path(self.figures, frames[1:], keys[1:], sim.speed)
                        told = None if rest is None else [found, *rest]
            self.found.append(found)

    def _steps(self, sim: Simulator, q: np.ndarray, frames: np.ndarray) -> None:
        """Every step's collisions between its poses, put before that pose's findings."""
        if self.figures is None:
            return
        # the way the joints turned: under the 1985 rules 179 -> -179 is a turn of 2 degrees
        turns = (q[1:] - q[:-1] + 180.0) % 360.0 - 180.0
        start = q[:-1]
        moments = self.scene.swept_path(frames, np.radians(turns), sim.cell.objects, self.figures,
                                        lambda: sim._frames_at(start[0]),
                                        lambda step, t: sim._frames_batch(start[step] + t[:, None] * turns[step]),
                                        sim.rules == RULES_1985)
        if self.scene.glancing is not None and sim.carried is None:
            keys = self.figures.keys
            self.scene.clear_glancing(frames[: len(keys) - 1], lambda: sim._frames_at(q[0]), keys[0], keys[-1])
        if not len(moments[0]) and self.scene.glancing is None:
            return
        # a path that collides at its poses most likely does between them (a cell crowded
        # round a path it clears seldom does): then the moments go in rounds
        rounds = self.collides or any(len(hit) for hit in self.figures.collided)
        for step, said in enumerate(sim._at_moments(self.scene, q[:-1], q[:-1] + turns, moments, rounds)):
            if said:
                self.found[step] = said + self.found[step]

    def settled(self, index: int, pose: Sequence[float]) -> list[float]:
        """The joint state at the path's pose ``index`` (worked out once)."""
        k = index - self.first
        return self.poses[k] if 0 <= k < len(self.poses) else self.sim._settled(pose)

    def findings(self, previous: Sequence[float]) -> list[Finding]:
        """The findings of the next pose (pose by pose, once dropped)."""
        if self.live and self.next < len(self.found):
            found = self.found[self.next]
            self.next += 1
            return found
        self.dropped()
        return self.sim._findings_here(previous, self.sim.joints)

    def dropped(self) -> None:
        """The checks stop here: the next step starts from the last pose checked."""
        if self.live and self.next:
            self.scene.keep_ends(self.figures, self.next)
        self.live = False
