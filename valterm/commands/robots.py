"""``--robot NAME``, the same on every command that moves or draws a robot (the app, ``run``,
``monitor``, ``grade``'s task files have a ``robot`` key instead): PUMA, the thesis's own model
(the default), or a bundled robot file such as PUMA560 (core/arms.py, docs/ROBOTS.md).
"""

from __future__ import annotations

import argparse

from valterm.core.robot_choice import THESIS_ROBOT, check_robot, robot_keys
from valterm.core.errors import RefusedValue


def robot_name(text: str) -> str:
    """argparse's type for --robot: the name as the core spells it, or a usage error."""
    try:
        return check_robot(text)
    except RefusedValue as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def add_robot_option(parser: argparse.ArgumentParser, default: str | None = None) -> None:
    """--robot on ``parser``. A subcommand's leaves the app's value alone unless given
    (``valterm --robot PUMA560 run X`` and ``valterm run X --robot PUMA560`` are one)."""
    parser.add_argument("--robot", type=robot_name, metavar="NAME",
                        default=argparse.SUPPRESS if default is None else default,
                        help=f"the robot: {THESIS_ROBOT} (the thesis's, default) or "
                             f"{', '.join(robot_keys()[1:])} (a robot file: standard DH, docs/ROBOTS.md)")


def robot_from(args: argparse.Namespace) -> str | None:
    """The robot asked for; None for the thesis's (the default)."""
    name = getattr(args, "robot", None)
    return None if name in (None, THESIS_ROBOT) else str(name)
