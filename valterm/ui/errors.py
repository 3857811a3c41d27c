"""What the app shows when something fails: the core's refusals, and bugs.

A ``ValtermError`` is a refusal the user can act on: its message is shown, upper case as on
the VS11. Anything else is a bug: it is written with its traceback to the log file and shown
as one line that says where the details are. No built-in exception is taken for a refusal.
"""

from __future__ import annotations

import datetime
import os
import traceback
from pathlib import Path

from valterm.core.errors import ValtermError
from valterm.core.motion import MotionRefused

LOG_ENV = "VALTERM_LOG"  # where bugs are logged (default: the user's state folder)


def log_path() -> Path:
    """$VALTERM_LOG, else $XDG_STATE_HOME/valterm/valterm.log (~/.local/state by default)."""
    given = os.environ.get(LOG_ENV)
    if given:
        return Path(given).expanduser()
    state = os.environ.get("XDG_STATE_HOME") or str(Path.home() / ".local" / "state")
    return Path(state) / "valterm" / "valterm.log"


def error_text(error: ValtermError) -> str:
    """The message of a core refusal, upper case as on the VS11."""
    text = (str(error).strip() or type(error).__name__).upper()
    return f"MOTION REFUSED: {text}" if isinstance(error, MotionRefused) else text


def bug_text(error: BaseException) -> str:
    """Log a bug with its traceback; the one line to show for it."""
    path = log_path()
    stamp = datetime.datetime.now().isoformat(timespec="seconds")
    trace = "".join(traceback.format_exception(type(error), error, error.__traceback__))
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with path.open("a", encoding="utf-8") as log:
            log.write(f"--- {stamp}\n{trace}\n")
        where = f"SEE {path}"
    except OSError:
        where = "THE LOG FILE COULD NOT BE WRITTEN"
    return upper_case(f"*** INTERNAL ERROR ({type(error).__name__}: {error}); {where}")


def upper_case(text: str) -> str:
    """A message in the VS11's upper case, file paths kept as they are (they are case-sensitive)."""
    return " ".join(word if word.startswith(("/", "~", "./")) else word.upper() for word in text.split(" "))


def problem_text(error: Exception) -> str:
    """The line to show for any exception: a refusal's message, or a logged bug's line."""
    return error_text(error) if isinstance(error, ValtermError) else bug_text(error)


class Refusal(ValtermError):
    """A typed answer the app itself cannot take (a menu's own question), shown like the core's."""
