"""The app: ``valterm`` alone starts the VAL-II SIMULATOR; ``valterm serve --web`` serves it
to a browser (textual-serve, the optional ``web`` extra).

Textual is imported only when the app starts, so the other subcommands stay quick.
"""

from __future__ import annotations

import argparse
import shlex
import sys

from valterm.commands import FAILURE, USAGE, fail


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    serve = sub.add_parser("serve", help="serve the app to a web browser (needs valterm[web])")
    serve.add_argument("--web", action="store_true", help="serve over HTTP with textual-serve")
    serve.add_argument("--host", default="localhost", help="the address to listen on (default localhost)")
    serve.add_argument("--port", type=int, default=8000, help="the port (default 8000)")
    serve.set_defaults(func=run_serve)


def run_app(args: argparse.Namespace) -> int:
    """Start the app on the workspace; ``--setup NAME`` goes straight to the MAIN MENU."""
    from valterm.ui.app import run

    return run(getattr(args, "workspace", None), getattr(args, "setup", None), ascii=bool(getattr(args, "ascii", False)))


def run_serve(args: argparse.Namespace) -> int:
    if not args.web:
        return fail("serve: say --web to serve the app over HTTP (valterm serve --web --port 8000)", USAGE)
    try:
        from textual_serve.server import Server
    except ImportError:
        return fail("serve --web needs textual-serve: pip install 'valterm[web]'", FAILURE)
    command = [sys.executable, "-m", "valterm"]
    if getattr(args, "workspace", None):
        command += ["--workspace", args.workspace]
    if getattr(args, "setup", None):
        command += ["--setup", args.setup]
    if getattr(args, "ascii", False):
        command.append("--ascii")
    server = Server(shlex.join(command), host=args.host, port=args.port, title="VAL-II SIMULATOR")
    server.serve()
    return 0
