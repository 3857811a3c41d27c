"""Atomic writes (SPEC §5): a crash or a full disk never leaves a file truncated."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from valterm.core.files.errors import FileWriteError


def write_text_atomic(path: str | Path, text: str, encoding: str = "utf-8") -> None:
    """Write ``text`` to ``path`` through a temporary file in the same folder, then rename.

    The temporary file lives beside the target so ``os.replace`` is a same-filesystem
    rename: readers see either the old file or the new one, never a part of either.
    """
    target = Path(path)
    data = text.encode(encoding, errors="strict")
    try:
        _write_replace(target, data)
    except OSError as error:  # the disk or the folder refused: say which file, and why
        raise FileWriteError(f"{target.name}: cannot write the file: {error.strerror or error}") from error
    _fsync_folder(target.parent)


def _write_replace(target: Path, data: bytes) -> None:
    fd, temp_name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(data)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(temp_name, target)
    except BaseException:
        try:
            os.unlink(temp_name)
        except OSError:
            pass
        raise


def _fsync_folder(folder: Path) -> None:
    """Make the rename itself durable where the platform allows it (not on Windows)."""
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)
