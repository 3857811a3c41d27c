"""``valterm monitor [--setup NAME] [--loc FILE]... [--workspace DIR]``

The VAL-II mode as a plain line-mode program, for scripts, screen readers, dumb terminals
and teletype exhibits: it reads command lines from standard input (prompting with ``.`` when
that is a terminal; a piped line is echoed after ``. `` instead) and prints the same
transcript lines as ``valterm run``, with no colour and no cursor movement.  EXECUTE runs
programs; PAUSE / PROCEED and the debugger (BPT, XSTEP, SSTEP, WATCH, TRACE) work as in the
app.  CTRL-C aborts the running (or paused) program, not the monitor.  Motions are not paced
and DELAY is not waited.

``--setup NAME`` reads NAME.SET (and NAME.LOC, without ``--loc``); ``--loc`` reads a location
file (a path, or a name in the workspace; may repeat).  CHECK.DAT's variables are read and
written back, as in the app.

Each EXECUTE stops at the run limits (docs/LIMITS.md; ``--max-steps``, ``--max-seconds``,
``--max-lines``) with a message naming the limit; the prompt goes on.

Exit at the end of the input: 0, or 1 if any command or program reported an error (a limit too);
2: a bad setup or location file.
"""

from __future__ import annotations

import argparse
import signal
import sys
from typing import Any, TextIO

from valterm.commands.limits import add_limit_flags, limits_from
from valterm.commands.robots import add_robot_option, robot_from


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    parser = subparsers.add_parser("monitor", help="the VAL-II prompt as a line-mode program (stdin in, transcript out)")
    # SUPPRESS: given before the subcommand (valterm --setup X monitor), the value stays
    parser.add_argument("--setup", metavar="NAME", default=argparse.SUPPRESS, help="read NAME.SET (and NAME.LOC)")
    parser.add_argument("--loc", metavar="FILE", action="append", help="a location file (may repeat)")
    parser.add_argument("--rules", choices=("1985", "controller"), default=argparse.SUPPRESS,
                        help="the joint-state rules (default 1985; RULES at the prompt shows or sets them)")
    add_robot_option(parser)
    add_limit_flags(parser)
    parser.set_defaults(func=run)


def _session(args: argparse.Namespace) -> Any:
    """The session with its setup and locations read (errors: the caller's exit 2)."""
    from valterm.commands.run import _find
    from valterm.core.files.locations import read_locations
    from valterm.core.session import Session

    session = Session(getattr(args, "workspace", None), setup=None, limits=limits_from(args),
                      robot=robot_from(args))
    setup = getattr(args, "setup", None)
    if setup:
        session.load_setup(setup)
    workspace = session.workspace
    loc_names = args.loc or ([session.setup_name] if setup and workspace.exists(session.setup_name, "LOC") else [])
    for name in loc_names:
        points = read_locations(_find(name, "LOC", workspace))
        session.simulator.locations.update(points)
        session.simulator.mark_locations_stored(points)
    if getattr(args, "rules", None):
        session.simulator.set_rules(args.rules)
    return session


def _ready(stdin: TextIO) -> bool:
    """More input can be read at once (a pipe with lines waiting); False when reading would wait,
    and for a stream that is no file (a test's StringIO: kept at the end)."""
    import select

    try:
        fd = stdin.fileno()
    except (OSError, ValueError):
        return True
    try:
        return bool(select.select([fd], [], [], 0)[0])
    except (OSError, ValueError):
        return False


def run(args: argparse.Namespace, stdin: TextIO | None = None, stdout: TextIO | None = None) -> int:
    from valterm.core.errors import ValtermError
    from valterm.core.monitor import LineMonitor
    from valterm.core.text.transcript import blocks_for

    stdin = stdin or sys.stdin
    out = stdout or sys.stdout
    try:
        session = _session(args)
    except (ValtermError, OSError) as error:
        print(error, file=sys.stderr)
        return 2

    blocks = blocks_for(out)  # a command's answer in blocks, flushed before the next line is read

    def write(text: str) -> None:
        blocks.write(text + "\n")

    monitor = LineMonitor(session, write)
    interactive = stdin.isatty()

    def on_sigint(signum: int, frame: Any) -> None:
        if monitor.running and not monitor.interpreter.paused:
            if getattr(on_sigint, "pressed", False):  # a second CTRL-C does not wait for the step
                raise KeyboardInterrupt
            on_sigint.pressed = True  # type: ignore[attr-defined]
            monitor.abort()
            return
        raise KeyboardInterrupt  # at the prompt

    previous = signal.signal(signal.SIGINT, on_sigint)  # the main thread: the CLI's
    try:
        while True:
            on_sigint.pressed = False  # type: ignore[attr-defined]
            try:
                if not _ready(stdin):  # the end of a batch of lines: CHECK.DAT is written once
                    monitor.keep()
                blocks.flush()  # the last command's whole answer, before waiting for the next
                if interactive:
                    out.write(". ")
                    out.flush()
                text = stdin.readline()
                if not text:
                    break
                text = text.rstrip("\r\n")
                if not interactive and text.strip():
                    write(f". {text}")
                monitor.line(text)
            except KeyboardInterrupt:
                write("" if interactive else "^C")  # a terminal has shown ^C itself
                monitor.interrupted()
    finally:
        signal.signal(signal.SIGINT, previous)
        blocks.flush()
    if interactive:
        blocks.write("\n")
    status = monitor.end()  # may say that the variables were not kept
    blocks.flush()
    return status
