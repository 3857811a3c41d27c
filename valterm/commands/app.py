"""The app: ``valterm`` alone starts the VAL-II SIMULATOR (no subcommand of its own; serving it
to browsers is ``valterm serve``, valterm/commands/serve.py).

Textual is imported only when the app starts, so the other subcommands stay quick.
"""

from __future__ import annotations

import argparse


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """The app is what ``valterm`` does without a subcommand: nothing to register."""


def run_app(args: argparse.Namespace) -> int:
    """Start the app on the workspace; ``--setup NAME`` goes straight to the MAIN MENU."""
    from valterm.commands.limits import limits_from
    from valterm.commands.robots import robot_from
    from valterm.ui.app import run

    return run(getattr(args, "workspace", None), getattr(args, "setup", None), ascii=bool(getattr(args, "ascii", False)),
               rules=getattr(args, "rules", None), limits=limits_from(args), keys=getattr(args, "keys", None),
               robot=robot_from(args), collect_after_first_frame=bool(getattr(args, "collect_after_first_frame", False)))
