"""The app: ``valterm`` alone starts the VAL-II SIMULATOR (no subcommand of its own; serving it
to browsers is ``valterm serve``, valterm/commands/serve.py).

Textual is imported only when the app starts, so the other subcommands stay quick.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from valterm.core.files.record import SessionRecord


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """The app is what ``valterm`` does without a subcommand: nothing to register."""


def run_app(args: argparse.Namespace) -> int:
    """Start the app on the workspace; ``--setup NAME`` goes straight to the MAIN MENU."""
    from valterm.commands.limits import limits_from
    from valterm.commands.robots import robot_from

    recorder = open_record(args)  # before the app: a refused record path is said on a plain terminal
    from valterm.ui.app import run

    return run(getattr(args, "workspace", None), getattr(args, "setup", None), ascii=bool(getattr(args, "ascii", False)),
               rules=getattr(args, "rules", None), limits=limits_from(args), keys=getattr(args, "keys", None),
               robot=robot_from(args), collect_after_first_frame=bool(getattr(args, "collect_after_first_frame", False)),
               recorder=recorder)


def open_record(args: argparse.Namespace) -> SessionRecord | None:
    """--record FILE: the session's record, opened (a new file) with what the session starts
    with; FileWriteError (said by the command line, exit 1) for a link, a FIFO, an old file."""
    path = getattr(args, "record", None)
    if not path:
        return None
    import shutil

    from valterm.commands.limits import limits_from
    from valterm.commands.robots import robot_from
    from valterm.core.files.record import SessionRecord
    from valterm.ui.app import keyboard_of

    size = shutil.get_terminal_size()
    limits = limits_from(args)
    header = {"keys": keyboard_of(getattr(args, "keys", None)), "setup": getattr(args, "setup", None),
              "rules": getattr(args, "rules", None), "robot": robot_from(args),
              "workspace": getattr(args, "workspace", None), "size": [size.columns, size.lines],
              "limits": {"steps": limits.steps, "seconds": limits.seconds, "lines": limits.lines}}
    return SessionRecord(path, header)
