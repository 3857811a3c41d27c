"""The run limits' flags, the same on every command that runs programs (the app, ``run``,
``monitor``, ``grade``): ``--max-steps``, ``--max-seconds``, ``--max-lines``.

The limits themselves and their defaults are the core's (``valterm.core.val.limits``);
this only reads the numbers a user gives. 0 means no limit.
"""

from __future__ import annotations

import argparse
import math

from valterm.core.val.limits import DEFAULT_LINES, DEFAULT_SECONDS, DEFAULT_STEPS, RunLimits


def _count(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"{value} is negative (0 means no limit)")
    return value


def _seconds(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of seconds") from None
    if not math.isfinite(value) or value < 0:
        raise argparse.ArgumentTypeError(f"{text} is not a number of seconds >= 0 (0 means no limit)")
    return value


def add_limit_flags(parser: argparse.ArgumentParser, top: bool = False) -> None:
    """The three flags; on a subcommand they are set only when given (as --workspace), so
    ``valterm --max-steps 10 run X`` and ``valterm run X --max-steps 10`` are the same."""
    default = None if top else argparse.SUPPRESS
    parser.add_argument("--max-steps", type=_count, metavar="N", default=default,
                        help=f"stop a program after N steps (default {DEFAULT_STEPS}; 0: no limit)")
    parser.add_argument("--max-seconds", type=_seconds, metavar="S", default=default,
                        help=f"stop a program after S seconds of robot time (default {DEFAULT_SECONDS:g}; 0: no limit)")
    parser.add_argument("--max-lines", type=_count, metavar="N", default=default,
                        help=f"stop a program after N lines of output (default {DEFAULT_LINES}; 0: no limit)")


def limits_from(args: argparse.Namespace) -> RunLimits:
    """The limits the flags give, the core's defaults for those not given."""
    steps = getattr(args, "max_steps", None)
    seconds = getattr(args, "max_seconds", None)
    lines = getattr(args, "max_lines", None)
    return RunLimits(DEFAULT_STEPS if steps is None else steps,
                     DEFAULT_SECONDS if seconds is None else seconds,
                     DEFAULT_LINES if lines is None else lines)
