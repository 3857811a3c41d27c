"""The one error every reader of a workspace file raises: located, never a traceback."""

from __future__ import annotations

from pathlib import Path

from valterm.core.errors import ValtermError


class FileFormatError(ValtermError):
    """A file that cannot be read as what it should be.

    ``line`` is 1-based; 0 means the whole file (empty, too large, unreadable).
    ``str()`` is ``NAME.SET:12: reason`` (``NAME.SET: reason`` for line 0), the form
    compilers use, so the message can be shown as it is.
    """

    def __init__(self, path: str | Path, line: int, reason: str) -> None:
        self.path = Path(path)
        self.line = int(line)
        self.reason = reason
        super().__init__(str(self))

    @property
    def name(self) -> str:
        return self.path.name or str(self.path)

    def __str__(self) -> str:
        if self.line > 0:
            return f"{self.name}:{self.line}: {self.reason}"
        return f"{self.name}: {self.reason}"


class BadName(ValtermError, ValueError):
    """A name (typed or read) that is not a VAL-II name; ``str()`` says why."""


class FileWriteError(ValtermError, OSError):
    """A file that could not be written (no space, no permission); nothing was half-written."""
