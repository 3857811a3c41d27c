"""Session records (issue 38 item 6): every key a person typed, with its time, and the lines
the screens showed, so an instructor can read a student's session and replay it
(``valterm --record FILE``, ``valterm replay FILE``).

A record is append-only JSON Lines, written as the session goes: each line one object,
written whole with one ``write`` on an unbuffered descriptor, so a session killed at any
moment (kill -9 included) leaves every line written before it (at most the last one cut,
which the reader skips). The first line says what the session was started with:

    {"valterm": "record", "version": 1, "started": "2026-11-28T19:42:36", "keys": "modern",
     "setup": "PROCESS", "rules": null, "robot": null, "size": [120, 40]}
    {"t": 1.204, "key": "e", "char": "e", "busy": false}
    {"t": 1.251, "line": "PROCESS.SET READ"}
    {"t": 2.5, "paste": "MOVE P1", "busy": false}
    {"t": 93.4, "end": 0}

``t`` is seconds since the start (the monotonic clock); ``busy``: the app was playing a
motion or holding typed-ahead keys when the key came (a replay then presses it without
waiting for the app to settle). The record is a new file: never one that exists, never
through a link, never a FIFO or a device (it cannot use the atomic whole-file write of
``atomic.py``, being written line by line, so it makes the same refusals itself).
"""

from __future__ import annotations

import errno
import json
import os
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from valterm.core.files._text import read_text
from valterm.core.files.atomic import check_writable
from valterm.core.files.errors import FileFormatError, FileWriteError

FORMAT = "record"
VERSION = 1
MAX_LINES_BYTES = 50 * 1024 * 1024  # the transcript's share: a TYPE loop for hours stops here
MAX_BYTES = 2 * MAX_LINES_BYTES      # keys go on to here (then nothing more is written)
MAX_READ = MAX_BYTES + 1024 * 1024   # the largest record a replay reads
_OPEN = (os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_APPEND | getattr(os, "O_NOFOLLOW", 0)
         | getattr(os, "O_CLOEXEC", 0) | getattr(os, "O_BINARY", 0))


class RecordError(FileFormatError):
    """A record that cannot be replayed: ``S.REC:3: reason``."""


@dataclass(frozen=True)
class RecordedKey:
    """One key as typed: Textual's key name, the character it typed (None for a named key
    such as ``enter``), when (seconds since the start) and whether the app was busy; or a
    paste (``paste`` its text, ``key`` "paste")."""

    at: float
    key: str
    char: str | None
    busy: bool
    paste: str | None = None


@dataclass
class Record:
    """A record read back: the header's settings, the keys and the lines shown, in order."""

    header: dict[str, Any]
    keys: list[RecordedKey] = field(default_factory=list)
    lines: list[str] = field(default_factory=list)
    ended: int | None = None  # the exit status, None when the session was cut off (killed)

    @property
    def seconds(self) -> float:
        return self.keys[-1].at if self.keys else 0.0


class SessionRecord:
    """The record being written: ``key`` and ``shown`` append a line each, at once."""

    def __init__(self, path: str | Path, header: dict[str, Any],
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.path = Path(path)
        self.clock = clock
        self.started = clock()
        self.written = 0
        self.failure: str | None = None  # why recording stopped (the disk refused), said at exit
        self._cut = False
        self._fd = _open_new(self.path)
        self._write({"valterm": FORMAT, "version": VERSION,
                     "started": time.strftime("%Y-%m-%dT%H:%M:%S"), **header})

    def key(self, key: str, char: str | None, busy: bool) -> None:
        self._write({"t": self._now(), "key": key, "char": char, "busy": busy})

    def paste(self, text: str, busy: bool) -> None:
        """Text pasted (the terminal's bracketed paste): replayed as one paste."""
        self._write({"t": self._now(), "paste": text, "busy": busy})

    def shown(self, lines: list[str]) -> None:
        """Lines a screen showed (the transcript), each its own record line, all in one write
        (a program that prints in a loop hands hundreds a tick)."""
        if self.written > MAX_LINES_BYTES:
            if not self._cut:
                self._cut = True
                self._write({"t": self._now(), "cut": f"the transcript stops here ({MAX_LINES_BYTES} bytes)"})
            return
        now = self._now()
        self._write(*({"t": now, "line": line} for line in lines))

    def close(self, status: int = 0) -> None:
        if self._fd >= 0:
            self._write({"t": self._now(), "end": status})
            os.close(self._fd)
            self._fd = -1

    def _now(self) -> float:
        return round(self.clock() - self.started, 3)

    def _write(self, *entries: dict[str, Any]) -> None:
        if self._fd < 0 or self.written > MAX_BYTES or not entries:
            return
        data = "".join(json.dumps(entry, ensure_ascii=False) + "\n" for entry in entries).encode(
            "utf-8", errors="replace")
        try:
            view = memoryview(data)
            while view:  # unbuffered: in the file (the kernel's) once this returns
                view = view[os.write(self._fd, view):]
        except OSError as error:
            self.failure = f"{self.path}: recording stopped: {error.strerror or error}"
            os.close(self._fd)
            self._fd = -1
            return
        self.written += len(data)


def _open_new(path: Path) -> int:
    """A new file at ``path``, opened for appending; FileWriteError for a link, a FIFO, a
    device, a folder or a file that exists (a record is never written over)."""
    check_writable(path)  # says what a link, a folder or a device is
    try:
        return os.open(path, _OPEN, 0o600)
    except FileExistsError:
        raise FileWriteError(path, "exists; a record is never written over (choose a new name)") from None
    except OSError as error:
        if error.errno == errno.ELOOP:
            raise FileWriteError(path, "is a symbolic link; refusing to write through it") from None
        raise FileWriteError(path, f"cannot write the record: {error.strerror or error}") from None


def read_record(path: str | Path) -> Record:
    """The record at ``path``; RecordError saying where it is not one. A last line cut short
    (the session was killed while writing it) is skipped."""
    path = Path(path)
    try:
        text = read_text(path, "record", limit=MAX_READ)
    except RecordError:
        raise
    except FileFormatError as error:  # missing, a FIFO, too large, not text: the record's error
        raise RecordError(path, error.line, error.reason) from None
    raw = text.split("\n")
    if raw and raw[-1] == "":
        raw.pop()
    elif raw:
        raw.pop()  # no newline after it: cut off mid-write
    if not raw:
        raise RecordError(path, 0, "is empty (not a valterm record)")
    header = _entry(raw[0], 1, path)
    if header.get("valterm") != FORMAT or header.get("version") != VERSION:
        raise RecordError(path, 1, f"is not a valterm record of version {VERSION}")
    record = Record(header)
    for number, line in enumerate(raw[1:], start=2):
        _add(record, _entry(line, number, path), number, path)
    return record


def _entry(line: str, number: int, path: Path) -> dict[str, Any]:
    try:
        entry = json.loads(line)
    except (ValueError, RecursionError):
        raise RecordError(path, number, "is not a JSON object") from None
    if not isinstance(entry, dict):
        raise RecordError(path, number, "is not a JSON object")
    return entry


def _add(record: Record, entry: dict[str, Any], number: int, path: Path) -> None:
    at = entry.get("t")
    if isinstance(at, bool) or not isinstance(at, (int, float)) or not 0 <= at < 1e9:
        raise RecordError(path, number, "has no time (t) in seconds")
    if "key" in entry:
        key, char = entry["key"], entry.get("char")
        if not isinstance(key, str) or not key or not (char is None or isinstance(char, str)):
            raise RecordError(path, number, "a key is a name and a character")
        record.keys.append(RecordedKey(float(at), key, char, bool(entry.get("busy", False))))
    elif "paste" in entry:
        if not isinstance(entry["paste"], str):
            raise RecordError(path, number, "a paste is a text")
        record.keys.append(RecordedKey(float(at), "paste", None, bool(entry.get("busy", False)), entry["paste"]))
    elif isinstance(entry.get("line"), str):
        record.lines.append(entry["line"])
    elif "end" in entry:
        record.ended = entry["end"] if isinstance(entry["end"], int) else None
