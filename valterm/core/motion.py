"""Motion as pure functions from a start and a goal to the sequence of poses shown (SPEC §3).

Joint-coordinated motion (§2.4.1) and straight-line motion (§2.4.2) both return an array of
joint vectors (steps, 6), the last row being the goal; the model is drawn at every row (the
apparent motion of §2.1). A motion the robot cannot make raises ``MotionRefused`` before
anything moves.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from valterm.core.arms import Arm, as_arm
from valterm.core.errors import JointAtStop, MotionRefused
from valterm.core.kinematics import (
    BeyondStop,
    Config,
    IKError,
    RobotGeometry,
    canonical_angle,
    shown_angle,
    wrap180,
)
from valterm.core.rules import CONTROLLER, RULES_1985

# Each function takes the robot (core/arms.py): an Arm, or the thesis's geometry, or None for
# the thesis's robot.
Robot = Arm | RobotGeometry | None

JOINT_INCREMENT = 12.0      # degrees per step at SPEED 100 (§2.6)
STRAIGHT_INCREMENT = 25.4   # millimetres per step at SPEED 100
PENDANT_INCREMENT = 8.0     # degrees per key press (§3.1)
PENDANT_STEP = 10.0         # millimetres per WORLD/TOOL key press at the default increment
MIN_SPEED, MAX_SPEED = 10.0, 100.0
# A step-to-step jump this large in JT1..JT3 means the arm had to change configuration.
CONFIG_JUMP = 45.0
# A step-to-step turn this large in JT4..JT6 is a wrist twirl, not a smooth line.
WRIST_JUMP = 90.0
# Within this of JT5 = 0 a line is at the wrist singularity: JT4 and JT6 swing as they please.
NEAR_WRIST = 10.0


OUT_OF_REACH_REASON = "location out of reach"  # the 1985 wording (a robot file's robot names itself)


def clamp_speed(speed: float) -> float:
    """SPEED is clamped to 10..100 (§6.6.1)."""
    return min(MAX_SPEED, max(MIN_SPEED, float(speed)))


def joint_increment(speed: float) -> float:
    return JOINT_INCREMENT * clamp_speed(speed) / 100.0


def straight_increment(speed: float) -> float:
    return STRAIGHT_INCREMENT * clamp_speed(speed) / 100.0


# ---------------------------------------------------------------------------
# Joint-coordinated motion
# ---------------------------------------------------------------------------

def joint_path(start: Sequence[float], goal: Sequence[float], increment: float) -> np.ndarray:
    """The poses of a joint-coordinated motion from start to goal (§2.4.1, Fig. 2-7).

    The joint with the largest difference moves ``increment`` per step and decides the
    number of steps, ceil(largest / increment); every other joint moves in proportion.
    When the division leaves a remainder, the last step is the remainder (each joint's last
    step is proportional to it). Returns (steps, 6); an empty array when already there.
    """
    if increment <= 0:
        raise ValueError("the increment must be positive")
    a = np.asarray(start, dtype=float)
    b = np.asarray(goal, dtype=float)
    delta = b - a
    largest = float(np.abs(delta).max())
    if largest < 1e-9:
        return np.zeros((0, len(a)))
    steps = math.ceil(largest / increment - 1e-9)
    # fraction of the whole motion done after each step: i*inc/largest, the last one 1
    fractions = np.minimum(np.arange(1, steps + 1) * increment / largest, 1.0)
    fractions[-1] = 1.0
    poses: np.ndarray = a + fractions[:, None] * delta
    return poses


# ---------------------------------------------------------------------------
# Straight-line motion
# ---------------------------------------------------------------------------

def _slerp(r0: np.ndarray, r1: np.ndarray, fractions: np.ndarray) -> np.ndarray:
    """Rotations from r0 to r1 along the shortest rotation (Rodrigues on the relative rotation)."""
    rel = r0.T @ r1
    cos = max(-1.0, min(1.0, (np.trace(rel) - 1.0) / 2.0))
    angle = math.acos(cos)
    n = len(fractions)
    if angle < 1e-12:
        return np.broadcast_to(r0, (n, 3, 3)).copy()
    if math.pi - angle < 1e-6:
        # half turn: the axis from the symmetric part
        axis = np.sqrt(np.clip((np.diag(rel) + 1.0) / 2.0, 0.0, None))
        i = int(np.argmax(axis))
        axis = rel[:, i] + np.eye(3)[i]
        axis /= np.linalg.norm(axis)
    else:
        axis = np.array([rel[2, 1] - rel[1, 2], rel[0, 2] - rel[2, 0], rel[1, 0] - rel[0, 1]])
        axis /= 2.0 * math.sin(angle)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    theta = fractions * angle
    steps = (np.eye(3)[None] + np.sin(theta)[:, None, None] * k[None]
             + (1.0 - np.cos(theta))[:, None, None] * (k @ k)[None])
    rotations: np.ndarray = r0[None] @ steps
    return rotations


def _refusal(error: IKError, step: int) -> MotionRefused:
    if isinstance(error, BeyondStop) and error.stop is not None:
        return beyond_stop(error.joint, error.angle, *error.stop, step)  # names the angle and the stop
    if isinstance(error, BeyondStop):
        return MotionRefused(str(error), error.joint, step)
    return MotionRefused(OUT_OF_REACH_REASON, 0, step)


def straight_path(
    start: Sequence[float],
    goal_xyz: Sequence[float] | np.ndarray,
    goal_rotation: np.ndarray,
    config: Config,
    increment: float,
    robot: Robot = None,
    rules: str = RULES_1985,
) -> np.ndarray:
    """The poses of a straight-line motion of the TCS origin (§2.4.2, SPEC §3).

    Position advances in equal steps (ceil(largest coordinate difference / increment));
    orientation is unchanged when start and goal share it, else interpolated along the
    shortest rotation. The goal is solved with the user's indicators; each intermediate
    step with the user's ARM and ELBOW and the wrist solution nearest the previous step.
    Raises MotionRefused (reason, joint, step) if any step is out of reach, beyond a stop,
    or would need ARM or ELBOW to change. The goal is solved before any step is built, so an
    absurd goal is refused at once (two reachable points lie at most the arm's span apart).
    ``rules``: under the 1985 rules a step is within the stops when a 360-degree equivalent
    is; under the controller's the angle itself must be (joints wind).
    """
    robot = as_arm(robot)
    current = [float(v) for v in start]
    here = robot.fk(current)
    _refuse_config_change(robot.indicators(current), config)
    goal_xyz = np.asarray(goal_xyz, dtype=float)
    goal_rotation = np.asarray(goal_rotation, dtype=float)
    try:
        goal_joints = robot.ik(goal_xyz, goal_rotation, config, None, enforce_stops=False)
    except IKError as error:
        raise _refusal(error, 0) from None
    steps = _line_steps(here.xyz, here.rotation, goal_xyz, goal_rotation, increment)
    fractions = np.arange(1, steps + 1) / steps
    positions = here.xyz + fractions[:, None] * (goal_xyz - here.xyz)
    same_orientation = np.allclose(here.rotation, goal_rotation, atol=1e-12)
    rotations = (np.broadcast_to(here.rotation, (steps, 3, 3)) if same_orientation
                 else _slerp(here.rotation, goal_rotation, fractions))
    # intermediate steps: both wrist solutions at once, then the nearest to the previous step
    solutions = []
    statuses = []
    for wrist in (1, -1):
        joints, status = robot.ik_batch(positions, rotations, (config.arm, config.elbow, wrist))
        solutions.append(joints)
        statuses.append(status)
    path = np.empty((steps, 6))
    previous = np.array(current)
    wound = rules == CONTROLLER
    for i in range(steps):
        if i == steps - 1:
            best = _nearest_equivalent(np.array(goal_joints), previous)
            _refuse_wrist_change(best, previous, current, robot, i + 1)
        else:
            best = _nearest_wrist(solutions, statuses, i, previous)
        _refuse_jumps(best, previous, robot, i + 1, wound)
        path[i] = best
        previous = best
    return path


def _refuse_config_change(now: Config, wanted: Config) -> None:
    """A straight line keeps ARM and ELBOW: refuse one that starts in the other configuration."""
    for kind, have, want in (("ARM", now.arm, wanted.arm), ("ELBOW", now.elbow, wanted.elbow)):
        if have != want:
            words = {"ARM": ("RIGHTY", "LEFTY"), "ELBOW": ("ABOVE", "BELOW")}[kind]
            raise MotionRefused(
                f"straight line would change {kind} from {words[have < 0]} to {words[want < 0]}"
            )


# The most steps a line may take: the arm's span at the smallest increment, with room to spare.
MAX_LINE_STEPS = 10_000


def _line_steps(start_xyz: np.ndarray, start_rotation: np.ndarray, goal_xyz: np.ndarray,
                goal_rotation: np.ndarray, increment: float) -> int:
    """How many steps a line takes: its length over the increment, and its turn over the joint
    increment scaled alike (a pure reorientation still takes steps)."""
    largest = float(np.abs(goal_xyz - start_xyz).max())
    cos = np.clip((np.trace(start_rotation.T @ goal_rotation) - 1) / 2, -1, 1)
    turn = float(np.degrees(np.arccos(cos)))
    steps = max(1, math.ceil(largest / increment - 1e-9))
    turn_increment = JOINT_INCREMENT * increment / STRAIGHT_INCREMENT
    steps = max(steps, math.ceil(turn / turn_increment - 1e-9))
    if steps > MAX_LINE_STEPS:  # both ends reachable: only a BASE far away could make this
        raise MotionRefused(f"the line is too long ({largest:.0f} mm): at most {MAX_LINE_STEPS} steps")
    return steps


def _nearest_wrist(solutions: list[np.ndarray], statuses: list[np.ndarray], i: int,
                   previous: np.ndarray) -> np.ndarray:
    """Step i of a line: of the two wrist solutions, the one nearest the previous step."""
    options = [_nearest_equivalent(joints[i], previous)
               for joints, status in zip(solutions, statuses) if int(status[i]) != -1]
    if not options:
        raise MotionRefused(OUT_OF_REACH_REASON, 0, i + 1)
    return min(options, key=lambda o: float(np.abs(o[3:] - previous[3:]).sum()))


def _refuse_wrist_change(goal: np.ndarray, previous: np.ndarray, start: Sequence[float],
                         robot: Arm, step: int) -> None:
    """The goal is solved with the user's WRIST; the steps before it tracked the nearest wrist.

    When the two differ the last step would twirl the wrist: refuse, as for ARM and ELBOW, and
    say why: a line along which JT5 passed 0 went through the wrist singularity.
    """
    have, want = robot.indicators(list(previous)).wrist, robot.indicators(list(goal)).wrist
    if have != want and float(np.abs(goal[3:] - previous[3:]).max()) > WRIST_JUMP:
        words = ("NOFLIP", "FLIP")
        if (previous[4] > 0) != (float(start[4]) > 0) or min(abs(previous[4]), abs(float(start[4]))) < NEAR_WRIST:
            raise MotionRefused(f"the line passes the wrist singularity (JT5 = 0): it would end "
                                f"{words[have < 0]}, the indicators ask {words[want < 0]}", 5, step)
        raise MotionRefused(f"straight line would change WRIST from {words[have < 0]} to {words[want < 0]}", 0, step)


def beyond_stop_message(joint: int, angle: float, low: float, high: float, shown_as: float | None = None) -> str:
    """One wording for a joint beyond its stop: the angle it would need, beside the stop, and
    (``shown_as``, the 1985 rules) how the readout shows that angle, (-180, 180]."""
    needed = f"{angle:.2f}" if abs(angle) < 1e6 else f"{angle:.6g}"  # no 300-digit angles
    also = "" if shown_as is None or f"{shown_as:.2f}" == needed else f", shown as {shown_as:.2f}"
    return f"joint {joint} beyond its stop ({needed} deg{also}, stop {low:g}..{high:g})"


def beyond_stop(joint: int, angle: float, low: float, high: float, step: int = 0,
                shown_as: float | None = None) -> JointAtStop:
    """The refusal of a joint beyond its stop, at ``angle`` (the angle it would need)."""
    return JointAtStop(beyond_stop_message(joint, angle, low, high, shown_as), joint, angle, low, high, step)


def needed_angle(angle: float, low: float, high: float) -> float:
    """1985 rules: the angle a joint beyond its stops would need, as the readout shows a joint:
    of its 360-degree equivalents the one nearest the stops (228.39 beside the stop 225, not
    its -131.61, which lies 86 degrees from the other stop)."""
    wrapped = wrap180(angle)
    return min((wrapped, wrapped - 360.0, wrapped + 360.0), key=lambda a: max(low - a, a - high, 0.0))


def _refuse_jumps(best: np.ndarray, previous: np.ndarray, robot: Arm, step: int,
                  wound: bool = False) -> None:
    """A step beyond a stop, or one that jumps (a configuration change or a wrist twirl)."""
    for joint, (angle, (low, high)) in enumerate(zip(best, robot.stops), start=1):
        # the controller's joints wind: the angle itself must be inside (no jump of 360 degrees);
        # under the 1985 rules the angle is a function of the pose: an equivalent inside will do
        inside = low - 1e-9 <= angle <= high + 1e-9 if wound else canonical_angle(angle, low, high) is not None
        if not inside:
            if wound:
                raise beyond_stop(joint, angle, low, high, step)
            # the 1985 rules show joints in (-180, 180]: the message says that form too
            raise beyond_stop(joint, needed_angle(angle, low, high), low, high, step, shown_as=shown_angle(angle))
    jumps = np.abs(best - previous)
    if float(jumps[:3].max()) > CONFIG_JUMP:
        if jumps[0] >= max(jumps[1], jumps[2]):
            raise MotionRefused("the line passes the shoulder singularity (the wrist crosses joint 1's axis)", 1, step)
        straight = f"{robot.elbow_straight:.4g}"
        raise MotionRefused(f"the line passes the elbow singularity (the arm straight, JT3 = {straight})", 3, step)
    if float(jumps[3:].max()) > WRIST_JUMP:
        raise MotionRefused("the line passes the wrist singularity (JT5 = 0)", 5, step)


def _nearest_equivalent(angles: np.ndarray, near: np.ndarray) -> np.ndarray:
    """Each angle shifted by whole turns to lie nearest ``near``."""
    shifted: np.ndarray = angles + 360.0 * np.round((near - angles) / 360.0)
    return shifted


# ---------------------------------------------------------------------------
# Targets: APPRO / DEPART / DRAW
# ---------------------------------------------------------------------------

def approach_point(xyz: Sequence[float] | np.ndarray, rotation: np.ndarray, distance: float) -> np.ndarray:
    """APPRO: the point ``distance`` back from the location along its tool Z (positive = -a)."""
    point: np.ndarray = np.asarray(xyz, dtype=float) - distance * np.asarray(rotation)[:, 2]
    return point


def joint_goal(
    xyz: Sequence[float] | np.ndarray, rotation: np.ndarray, config: Config, current: Sequence[float],
    robot: Robot = None,
) -> list[float]:
    """The joint vector of a location for a joint-coordinated move; MotionRefused if none."""
    robot = as_arm(robot)
    try:
        return robot.ik(xyz, rotation, config, current)
    except IKError as error:
        raise _refusal(error, 0) from None


def check_joint_goal(goal: Sequence[float], robot: Robot = None) -> None:
    """Refuse a relative joint move (DRIVE, pendant joints) whose goal is beyond a stop.

    The joint turns through every angle on its way, so the goal itself must lie within the
    stops: no 360-degree equivalent helps here. The goal is checked before any path is built,
    so an absurd turn is refused at once.
    """
    robot = as_arm(robot)
    _refuse_not_finite(goal)
    for joint, (angle, (low, high)) in enumerate(zip(goal, robot.stops), start=1):
        if not low - 1e-9 <= angle <= high + 1e-9:
            raise beyond_stop(joint, angle, low, high)


def _refuse_not_finite(angles: Sequence[float]) -> None:
    """A joint goal with an angle that is no finite number is refused, naming the joint."""
    for joint, angle in enumerate(angles, start=1):
        if not math.isfinite(angle):
            raise MotionRefused(f"joint {joint}: the angle is not a finite number", joint)


def fit_precision_point(goal: Sequence[float], current: Sequence[float],
                        robot: Robot = None) -> list[float]:
    """A precision point's joints as the robot takes them: each the 360-degree equivalent inside
    its stops nearest the current angle (an angle copied from WHERE or ``kin ik`` is never
    refused; JT3 -144.96 is JT3 215.04). MotionRefused when a joint has no equivalent inside."""
    robot = as_arm(robot)
    values = [float(v) for v in goal]
    _refuse_not_finite(values)
    try:
        return robot.fit_to_stops(values, current)
    except BeyondStop as error:
        raise MotionRefused(str(error), error.joint) from None


# ---------------------------------------------------------------------------
# Pendant (Chapter 3)
# ---------------------------------------------------------------------------

def pendant_straight(
    current: Sequence[float],
    displacement: np.ndarray,
    increment: float,
    robot: Robot = None,
    rules: str = RULES_1985,
) -> np.ndarray:
    """A WORLD or TOOL step: the TCS origin moves by ``displacement`` keeping its orientation.

    Uses the theoretical indicators of the current pose (§3.2) and refuses a step that would
    change them or bring JT3 within one increment of the elbow-straight singularity (§3.3).
    """
    robot = as_arm(robot)
    here = robot.fk(current)
    config = robot.indicators(current)
    goal = here.xyz + np.asarray(displacement, dtype=float)
    length = float(np.abs(displacement).max())
    path = straight_path(current, goal, here.rotation, config, max(length, 1e-9), robot, rules)
    for step, joints in enumerate(path, start=1):
        if robot.indicators(joints) != config:
            raise MotionRefused("the move would change the configuration indicators", 0, step)
        # elbow straight: forearm in line with the upper arm (the thesis's: JT3 = 90, JTsim3 = 0)
        if abs(joints[2] - robot.elbow_straight) < abs(increment):
            raise MotionRefused("links 2 and 3 nearly aligned (elbow singularity)", 3, step)
    return path


def world_displacement(axis: int, step: float) -> np.ndarray:
    d = np.zeros(3)
    d[axis] = step
    return d


def tool_displacement(current: Sequence[float], axis: int, step: float,
                      robot: Robot = None) -> np.ndarray:
    """A step along the tool's own X, Y or Z axis, in world coordinates."""
    robot = as_arm(robot)
    return robot.fk(current).rotation[:, axis] * step


__all__ = [
    "OUT_OF_REACH_REASON",
    "PENDANT_INCREMENT",
    "PENDANT_STEP",
    "MotionRefused",
    "approach_point",
    "beyond_stop",
    "beyond_stop_message",
    "check_joint_goal",
    "clamp_speed",
    "fit_precision_point",
    "joint_goal",
    "joint_increment",
    "joint_path",
    "needed_angle",
    "pendant_straight",
    "straight_increment",
    "straight_path",
    "tool_displacement",
    "world_displacement",
]
