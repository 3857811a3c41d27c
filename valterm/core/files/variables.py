"""CHECK.DAT, the VAL-II variables and their values (§6.7), kept across sessions.

One ``NAME=value`` a line (the thesis's own form: "ROW=10"). An empty file holds no
variables. Names are a letter then up to 8 letters, digits, ``_`` or ``.``.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

from valterm.core.files._text import (
    check_line_lengths,
    numbered_lines,
    parse_number,
    read_text,
)
from valterm.core.files.atomic import write_text_atomic
from valterm.core.files.errors import FileFormatError, FileWriteError, shown_name
from valterm.core.files.limits import MAX_VARIABLES
from valterm.core.numbers import MAX_FINITE

CHECK = "CHECK.DAT"

VARIABLE_NAME = re.compile(r"[A-Z][A-Z0-9_.]{0,8}")


def check_variable_name(name: str) -> str:
    """The name upper-cased, or ValueError saying why it is not a variable name."""
    upper = name.strip().upper()
    if not VARIABLE_NAME.fullmatch(upper):
        raise ValueError(f"{shown_name(name)!r} is not a variable name: a letter then up to 8 letters or digits")
    return upper


def parse_variables(text: str, path: str | Path = CHECK) -> dict[str, float]:
    """{NAME: value} from CHECK.DAT text; a later line with the same name wins."""
    values: dict[str, float] = {}
    check_line_lengths(text, path, "variables")
    for number, line in numbered_lines(text):
        entry = line.strip()
        if not entry or entry.startswith(";"):
            continue
        name, equals, value = entry.partition("=")
        if not equals:
            raise FileFormatError(path, number, f"expected NAME=value, not {entry[:40]!r}")
        try:
            variable = check_variable_name(name)
        except ValueError as error:
            raise FileFormatError(path, number, str(error)) from None
        if variable not in values and len(values) >= MAX_VARIABLES:
            raise FileFormatError(path, number, f"more than {MAX_VARIABLES} variables")
        # any finite value: what a program computed must read back
        values[variable] = parse_number(value.strip(), path, number, variable, MAX_FINITE)
    return values


def read_variables(path: str | Path) -> dict[str, float]:
    """Read CHECK.DAT (FileFormatError if malformed)."""
    path = Path(path)
    return parse_variables(read_text(path, "variables"), path)


def format_value(value: float) -> str:
    """``10`` for whole numbers (as typed: ROW=10), else the shortest exact decimal."""
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"{value} cannot be stored as a VAL-II variable")
    if value.is_integer() and abs(value) < 1e15:
        return str(int(value))
    return repr(value)


def format_variables(values: dict[str, float]) -> str:
    return "".join(f"{check_variable_name(name)}={format_value(value)}\n" for name, value in values.items())


def write_variables(path: str | Path, values: dict[str, float]) -> None:
    """Write CHECK.DAT atomically; FileWriteError (nothing written) for a value no file can hold,
    or more variables than its reader takes (a file written over the limit stopped every later
    run in the workspace: issue 38)."""
    if len(values) > MAX_VARIABLES:
        raise FileWriteError(path, f"{len(values)} variables cannot be kept: at most {MAX_VARIABLES} "
                                   "(nothing was written)")
    for name, value in values.items():
        if not math.isfinite(float(value)):
            raise FileWriteError(path, f"{shown_name(name)}={value} cannot be kept: not a finite number")
    write_text_atomic(path, format_variables(values))
