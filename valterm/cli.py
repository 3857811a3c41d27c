"""The ``valterm`` command line: the app with no arguments, subcommands for scripts.

Exit status: 0 ok, 1 failure, 2 usage (see ``valterm.commands``); an unexpected
exception is a bug: one line on stderr naming the log file with its traceback
(``valterm.core.crashlog``), exit 70.
"""

from __future__ import annotations

import argparse
import gc
import os
import re
import sys
from collections.abc import Callable, Sequence
from typing import NoReturn

# Nothing of the package is imported here: ``main`` pauses the cycle collector and sets
# numpy's threads before the start's imports (issue 25, the start).

# The subcommands in the order of --help. A command line loads only its own command's module
# (the app none: issue 25, the start); --help and a usage error load them all.
COMMANDS = ("kin", "cell", "import", "export", "export-program", "check", "run", "monitor", "grade", "render",
            "bench", "demo", "replay", "serve")

def registrar(command: str) -> Callable[..., None]:
    """The ``register`` of the module (valterm.commands) that adds ``command``, imported now."""
    if command == "kin":
        from valterm.commands import kin
        return kin.register
    if command == "cell":
        from valterm.commands import cell
        return cell.register
    if command == "import":
        from valterm.commands import cad
        return cad.register
    if command == "export":
        from valterm.commands import export
        return export.register
    if command == "export-program":
        from valterm.commands import exportprogram
        return exportprogram.register
    if command == "check":
        from valterm.commands import check
        return check.register
    if command == "run":
        from valterm.commands import run
        return run.register
    if command == "monitor":
        from valterm.commands import monitor
        return monitor.register
    if command == "grade":
        from valterm.commands import grade
        return grade.register
    if command == "render":
        from valterm.commands import render
        return render.register
    if command == "bench":
        from valterm.commands import bench
        return bench.register
    if command == "demo":
        from valterm.commands import demo
        return demo.register
    if command == "replay":
        from valterm.commands import replay
        return replay.register
    from valterm.commands import serve
    return serve.register

def epilog() -> str:
    """What --help says after the options."""
    from valterm.core.workspace import ENV_VAR

    return (f"The workspace (programs, setup and location files) is --workspace DIR, else ${ENV_VAR}, "
            "else ~/valterm; it is created and filled with the bundled examples on first use. "
            "--workspace may also follow the subcommand. "
            "Exit status: 0 ok, 1 failure, 2 usage error, 70 internal error (traceback logged).")


NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)(e[-+]?\d+)?$|^-(inf|infinity|nan)$", re.IGNORECASE)


class Parser(argparse.ArgumentParser):
    """Every parser of the command line: usage errors say ``valterm:`` and exit 2, and each
    subcommand also takes ``--workspace`` (after its name as well as before)."""

    def __init__(self, *args: object, **kwargs: object) -> None:
        from valterm.core.workspace import ENV_VAR

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
        from valterm.commands import USAGE, say

        self.print_usage(sys.stderr)
        where = self.prog.removeprefix("valterm").strip()
        say(f"{where}: {message}" if where else message)
        raise SystemExit(USAGE)


class VersionAction(argparse.Action):
    """--version: the installed version, looked up only when asked (importlib.metadata is
    about 10 ms of every start otherwise)."""

    def __init__(self, option_strings: Sequence[str], dest: str, **kwargs: object) -> None:
        super().__init__(option_strings, dest, nargs=0, default=argparse.SUPPRESS,
                         help="show program's version number and exit")

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace,
                 values: object, option_string: str | None = None) -> None:
        from valterm import version

        print(f"valterm {version()}")  # on stdout, as argparse's own version action
        parser.exit()


class _Unsure(Exception):
    """The first look at a command line could not tell which command it names."""


class _Glance(Parser):
    """The top-level options as the real parser has them, every command a stub that takes
    anything: which command a command line names, without loading any command's module."""

    def error(self, message: str) -> NoReturn:
        raise _Unsure(message)


class _UnsureHelp(argparse.Action):
    """-h before any command: the whole --help, every command listed."""

    def __call__(self, *args: object, **kwargs: object) -> None:
        raise _Unsure("--help")


def chosen_commands(argv: Sequence[str] | None) -> tuple[str, ...]:
    """The commands' names whose modules ``argv`` needs: its own command's; none for the app;
    all of them for --help, --version or anything the glance cannot tell apart."""
    glance = _Glance(prog="valterm", top=True, add_help=False)
    glance.add_argument("-h", "--help", nargs=0, action=_UnsureHelp)
    _top_options(glance)
    stubs = glance.add_subparsers(dest="command", parser_class=_Glance)
    for name in COMMANDS:
        stubs.add_parser(name, add_help=False)
    try:
        args, extra = glance.parse_known_args(argv)
    except _Unsure:
        return tuple(COMMANDS)
    if args.command is not None:
        return (args.command,)
    return tuple(COMMANDS) if extra else ()


def parse_command_line(argv: Sequence[str] | None) -> argparse.Namespace:
    """``argv`` parsed by the parser that ``chosen_commands`` picks. A line that names no
    command is tried first on the app's own parser alone, without the glance (the first
    argparse parser a process builds costs some milliseconds of the app's start, issue 25);
    anything it cannot take (a help, version or usage question) goes the long way."""
    tokens = sys.argv[1:] if argv is None else list(argv)
    if not any(token in COMMANDS or token.startswith(("-h", "--h", "--v")) for token in tokens):
        try:
            return build_parser((), top_class=_Glance).parse_args(argv)
        except _Unsure:
            pass
    return build_parser(chosen_commands(argv)).parse_args(argv)


def build_parser(commands: Sequence[str] | None = None,
                 top_class: type[Parser] | None = None) -> argparse.ArgumentParser:
    """The command line's parser with ``commands`` registered (default: every one);
    ``top_class`` (default Parser) the top parser's class."""
    parser = (top_class or Parser)(
        prog="valterm", top=True,
        description="VAL-II SIMULATOR: teach and program a PUMA robot in VAL-II, in the terminal. "
                    "With no COMMAND it starts the app.",
        epilog=epilog(),
    )
    parser.add_argument("--version", action=VersionAction)
    _top_options(parser)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=Parser)
    for command in COMMANDS if commands is None else commands:
        registrar(command)(sub)
    return parser


def _top_options(parser: argparse.ArgumentParser) -> None:
    """The app's options, before any command."""
    from valterm.commands.limits import add_limit_flags
    from valterm.commands.robots import add_robot_option
    from valterm.core.rules import RULES

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
    parser.add_argument("--record", metavar="FILE",
                        help="the app: keep every key typed (with its time) and every line shown in FILE, a new "
                             "file written as the session goes; `valterm replay FILE` plays it")


def main(argv: Sequence[str] | None = None) -> int:
    # The app's start makes some hundred thousand objects that live as long as it does, and
    # the cycle collector would walk them again and again before the first frame (about a
    # tenth of the start, issue 25): it waits until the command is known, then runs again at
    # once for a subcommand and after MAIN MENU's first frame for the app.
    collecting = gc.isenabled()
    gc.disable()
    # numpy's OpenBLAS starts a thread per core at import, and each spins for a while waiting
    # for work that the simulator's small matrices never give it: about 0.1 s of CPU at every
    # start, which a busy two-core machine takes from the app. The user's own setting wins.
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    try:
        return _dispatch(argv, collecting)
    except Exception as bug:
        from valterm.core.crashlog import report_crash

        return report_crash(bug)
    finally:
        if collecting:
            gc.enable()


def _dispatch(argv: Sequence[str] | None, collecting: bool = True) -> int:
    from valterm.commands import FAILURE, USAGE, app, say
    from valterm.core.errors import ValtermError

    try:
        args = parse_command_line(argv)
    except SystemExit as done:  # --help, --version, a usage error
        return done.code if isinstance(done.code, int) else USAGE
    func = getattr(args, "func", None) or app.run_app
    if func is app.run_app:
        args.collect_after_first_frame = collecting
    elif collecting:
        gc.enable()
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
