"""The picture of the last start, kept (issue 40: the picture at start).

``valterm --setup NAME`` shows MAIN MENU in its first frame and the model's picture once the
set-up is read, which loads numpy, the simulator and the raster (about 90 ms after the menu,
most of it numpy's import). The picture the app drew at its last start is kept in the user's
cache with what it was drawn from: the set-up file's bytes, the robot, the rules, the view's
options, and the program's own files (their sizes and times: a new version or an edited
module draws afresh). A start from the same shows the kept picture in its first frame, beside
the menu; the picture drawn once the set-up is read (the same, cell for cell) replaces it.

A cache only: a missing, unreadable or stale file is no kept picture, and one that cannot be
written is not kept. Neither numpy nor the raster loads here.
"""

from __future__ import annotations

import os
import zlib
from functools import cache
from pathlib import Path

from valterm.core.files.atomic import write_bytes_atomic

FORMAT = "valterm start picture 1"
FILE_NAME = "start-picture"
MAX_BYTES = 16 * 1024 * 1024  # a picture of a 1000x300 terminal is about 2 MB
Runs = tuple[tuple[int, int], ...]  # (colour, cells) along a row


class KeptPicture:
    """A picture as the model view painted it: each row's text and its colours' runs."""

    __slots__ = ("height", "key", "rows", "width")

    def __init__(self, key: str, width: int, rows: list[tuple[str, Runs]]) -> None:
        self.key = key
        self.width = width
        self.height = len(rows)
        self.rows = rows

    def __eq__(self, other: object) -> bool:
        return (isinstance(other, KeptPicture) and (self.key, self.width, self.rows)
                == (other.key, other.width, other.rows))

    __hash__ = None  # type: ignore[assignment]  # mutable rows: not a dict key

    def fits(self, width: int, height: int) -> bool:
        return (self.width, self.height) == (width, height)


def cache_path() -> Path:
    """``$XDG_CACHE_HOME/valterm/start-picture`` (``~/.cache`` when unset)."""
    cache = os.environ.get("XDG_CACHE_HOME") or str(Path("~/.cache").expanduser())
    return Path(cache) / "valterm" / FILE_NAME


@cache  # the code this process runs: one walk of the package a start, not one a read and a keep
def code_stamp() -> str:
    """The package's own files and the bundled robot files as they were when first asked
    (names, sizes, times): a picture drawn by other code is not shown."""
    from valterm import __version__
    from valterm.core import resources

    stamp = zlib.crc32(__version__.encode())
    for top in (resources.PACKAGE_DIR, resources.data_path("robot")):
        stamp = _tree_stamp(top, stamp)
    return f"{stamp:08x}"


def _tree_stamp(folder: Path, stamp: int) -> int:
    try:
        entries = sorted(os.scandir(folder), key=lambda e: e.name)
    except OSError:
        return zlib.crc32(b"?", stamp)
    for entry in entries:
        if entry.name == "__pycache__":
            continue
        if entry.is_dir(follow_symlinks=False):
            stamp = _tree_stamp(Path(entry.path), stamp)
        else:
            info = entry.stat(follow_symlinks=False)
            stamp = zlib.crc32(f"{entry.name}:{info.st_size}:{info.st_mtime_ns};".encode(), stamp)
    return stamp


def start_key(setup: bytes, **drawn_with: object) -> str:
    """What a start's picture is drawn from: the set-up file's bytes, the options given
    (robot, rules, view options) and the code."""
    options = ",".join(f"{name}={value}" for name, value in sorted(drawn_with.items()))
    return f"{zlib.crc32(setup):08x}:{len(setup)}|{options}|code={code_stamp()}"


def read_kept(path: Path, key: str) -> KeptPicture | None:
    """The picture kept at ``path`` if it was drawn from ``key``, else None."""
    from valterm.core.errors import ValtermError
    from valterm.core.files._text import read_bytes

    try:  # opened as every file is read: a FIFO or a device is no picture, never waited on
        text = read_bytes(path, "kept picture", limit=MAX_BYTES).decode("utf-8")
    except (ValtermError, UnicodeDecodeError):
        return None
    lines = text.split("\n")
    if len(lines) < 3 or lines[0] != FORMAT or lines[1] != key:
        return None
    try:
        width = int(lines[2])
        rows = [_row(line, width) for line in lines[3:] if line]
    except ValueError:  # cut short or changed by hand: drawn afresh
        return None
    return KeptPicture(key, width, rows)


def _row(line: str, width: int) -> tuple[str, Runs]:
    text, _, coded = line.rpartition("\t")
    runs = tuple((int(colour), int(cells)) for colour, cells in
                 (run.split(":") for run in coded.split(" ")))
    if len(text) != width or sum(cells for _, cells in runs) != width:
        raise ValueError("a row of the wrong width")
    if not text.isprintable():  # painted as it is: no control sequence reaches the terminal
        raise ValueError("a control character in a row")
    return text, runs


def write_kept(path: Path, picture: KeptPicture) -> bool:
    """Keep ``picture`` at ``path`` (its folder made); False when it cannot be written."""
    from valterm.core.errors import ValtermError

    rows = (f"{text}\t{' '.join(f'{c}:{n}' for c, n in runs)}" for text, runs in picture.rows)
    data = "\n".join([FORMAT, picture.key, str(picture.width), *rows, ""]).encode("utf-8")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        write_bytes_atomic(path, data)
    except (OSError, ValtermError):  # a read-only or full cache: the next start draws afresh
        return False
    return True


def runs_of(colours: list[int]) -> Runs:
    """A row's colours, cell by cell, as runs."""
    runs: list[tuple[int, int]] = []
    for colour in colours:
        if runs and runs[-1][0] == colour:
            runs[-1] = (colour, runs[-1][1] + 1)
        else:
            runs.append((colour, 1))
    return tuple(runs)
