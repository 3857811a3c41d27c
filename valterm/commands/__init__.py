"""Subcommands of the ``valterm`` command line, one module each.

Each module defines ``register(subparsers)`` which adds its parser and sets
``func=<callable(args) -> int>`` as the default. ``valterm.cli`` lists them.

Exit status everywhere: 0 ok, 1 failure (a bad file, a refused program, a run-time
error), 2 usage (bad arguments); a bug exits 70 (``valterm.core.crashlog``). Messages
go to standard error, prefixed ``valterm:``.
"""

from __future__ import annotations

import sys

from valterm.core.files.errors import error_message

OK = 0
FAILURE = 1
USAGE = 2


def say(message: object) -> None:
    """One message on standard error, prefixed ``valterm:`` (unless it already is)."""
    # an OSError as NAME: reason (not "[Errno 2] ..."), long names cut
    text = error_message(message) if isinstance(message, BaseException) else str(message)
    print(text if text.startswith("valterm:") else f"valterm: {text}", file=sys.stderr)


def fail(message: object, status: int = FAILURE) -> int:
    """Say ``message`` and give the exit status (``return fail(...)``)."""
    say(message)
    return status
