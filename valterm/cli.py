"""The ``valterm`` command line: the app with no arguments, subcommands for scripts.

Exit status: 0 ok, 1 failure, 2 usage (see ``valterm.commands``); an unexpected
exception is a bug: one line on stderr naming the log file with its traceback
(``valterm.core.crashlog``), exit 70.
"""

from __future__ import annotations

import argparse
import os
import re
import sys
from collections.abc import Sequence
from typing import NoReturn

from valterm import version
from valterm.commands import (
    FAILURE,
    USAGE,
    app,
    bench,
    cad,
    cell,
    check,
    demo,
    export,
    exportprogram,
    grade,
    kin,
    monitor,
    render,
    run,
    say,
    serve,
)
from valterm.commands.limits import add_limit_flags
from valterm.commands.robots import add_robot_option
from valterm.core.crashlog import report_crash
from valterm.core.errors import ValtermError
from valterm.core.rules import RULES
from valterm.core.workspace import ENV_VAR

# Each module registers its subcommand(s); the order is the order of --help.
COMMANDS = (kin, cell, cad, export, exportprogram, check, run, monitor, grade, render, bench, app, demo, serve)

EPILOG = (
    f"The workspace (programs, setup and location files) is --workspace DIR, else ${ENV_VAR}, "
    "else ~/valterm; it is created and filled with the bundled examples on first use. "
    "--workspace may also follow the subcommand. "
    "Exit status: 0 ok, 1 failure, 2 usage error, 70 internal error (traceback logged)."
)


NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)(e[-+]?\d+)?$|^-(inf|infinity|nan)$", re.IGNORECASE)


class Parser(argparse.ArgumentParser):
    """Every parser of the command line: usage errors say ``valterm:`` and exit 2, and each
    subcommand also takes ``--workspace`` (after its name as well as before)."""

    def __init__(self, *args: object, **kwargs: object) -> None:
        top = kwargs.pop("top", False)
        super().__init__(*args, **kwargs)  # type: ignore[arg-type]
        self.add_argument(
            "--workspace", metavar="DIR",
            # a subcommand's parser only sets it when given, so it never hides the top one
            default=None if top else argparse.SUPPRESS,
            help=f"the workspace folder (default ${ENV_VAR}, else ~/valterm)",
        )
        # -1e3, -.5 and -inf are numbers (kin's poses), not options (argparse knows only -12, -1.5)
        self._negative_number_matcher = NEGATIVE_NUMBER

    def error(self, message: str) -> NoReturn:
        self.print_usage(sys.stderr)
        where = self.prog.removeprefix("valterm").strip()
        say(f"{where}: {message}" if where else message)
        raise SystemExit(USAGE)


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(
        prog="valterm", top=True,
        description="VAL-II SIMULATOR: teach and program a PUMA robot in VAL-II, in the terminal. "
                    "With no COMMAND it starts the app.",
        epilog=EPILOG,
    )
    parser.add_argument("--version", action="version", version=f"valterm {version()}")
    parser.add_argument("--setup", metavar="NAME", help="the app: read NAME.SET and go straight to the MAIN MENU")
    parser.add_argument("--ascii", action="store_true", help="the app: draw the model in ASCII, not braille")
    parser.add_argument("--rules", choices=RULES, default=None,
                        help="the joint-state rules: 1985 (the thesis's, default) or controller (a real PUMA's); "
                             "docs/MOTION.md")
    add_robot_option(parser)  # the app's robot (run, monitor take it too; grade's task files name it)
    add_limit_flags(parser, top=True)  # the app's programs' limits (run, monitor, grade take them too)
    parser.add_argument("--keys", choices=("modern", "1985"), default=None,
                        help="the app's keyboard: modern (default, or $VALTERM_KEYS) or 1985, the thesis's: "
                             "VAL-II mode and the editor return to their menus after each command, so "
                             "Tables C-1..C-3 typed as printed replay")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=Parser)
    for command in COMMANDS:
        command.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    try:
        return _dispatch(argv)
    except Exception as bug:
        return report_crash(bug)


def _dispatch(argv: Sequence[str] | None) -> int:
    try:
        args = build_parser().parse_args(argv)
    except SystemExit as done:  # --help, --version, a usage error
        return done.code if isinstance(done.code, int) else USAGE
    func = getattr(args, "func", None) or app.run_app
    try:
        return int(func(args) or 0)
    except ValtermError as error:  # a refusal the command did not word itself
        say(error)
        return FAILURE
    except KeyboardInterrupt:
        say("interrupted")
        return 130
    except BrokenPipeError:
        # the reader went away (`valterm kin fk < poses | head`): quietly, and with no
        # second complaint when Python flushes stdout at exit
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


if __name__ == "__main__":
    raise SystemExit(main())
