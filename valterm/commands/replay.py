"""``valterm replay FILE``: a session record (``valterm --record FILE``) played in the app, key
by key at the pace it was typed, so an instructor watches a student's session (valterm/ui/replay.py).
It replays into a fresh temporary workspace (removed after) unless ``--workspace DIR`` names one.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    parser = sub.add_parser("replay", help="play a session record (valterm --record FILE) in the app")
    parser.add_argument("file", metavar="FILE", help="the record")
    parser.add_argument("--speed", type=float, default=1.0,
                        help="faster (4) or slower (0.5) than the student typed; pauses over 5 s are shortened")
    parser.add_argument("--once", action="store_true", help="exit at the end of the record")
    for action in parser._actions:  # every subcommand's --workspace (cli.Parser): here not ~/valterm
        if action.dest == "workspace":
            action.help = "replay into this folder (default: a fresh temporary workspace, removed after)"
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if not args.speed > 0 or args.speed == float("inf"):
        print("valterm: replay: --speed must be a positive number", file=sys.stderr)
        return 2
    from valterm.ui.replay import run_replay

    workspace = getattr(args, "workspace", None)
    return run_replay(args.file, speed=args.speed, once=args.once, ascii=bool(getattr(args, "ascii", False)),
                      workspace=Path(workspace) if workspace else None)
