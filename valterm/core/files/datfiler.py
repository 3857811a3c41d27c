"""DATFILER.DAT, the directory of VAL-II programs (§5.1): one ``NAME.DAT`` a line.

The editor opens it to learn whether a program is new, and adds the name of a new one.
An empty file is an empty directory. Names are read with or without ``.DAT``.
"""

from __future__ import annotations

import re
from pathlib import Path

from valterm.core.files._text import check_line_lengths, numbered_lines, read_text
from valterm.core.files.atomic import folder_lock, write_text_atomic
from valterm.core.files.errors import FileFormatError, shown_name

DATFILER = "DATFILER.DAT"

_ENTRY = re.compile(r"([A-Z0-9]{1,9})(?:\.DAT)?")


def parse_datfiler(text: str, path: str | Path = DATFILER) -> list[str]:
    """Program names (upper case, no extension) in file order, each once."""
    names: list[str] = []
    check_line_lengths(text, path, "program directory")
    for number, line in numbered_lines(text):
        entry = line.strip().upper()
        if not entry or entry.startswith(";"):
            continue
        match = _ENTRY.fullmatch(entry)
        if match is None:
            raise FileFormatError(
                path, number, f"{shown_name(line.strip())!r} is not a program name (1-9 letters or digits, then .DAT)")
        if match.group(1) not in names:
            names.append(match.group(1))
    return names


def read_datfiler(path: str | Path) -> list[str]:
    """Read the program directory (FileFormatError if malformed)."""
    path = Path(path)
    return parse_datfiler(read_text(path, "program directory"), path)


def format_datfiler(names: list[str]) -> str:
    lines = []
    for name in names:
        upper = name.upper().removesuffix(".DAT")
        if not _ENTRY.fullmatch(upper):
            raise ValueError(f"{shown_name(name)!r} is not a program name (1-9 letters or digits)")
        entry = f"{upper}.DAT"
        if entry not in lines:
            lines.append(entry)
    return "".join(f"{line}\n" for line in lines)


def write_datfiler(path: str | Path, names: list[str]) -> None:
    """Write the program directory atomically."""
    write_text_atomic(path, format_datfiler(names))


def add_program_name(path: str | Path, name: str) -> bool:
    """Add ``name`` to the directory (created if missing); False when it was already listed."""
    path = Path(path)
    with folder_lock(path.parent):  # two sessions adding programs at once both stay listed
        names = read_datfiler(path) if path.exists() else []
        upper = name.upper().removesuffix(".DAT")
        if upper in names:
            return False
        write_datfiler(path, [*names, upper])
    return True


def remove_program_name(path: str | Path, name: str) -> bool:
    """Take ``name`` off the directory (a new program left unsaved); False when it was not listed."""
    path = Path(path)
    with folder_lock(path.parent):  # another session's addition meanwhile stays listed
        names = read_datfiler(path) if path.exists() else []
        upper = name.upper().removesuffix(".DAT")
        if upper not in names:
            return False
        write_datfiler(path, [n for n in names if n != upper])
    return True
