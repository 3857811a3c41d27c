"""``valterm kin fk|ik``: the kinematics core from the command line, one pose or many.

With the pose on the command line it prints one result; with none it reads one pose per
line from standard input and prints one result per line, so thousands of poses take one
call. A bad line gives an error for that line and the rest go on.
"""

from __future__ import annotations

import argparse
import json
import sys
from typing import Iterable, Sequence

from valterm.core.kinematics import Config, IKError, fk, ik_oat, indicators, wrap180


def register(sub: argparse._SubParsersAction) -> None:
    kin = sub.add_parser("kin", help="forward and inverse kinematics of the PUMA")
    kin_sub = kin.add_subparsers(dest="kin_command", metavar="fk|ik", required=True)

    fk_parser = kin_sub.add_parser("fk", help="JT1..JT6 -> XW YW ZW O A T and indicators")
    fk_parser.add_argument("joints", nargs="*", metavar="JT", help="six joint angles in degrees (PUMA convention)")
    fk_parser.add_argument("--point", type=int, choices=(1, 2, 3), default=1,
                           help="1 TCS origin, 2 LED sensor, 3 clamp tip")
    fk_parser.add_argument("--json", action="store_true", help="one JSON object per result")
    fk_parser.set_defaults(func=run_fk)

    ik_parser = kin_sub.add_parser("ik", help="XW YW ZW O A T -> JT1..JT6")
    ik_parser.add_argument("pose", nargs="*", metavar="V", help="X Y Z (mm) O A T (degrees)")
    ik_parser.add_argument("--config", default="RIGHTY,ABOVE,NOFLIP",
                           help="configuration indicators, e.g. LEFTY,ABOVE,NOFLIP")
    ik_parser.add_argument("--json", action="store_true", help="one JSON object per result")
    ik_parser.set_defaults(func=run_ik)


def _numbers(words: Sequence[str], count: int, what: str) -> list[float]:
    if len(words) != count:
        raise ValueError(f"expected {count} numbers ({what}), got {len(words)}")
    values = []
    for word in words:
        try:
            values.append(float(word))
        except ValueError:
            raise ValueError(f"{word!r} is not a number") from None
    return values


def _lines(args_values: Sequence[str]) -> Iterable[tuple[int, list[str]]]:
    """The command-line pose, or one pose per line of standard input (blank lines skipped)."""
    if args_values:
        yield 0, list(args_values)
        return
    for number, line in enumerate(sys.stdin, start=1):
        words = line.split()
        if not words:
            continue
        # a trailing configuration word (RIGHTY,BELOW,NOFLIP) keeps its commas
        tail = [words.pop()] if words[-1][:1].isalpha() and len(words) > 1 else []
        yield number, " ".join(words).replace(",", " ").split() + tail


def _error(message: str, line: int, as_json: bool, joint: int | None = None) -> None:
    if as_json:
        obj: dict[str, object] = {"error": message}
        if joint is not None:
            obj["joint"] = joint
        if line:
            obj["line"] = line
        print(json.dumps(obj))
    else:
        where = f"line {line}: " if line else ""
        print(f"{where}{message}", file=sys.stdout if line else sys.stderr)


def _table(xyz: Sequence[float], oat: Sequence[float], config: Config, joints: Sequence[float], clamp: str = "OPENED") -> str:
    """The Fig. 2-8 readout."""
    arm, elbow, wrist = config.words
    row = "{:<7}" + "{:>9}" * 6
    head = row.format(clamp, "XW", "YW", "ZW", "O", "A", "T")
    values = row.format(arm, *(f"{v:.2f}" for v in (*xyz, *oat)))
    head2 = row.format(elbow, "JT1", "JT2", "JT3", "JT4", "JT5", "JT6")
    values2 = row.format(wrist, *(f"{wrap180(v):.2f}" for v in joints))
    return "\n".join((head, values, head2, values2))


def run_fk(args: argparse.Namespace) -> int:
    failed = False
    for line, words in _lines(args.joints):
        try:
            joints = _numbers(words, 6, "JT1..JT6")
        except ValueError as error:
            _error(str(error), line, args.json)
            failed = True
            continue
        pose = fk(joints, point=args.point)
        xyz = [round(float(v), 6) for v in pose.xyz]
        oat = [round(v, 6) for v in pose.oat]
        config = indicators(joints)
        shown = [round(wrap180(j), 6) for j in joints]
        if args.json:
            print(json.dumps({"xyz": xyz, "oat": oat, "config": config.as_dict(), "joints": shown}))
        else:
            print(_table(xyz, oat, config, joints))
    # a single pose that failed exits 1; a batch reports per line and exits 0
    return 1 if failed and args.joints else 0


def run_ik(args: argparse.Namespace) -> int:
    try:
        default_config = Config.parse(args.config)
    except ValueError as error:
        print(f"valterm kin ik: --config: {error}", file=sys.stderr)
        return 2
    failed = False
    for line, words in _lines(args.pose):
        config = default_config
        try:
            if len(words) == 7:
                config = Config.parse(words[6])
                words = words[:6]
            pose = _numbers(words, 6, "X Y Z O A T")
            joints = ik_oat(pose[:3], pose[3:], config)
        except IKError as error:
            _error(str(error.reason), line, args.json, error.joint)
            failed = True
            continue
        except ValueError as error:
            _error(str(error), line, args.json)
            failed = True
            continue
        shown = [round(wrap180(j), 6) for j in joints]
        if args.json:
            print(json.dumps({"joints": shown, "config": config.as_dict()}))
        else:
            print(" ".join(f"{v:.2f}" for v in shown))
    # a single pose that failed exits 1; a batch reports per line and exits 0
    return 1 if failed and args.pose else 0
