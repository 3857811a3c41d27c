"""The one error every reader of a workspace file raises: located, never a traceback."""

from __future__ import annotations

from pathlib import Path

from valterm.core.errors import ValtermError


class FileProblem(ValtermError):
    """A file the program could not use, named as a message shows it: ``NAME.SET:12: reason``
    (``NAME.SET: reason`` when ``line`` is 0, the whole file)."""

    def __init__(self, path: str | Path, reason: str, line: int = 0) -> None:
        self.path = Path(path)
        self.line = int(line)
        self.reason = reason
        super().__init__(str(self))

    @property
    def name(self) -> str:
        return shown_name(self.path.name or str(self.path))

    def __str__(self) -> str:
        if self.line > 0:
            return f"{self.name}:{self.line}: {self.reason}"
        return f"{self.name}: {self.reason}"


class FileFormatError(FileProblem):
    """A file that cannot be read as what it should be.

    ``line`` is 1-based; 0 means the whole file (empty, too large, unreadable).
    ``str()`` is ``NAME.SET:12: reason`` (``NAME.SET: reason`` for line 0), the form
    compilers use, so the message can be shown as it is.
    """

    def __init__(self, path: str | Path, line: int, reason: str) -> None:
        super().__init__(path, reason, line)


class BadName(ValtermError, ValueError):
    """A name (typed or read) that is not a VAL-II name; ``str()`` says why."""


class FileWriteError(FileProblem, OSError):
    """A file the program will not or cannot write: ``NAME.SET: reason``.

    Raised for a target that is a symbolic link (never written through), a folder or a
    device, and for a disk that refuses (full, read-only, no permission). It is an OSError
    too, so code that already catches failed writes keeps catching it.
    """

    def __init__(self, path: str | Path, reason: str) -> None:
        super().__init__(path, reason)


class NotAFile(FileProblem, OSError):
    """A path that is there but is no regular file: a folder, a FIFO, a device, a socket (or a
    symbolic link where links are refused). Never read: a FIFO blocks for ever, /dev/zero never
    ends. ``kind`` names it (``a FIFO (a named pipe)``); an OSError too, as a failed read is."""

    def __init__(self, path: str | Path, kind: str) -> None:
        self.kind = kind
        super().__init__(path, f"is {kind}, not a regular file")


class FileChanged(FileProblem):
    """A save refused because the file changed on disk since this session read it (another
    session saved it): nothing was written. The UI asks: overwrite, reload or save as."""

    def __init__(self, path: str | Path) -> None:
        super().__init__(path, "changed on disk since this session read it (another session saved it)")


# Names echoed in messages are cut to this many characters: a 10 000-character name typed
# or planted in a file is shown as its start, not as a screenful.
SHOWN_NAME = 40


def shown_name(name: str, limit: int = SHOWN_NAME) -> str:
    """``name`` as a message shows it: whole up to ``limit`` characters, else its start and '...'."""
    return name if len(name) <= limit else name[:limit] + "..."


def error_message(error: BaseException) -> str:
    """The one line an edge prints for ``error``: a ValtermError's own message; an OSError as
    ``NAME: reason`` with the name cut (``[Errno 36] File name too long: '<10 000 characters>'``
    is not a message)."""
    if isinstance(error, OSError) and not isinstance(error, ValtermError) and error.strerror:
        if error.filename is None:
            return error.strerror
        return f"{shown_name(str(error.filename))}: {error.strerror}"
    return str(error)
