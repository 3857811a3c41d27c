"""``valterm kin fk|ik``: the kinematics core from the command line, one pose or many.

With the pose on the command line it prints one result; a malformed pose there is a
usage error (exit 2), an unreachable one a failure (exit 1). With no pose it reads one
pose per line from standard input (blank lines and ``#`` comments skipped) and prints
one result per line; a bad line is reported on standard error with its line number (and
as an ``{"error": ...}`` object in --json, so outputs stay aligned with inputs), the rest
go on, and the status is 1 if any line failed.

``kin ik`` prints the geometric solution even when a joint is beyond its stop (the
thesis's Figs. 2-8a2 and 2-8c show such rows), flagged ``"beyond_stop": n`` in JSON and
by a warning on standard error; motions still refuse such poses.

``--robot PUMA560`` takes the PUMA 560 of the robotics courses (``robot/PUMA560.toml``, its
standard DH table, ``valterm.core.dh``) instead of the thesis's robot: joint angles with
that table's zero (Corke's Robotics Toolbox ``Puma560``), positions of its frame 6 in mm.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Callable, Iterator, Sequence

import numpy as np

from valterm.core.errors import RefusedValue
from valterm.commands import FAILURE, OK, USAGE, say
from valterm.commands.robots import add_robot_option, robot_from
from valterm.core.arms import Arm, arm_of
from valterm.core.robot_choice import THESIS_ROBOT
from valterm.core.dh import RobotFileError
from valterm.core.kinematics import (
    BeyondStop,
    Config,
    HasStops,
    IKError,
    oat_to_rotation,
    readout_joints,
    shown_angle,
)
from valterm.core.numbers import angle_text, two_decimals
from valterm.core.rules import CONTROLLER


# Larger numbers are no pose at all (mm or degrees); they would only overflow.
LIMIT = 1e9


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    kin = sub.add_parser("kin", help="forward and inverse kinematics of the PUMA")
    kin_sub = kin.add_subparsers(dest="kin_command", metavar="fk|ik", required=True)

    fk_parser = kin_sub.add_parser("fk", help="JT1..JT6 -> XW YW ZW O A T and indicators")
    fk_parser.add_argument("joints", nargs="*", metavar="JT",
                           help="six joint angles in degrees (PUMA convention); none: one pose a line on stdin")
    fk_parser.add_argument("--point", type=int, choices=(1, 2, 3), default=1,
                           help="1 TCS origin, 2 LED sensor, 3 clamp tip")
    fk_parser.add_argument("--json", action="store_true", help="one JSON object per result")
    _robot_option(fk_parser)
    fk_parser.set_defaults(func=run_fk)

    ik_parser = kin_sub.add_parser("ik", help="XW YW ZW O A T -> JT1..JT6")
    ik_parser.add_argument("pose", nargs="*", metavar="V",
                           help="X Y Z (mm) O A T (degrees); none: one pose a line on stdin")
    ik_parser.add_argument("--config", default="RIGHTY,ABOVE,NOFLIP",
                           help="configuration indicators, e.g. LEFTY,ABOVE,NOFLIP")
    ik_parser.add_argument("--json", action="store_true", help="one JSON object per result")
    _robot_option(ik_parser)
    ik_parser.set_defaults(func=run_ik)


def _robot_option(parser: argparse.ArgumentParser) -> None:
    add_robot_option(parser)


def _arm(args: argparse.Namespace) -> Arm:
    """The robot --robot names (core/arms.py); RobotFileError for a robot file that is unusable."""
    return arm_of(robot_from(args))


class BadPose(ValueError):
    """The words of a pose are not what the command takes (a usage error on the command line)."""


def _numbers(words: Sequence[str], count: int, what: str) -> list[float]:
    if len(words) != count:
        raise BadPose(f"expected {count} numbers ({what}), got {len(words)}")
    values = []
    for word in words:
        try:
            value = float(word)
        except ValueError:
            raise BadPose(f"{word!r} is not a number") from None
        if not math.isfinite(value) or abs(value) > LIMIT:
            raise BadPose(f"{word!r} is not a usable number (finite, at most {LIMIT:g} in size)")
        values.append(value)
    return values


def _poses(given: Sequence[str]) -> Iterator[tuple[int, list[str]]]:
    """The command-line pose (line 0), or one pose per line of standard input."""
    if given:
        yield 0, list(given)
        return
    for number, line in enumerate(sys.stdin, start=1):
        words = line.split("#", 1)[0].split()
        if not words:
            continue
        # a trailing configuration word (RIGHTY,BELOW,NOFLIP) keeps its commas
        tail = [words.pop()] if words[-1][:1].isalpha() and len(words) > 1 else []
        yield number, " ".join(words).replace(",", " ").split() + tail


def _each(args: argparse.Namespace, given: Sequence[str], solve: Callable[[list[str], int], None]) -> int:
    """Solve each pose; report failures on stderr (and as JSON records); the exit status."""
    if not given and sys.stdin.isatty():
        return _usage_hint(args)
    status = OK
    for line, words in _poses(given):
        try:
            with np.errstate(all="ignore"):  # overflow shows as a message below, not a warning
                solve(words, line)
        except BadPose as error:
            _failed(args, str(error), line)
            status = max(status, USAGE if line == 0 else FAILURE)
        except IKError as error:
            _failed(args, str(error), line, error.joint)
            status = max(status, FAILURE)
    return status


def _usage_hint(args: argparse.Namespace) -> int:
    what = "six joint angles" if args.kin_command == "fk" else "X Y Z O A T"
    say(f"kin {args.kin_command}: give {what}, or pipe one pose a line on standard input")
    return USAGE


def _failed(args: argparse.Namespace, message: str, line: int, joint: int | None = None) -> None:
    where = f"line {line}: " if line else ""
    say(f"kin {args.kin_command}: {where}{message}")
    if args.json:
        record: dict[str, object] = {"error": message}
        if joint is not None:
            record["joint"] = joint
        if line:
            record["line"] = line
        print(json.dumps(record))


def _warn(args: argparse.Namespace, message: str, line: int) -> None:
    where = f"line {line}: " if line else ""
    say(f"kin {args.kin_command}: {where}warning: {message}")


def _finite(values: Sequence[float]) -> list[float]:
    if not all(math.isfinite(v) for v in values):
        raise IKError("no finite solution")
    return list(values)


def frame_line(robot: Arm) -> str:
    """Another robot's positions are in its own base frame (frame 0), not the cell's that WHERE
    shows: say so, and how WHERE's follow (the mount: the 560's base d1 below the shoulder)."""
    offsets = [f"{axis}W = {axis}0 {'+' if v > 0 else '-'} {abs(v):.2f}"
               for axis, v in zip("XYZ", robot.mount[:3, 3]) if abs(v) >= 0.005]
    where = f": WHERE IN THE CELL HAS {', '.join(offsets)}" if offsets else ""
    return f"{robot.name} BASE FRAME (FRAME 0 OF ITS DH TABLE){where}"


def _table(xyz: Sequence[float], oat: Sequence[float], config: Config, shown: Sequence[float],
           clamp: str = "OPENED", frame: str = "W") -> str:
    """The Fig. 2-8 readout (``shown``: the joints as ``_shown`` gives them); ``frame`` names
    the axes' frame (W: the world's, 0: a robot's base)."""
    arm, elbow, wrist = config.words
    row = "{:<7}" + "{:>9}" * 6
    head = row.format(clamp, f"X{frame}", f"Y{frame}", f"Z{frame}", "O", "A", "T")
    values = row.format(arm, *map(two_decimals, xyz), *map(angle_text, oat))
    head2 = row.format(elbow, "JT1", "JT2", "JT3", "JT4", "JT5", "JT6")
    values2 = row.format(wrist, *map(two_decimals, shown))
    return "\n".join((head, values, head2, values2))


def _shown(args: argparse.Namespace, joints: Sequence[float], stops: HasStops) -> list[float]:
    """Joints as printed (SPEC §3a): the 1985 rules (the default) show them in (-180, 180] as
    the thesis's figures do (JT2 172.08); --rules controller, inside the stops (JT3 215.04)."""
    if getattr(args, "rules", None) == CONTROLLER:
        return [round(j, 6) for j in readout_joints(joints, stops)]
    return [round(shown_angle(j), 6) for j in joints]


def _chosen(args: argparse.Namespace) -> tuple[Arm | None, int]:
    """The robot --robot names and OK, or None and USAGE after saying why."""
    try:
        robot = _arm(args)
    except RobotFileError as error:
        say(f"kin {args.kin_command}: --robot: {error}")
        return None, USAGE
    if robot.key != THESIS_ROBOT and getattr(args, "point", 1) != 1:
        say(f"kin fk: --point {args.point}: the LED sensor and the clamp tip are the thesis's robot's; "
            f"{robot.name} has its frame 6 only")
        return None, USAGE
    return robot, OK


def _fk_pose(robot: Arm, joints: list[float], point: int) -> tuple[list[float], list[float], Config]:
    """XYZ (mm), O A T (degrees) and the indicators of a joint vector on the chosen robot."""
    pose = robot.fk(joints, point)
    return [float(v) for v in pose.xyz], list(pose.oat), robot.indicators(joints)


def run_fk(args: argparse.Namespace) -> int:
    robot, status = _chosen(args)
    if robot is None:
        return status
    stops = robot

    def solve(words: list[str], line: int) -> None:
        joints = _numbers(words, 6, "JT1..JT6")
        position, orientation, config = _fk_pose(robot, joints, args.point)
        xyz = [round(v, 6) for v in _finite(position)]
        oat = [round(v, 6) for v in _finite(orientation)]
        shown = _shown(args, joints, stops)
        if args.json:
            print(json.dumps({"xyz": xyz, "oat": oat, "config": config.as_dict(), "joints": shown,
                              "robot": stops.name}))
        elif robot.key == THESIS_ROBOT:  # the cell's frame is the robot's own (Fig. 2-8)
            print(_table(xyz, oat, config, shown))
        else:
            print(frame_line(robot))
            print(_table(xyz, oat, config, shown, frame="0"))

    return _each(args, args.joints, solve)


def _ik_joints(robot: Arm, pose: list[float], config: Config) -> list[float]:
    """The geometric solution (degrees, wrapped) of X Y Z O A T on the chosen robot."""
    return robot.ik(pose[:3], oat_to_rotation(*pose[3:]), config, enforce_stops=False)


def run_ik(args: argparse.Namespace) -> int:
    try:
        default_config = Config.parse(args.config)
    except RefusedValue as error:
        say(f"kin ik: --config: {error}")
        return USAGE
    robot, status = _chosen(args)
    if robot is None:
        return status
    stops = robot

    def solve(words: list[str], line: int) -> None:
        config = default_config
        if len(words) == 7:
            try:
                config = Config.parse(words[6])
            except RefusedValue as error:
                raise BadPose(str(error)) from None
            words = words[:6]
        pose = _numbers(words, 6, "X Y Z O A T")
        # the geometric solution first; the stops only flag it
        joints = _finite(_ik_joints(robot, pose, config))
        beyond = 0
        try:
            joints = robot.fit_to_stops(joints)
        except BeyondStop as stop:
            beyond = stop.joint
            _warn(args, f"joint {beyond} beyond its stop ({stop.angle:.2f} deg): "
                        "the geometric solution is shown; the robot cannot take this pose", line)
        shown = _shown(args, joints, stops)
        if args.json:
            result: dict[str, object] = {"joints": shown, "config": config.as_dict(), "robot": stops.name}
            if beyond:
                result["beyond_stop"] = beyond
            print(json.dumps(result))
        else:
            print(" ".join(map(two_decimals, shown)))

    return _each(args, args.pose, solve)
