"""The last resort for bugs: an unexpected exception's traceback goes to a log file, the
user gets one line naming it.

Errors the program means (``ValtermError``) are messages, never logged. Anything else that
reaches the command line or the app is a bug; its full traceback is written to
``$XDG_STATE_HOME/valterm/crash-<time>-<pid>.log`` (``~/.local/state/valterm`` when the
variable is unset; the system's temporary folder if that cannot be written).
"""

from __future__ import annotations

import os
import platform
import sys
import tempfile
import time
import traceback
from pathlib import Path

# Exit status of a bug (BSD sysexits EX_SOFTWARE): scripts can tell it from a refusal (1).
EXIT_BUG = 70

_MAX_SHOWN = 160  # characters of the exception's text on the one line


def log_folder() -> Path:
    """Where crash logs go (see the module docstring)."""
    state = os.environ.get("XDG_STATE_HOME") or str(Path("~/.local/state").expanduser())
    return Path(state) / "valterm"


def write_crash_log(error: BaseException) -> Path | None:
    """Write ``error``'s traceback with the version and command line; the file, or None."""
    from valterm import version

    text = "".join(traceback.format_exception(error))
    header = (
        f"valterm {version()} on Python {platform.python_version()} ({platform.platform()})\n"
        f"time: {time.strftime('%Y-%m-%d %H:%M:%S %z')}\n"
        f"command: {' '.join(sys.argv)}\n\n"
    )
    name = f"crash-{time.strftime('%Y%m%d-%H%M%S')}-{os.getpid()}.log"
    for folder in (log_folder(), Path(tempfile.gettempdir()) / "valterm"):
        try:
            folder.mkdir(parents=True, exist_ok=True)
            path = folder / name
            # exclusive create: never write through a planted file or link
            with open(path, "x", encoding="utf-8") as log:
                log.write(header + text)
            return path
        except OSError:
            continue
    return None


def crash_line(error: BaseException, log: Path | None) -> str:
    """The one line the user sees for a bug."""
    what = f"{type(error).__name__}: {error}".strip().rstrip(":")
    what = " ".join(what.split())
    if len(what) > _MAX_SHOWN:
        what = what[: _MAX_SHOWN - 3] + "..."
    where = f"the traceback is in {log}" if log else "no log file could be written"
    return f"valterm: internal error ({what}); {where}"


def report_crash(error: BaseException) -> int:
    """Log ``error``, print the one line on stderr, and give the exit status of a bug."""
    log = write_crash_log(error)
    print(crash_line(error, log), file=sys.stderr)
    return EXIT_BUG
