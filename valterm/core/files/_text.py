"""Reading a workspace file as text, refusing what is not text before parsing it."""

from __future__ import annotations

import errno
import re
from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

from valterm.core import numbers
from valterm.core.files.atomic import open_regular
from valterm.core.files.errors import FileFormatError, NotAFile
from valterm.core.files.limits import MAX_FILE_BYTES, MAX_LINE
from valterm.core.numbers import MAX_MAGNITUDE, NumberError

Parsed = TypeVar("Parsed")

# Control characters other than tab, newline, carriage return and form feed mark binary junk.
_JUNK = re.compile(r"[\x00-\x08\x0b\x0e-\x1f\x7f]")



def read_parsed(path: str | Path, what: str, parse: Callable[[str, Path], Parsed]) -> Parsed:
    """A ``what`` file read as text (the checks of ``read_text``) and given to ``parse``."""
    path = Path(path)
    return parse(read_text(path, what), path)


def read_text(path: str | Path, what: str, limit: int = MAX_FILE_BYTES, eight_bit: bool = False) -> str:
    """The file's text, or a FileFormatError saying why it is not a readable ``what`` file.

    ``eight_bit``: bytes that are not UTF-8 are read as latin-1 (V+ files written on a
    controller or an old PC carry comments in some 8-bit code page)."""
    return decode_text(read_bytes(path, what, limit), path, what, eight_bit)


def read_bytes(path: str | Path, what: str, limit: int = MAX_FILE_BYTES, follow_links: bool = True) -> bytes:
    """The file's bytes, refused as ``read_text`` refuses them (missing, a folder, a FIFO or a
    device, too large, unreadable): for a reader that keeps the bytes too (a session stamps its
    set-up file from the bytes it parsed, ``valterm.core.session``). Opened the one way,
    :func:`~valterm.core.files.atomic.open_regular` (``follow_links=False``: a link is refused)."""
    path = Path(path)
    try:
        handle, info = open_regular(path, follow_links)
    except FileNotFoundError:
        raise FileFormatError(path, 0, f"no such {what} file") from None
    except NotAFile as error:
        raise FileFormatError(path, 0, f"is {error.kind}, not a {what} file") from None
    except OSError as error:
        if error.errno == errno.ELOOP and not follow_links:  # swapped for a link after the look
            raise FileFormatError(path, 0, f"is a symbolic link, not a {what} file") from None
        if path.is_dir():  # Windows opens no folder
            raise FileFormatError(path, 0, f"is a folder, not a {what} file") from None
        raise FileFormatError(path, 0, f"cannot read the {what} file: {error.strerror or error}") from None
    with handle:
        if info.st_size > limit:
            raise FileFormatError(path, 0,
                                  f"{_size(info.st_size)} is too large for a {what} file (limit {_size(limit)})")
        try:
            data = handle.read(limit + 1)  # a file that grew or lied about its size stops here
        except OSError as error:
            raise FileFormatError(path, 0, f"cannot read the {what} file: {error.strerror or error}") from None
    if len(data) > limit:
        raise FileFormatError(path, 0, f"too large for a {what} file (limit {_size(limit)})")
    return data


def decode_text(data: bytes, path: str | Path, what: str, eight_bit: bool = False) -> str:
    """Bytes to text: UTF-8 (plain ASCII in practice), no binary junk; ``eight_bit``:
    latin-1 when the bytes are not UTF-8."""
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as error:
        if eight_bit:
            text = data.decode("latin-1")
            check_text(text, path, what)
            return text
        line = data.count(b"\n", 0, error.start) + 1
        raise FileFormatError(path, line,
                              f"not a text {what} file (undecodable byte 0x{data[error.start]:02X})") from None
    check_text(text, path, what)
    return text


def check_text(text: str, path: str | Path, what: str) -> None:
    """Refuse NUL bytes and other control characters with the line they are on."""
    junk = _JUNK.search(text)
    if junk is not None:
        line = text.count("\n", 0, junk.start()) + 1
        raise FileFormatError(path, line, f"not a text {what} file (control character 0x{ord(junk.group()):02X})")


def numbered_lines(text: str) -> list[tuple[int, str]]:
    """(1-based line number, line without its end) for every line, tabs expanded to column 5 stops."""
    return [(number, line.expandtabs(4)) for number, line in enumerate(text.splitlines(), start=1)]


def split_fields(line: str) -> list[str]:
    """Fields separated by commas and/or spaces (App. C §4: "separated by commas or spaces")."""
    return [field for field in re.split(r"[,\s]+", line.strip()) if field]


def parse_number(field: str, path: str | Path, line: int, what: str, limit: float = MAX_MAGNITUDE) -> float:
    """One number, Fortran style (valterm.core.numbers), or a located error naming the field."""
    try:
        return numbers.parse_number(field, limit)
    except NumberError as error:
        raise FileFormatError(path, line, f"{what}: {error}") from None


def parse_count(field: str, path: str | Path, line: int, what: str, limit: int) -> int:
    """A whole number 0..limit (a count, a vertex number), or a located error."""
    try:
        return numbers.parse_count(field, limit, what)
    except NumberError as error:
        raise FileFormatError(path, line, str(error)) from None


def check_line_lengths(text: str, path: str | Path, what: str, limit: int = MAX_LINE) -> None:
    """Refuse the first line longer than ``limit`` characters, with its number."""
    for number, line in enumerate(text.splitlines(), start=1):
        if len(line) > limit:
            raise FileFormatError(path, number,
                                  f"line is {len(line)} characters long (at most {limit} in a {what} file)")


def format_number(value: float) -> str:
    """Thesis style (`440.00`) when two decimals hold the value exactly, else the shortest exact form."""
    value = float(value) + 0.0  # no "-0.00"
    two = round(value, 2)
    if abs(value - two) <= 1e-9:
        return f"{two + 0.0:.2f}"
    return repr(value)


def _size(size: int) -> str:
    if size >= 1024 * 1024:
        return f"{size / (1024 * 1024):.1f} MB"
    if size >= 1024:
        return f"{size / 1024:.1f} KB"
    return f"{size} bytes"
