"""What the app shows when something fails: the core's refusals, and bugs.

A ``ValtermError`` is a refusal the user can act on: its message is shown, upper case as on
the VS11. Anything else is a bug: it is written with its traceback to the log file and shown
as one line that says where the details are. No built-in exception is taken for a refusal.
"""

from __future__ import annotations

from valterm.core.crashlog import write_crash_log
from valterm.core.errors import MotionRefused, ValtermError


def error_text(error: ValtermError) -> str:
    """The message of a core refusal, upper case as on the VS11."""
    text = (str(error).strip() or type(error).__name__).upper()
    return f"MOTION REFUSED: {text}" if isinstance(error, MotionRefused) else text


def bug_text(error: BaseException) -> str:
    """Log a bug with its traceback (the one crash log, ``core/crashlog.py``); the line to show."""
    path = write_crash_log(error)
    where = f"SEE {path}" if path is not None else "THE LOG FILE COULD NOT BE WRITTEN"
    return upper_case(f"*** INTERNAL ERROR ({type(error).__name__}: {error}); {where}")


def upper_case(text: str) -> str:
    """A message in the VS11's upper case, file paths kept as they are (they are case-sensitive)."""
    return " ".join(word if word.startswith(("/", "~", "./")) else word.upper() for word in text.split(" "))


def problem_text(error: Exception) -> str:
    """The line to show for any exception: a refusal's message, or a logged bug's line."""
    return error_text(error) if isinstance(error, ValtermError) else bug_text(error)


class Refusal(ValtermError):
    """A typed answer the app itself cannot take (a menu's own question), shown like the core's."""
