"""The ``valterm`` command line: the app with no arguments, subcommands for scripts."""

from __future__ import annotations

import argparse
import importlib
import sys
from typing import Sequence

# Each module in valterm.commands registers one subcommand (see its docstring).
SUBCOMMANDS = ("kin", "cell", "cad", "check", "run", "bench", "app", "demo", "serve")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="valterm",
        description="VAL-II SIMULATOR: teach and program a PUMA robot in VAL-II, in the terminal.",
    )
    parser.add_argument("--workspace", metavar="DIR", help="the workspace folder (default ~/valterm)")
    parser.add_argument("--setup", metavar="NAME", help="the app: read NAME.SET and go straight to the MAIN MENU")
    parser.add_argument("--ascii", action="store_true", help="the app: draw the model in ASCII, not braille")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in SUBCOMMANDS:
        try:
            module = importlib.import_module(f"valterm.commands.{name}")
        except ModuleNotFoundError as error:
            if error.name == f"valterm.commands.{name}":
                continue  # not built yet
            raise
        module.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    func = getattr(args, "func", None)
    if func is None:
        app = getattr(args, "default_app", None)
        if app is None:
            try:
                from valterm.commands.app import run_app
            except ModuleNotFoundError:
                print(
                    "valterm: the VAL-II SIMULATOR app is being built; "
                    "try `valterm kin fk 0 -90 90 0 0 0` meanwhile."
                )
                return 0
            return run_app(args)
        return app(args)
    try:
        return int(func(args) or 0)
    except KeyboardInterrupt:
        print("valterm: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0


if __name__ == "__main__":
    raise SystemExit(main())
