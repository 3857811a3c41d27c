"""The one error of CAD import: a located, one-line reason (never a traceback)."""

from __future__ import annotations

import os
from pathlib import Path

from valterm.core.errors import ValtermError


class CadImportError(ValtermError, ValueError):
    """A CAD file that cannot be imported: ``file:line: reason`` (line omitted when unknown)."""

    def __init__(self, path: str | Path, line: int | None, reason: str) -> None:
        self.path = str(path)
        self.line = line
        self.reason = reason
        where = f"{self.path}:{line}" if line is not None else self.path
        super().__init__(f"{where}: {reason}")


def read_cad_bytes(path: str | Path) -> bytes:
    """A CAD file's bytes, or CadImportError saying it is missing or unreadable."""
    from valterm.core.files.atomic import open_regular
    from valterm.core.files.errors import NotAFile

    path = Path(path)
    try:
        handle, _info = open_regular(path)  # the one read path: a FIFO or a device is refused
        with handle:
            return handle.read()
    except FileNotFoundError:
        raise CadImportError(path, None, "no such file") from None
    except NotAFile as error:
        raise CadImportError(path, None, error.reason) from None
    except OSError as error:
        raise CadImportError(path, None, f"cannot read the file: {error.strerror or error}") from None


def check_cad_file(path: str | Path) -> None:
    """The file is there and is a regular file (CadImportError at once for a FIFO or a device:
    for the readers that open it by name, a STEP library's)."""
    from valterm.core.files.atomic import file_kind

    try:
        kind = file_kind(os.stat(path).st_mode)
    except OSError:
        raise CadImportError(path, None, "no such file") from None
    if kind is not None:
        raise CadImportError(path, None, f"is {kind}, not a regular file")


class DegeneratePart(ValtermError, ValueError):
    """A part whose points enclose no area (coincident or collinear): the reason is the message."""


class CadExportError(ValtermError, ValueError):
    """A scene that cannot be exported (unknown format, nothing to write): the reason is the message."""
