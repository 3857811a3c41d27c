"""The one error of CAD import: a located, one-line reason (never a traceback)."""

from __future__ import annotations

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
    path = Path(path)
    if not path.is_file():
        raise CadImportError(path, None, "no such file")
    try:
        return path.read_bytes()
    except OSError as error:
        raise CadImportError(path, None, f"cannot read the file: {error.strerror or error}") from None


class DegeneratePart(ValtermError, ValueError):
    """A part whose points enclose no area (coincident or collinear): the reason is the message."""


class CadExportError(ValtermError, ValueError):
    """A scene that cannot be exported (unknown format, nothing to write): the reason is the message."""
