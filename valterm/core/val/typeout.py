"""TYPE's output list: quoted text, values and V+ formats (``TYPE "X=", X /F8.2``).

The 1985 simulator typed the rest of the line as it was (``TYPE PICK UP THE PART``,
section 6.6.2) or a variable's value (``TYPE COL=``); a list that starts with a quote is
an output list as on the real controller: quoted text is typed without its quotes, an
expression is typed as its value, and a format (Adept V+ reference, TYPE) changes how
the values after it are written:

- ``/Fw.d`` fixed point, ``/Ew.d`` exponent, ``/Iw`` whole number, ``/Hw`` hexadecimal,
  ``/D`` back to the default (w is the width, right-aligned);
- ``/Xn`` n blanks, ``/Cn`` n line breaks, ``/S`` no line break at the end (V+: the next
  TYPE goes on on the same line), ``/Un`` n lines up, ``/Bn`` n beeps (the last two ignored:
  the transcript is line based and silent).

In the v+ dialect (``dialects/vplus/expr.render_output``) two values typed one after the other in the
default format are separated by a blank (``TYPE a, b`` types ``1 2``, never ``12``).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass

from valterm.core.errors import ValtermError

_FORMAT = re.compile(r"^/([FEIHDXCSUB])(\d*)(?:\.(\d+))?$", re.IGNORECASE)


class TypeListError(ValtermError, ValueError):
    """An output list that cannot be decoded (an unclosed quote, a bad format)."""


@dataclass(frozen=True)
class Item:
    """One item: ``text`` typed as is, or the value of ``expr`` in ``fmt`` (e.g. F8.2)."""

    text: str = ""
    expr: object | None = None  # whatever the dialect's compile function returns
    fmt: str = "D"


def split_items(text: str) -> list[str]:
    """The top-level items of an output list (commas and blanks outside quotes and brackets)."""
    items: list[str] = []
    current, depth, quoted = "", 0, False
    for ch in text:
        if quoted:
            current += ch
            quoted = ch != '"'
            continue
        if ch == '"':
            if current.strip() and depth == 0:
                items.append(current.strip())
                current = ""
            current += ch
            quoted = True
        elif ch in "([":
            depth += 1
            current += ch
        elif ch in ")]":
            depth -= 1
            current += ch
        elif ch == "," and depth == 0:
            items.append(current.strip())
            current = ""
        elif ch == "/" and depth == 0 and not current.strip():
            current += ch
        elif ch.isspace() and depth == 0 and current.strip().startswith(("/", '"')):
            items.append(current.strip())
            current = ""
        else:
            if current.strip().startswith('"') and depth == 0:  # text glued after a string
                items.append(current.strip())
                current = ""
            current += ch
    if quoted:
        raise TypeListError("TYPE: A QUOTE IS NOT CLOSED")
    if current.strip():
        items.append(current.strip())
    return [item for item in items if item]


def parse_items(text: str, compile_value: Callable[[str], object]) -> list[Item]:
    """An output list decoded once; ``compile_value`` compiles one value (raises on a bad one)."""
    items: list[Item] = []
    fmt = "D"
    for word in split_items(text):
        if word.startswith('"'):
            items.append(Item(text=word[1:-1]))
            continue
        match = _FORMAT.match(word)
        if match is not None:
            kind, width, digits = match.group(1).upper(), match.group(2), match.group(3)
            if kind == "X":
                items.append(Item(text=" " * int(width or 1)))
            elif kind == "C":
                items.append(Item(text="\n" * int(width or 1)))
            elif kind in "FEIH":
                fmt = f"{kind}{width}{'.' + digits if digits else ''}"
            elif kind == "D":
                fmt = "D"
            elif kind == "S":
                items.append(Item(fmt=NO_LINE_END))  # no text: the TYPE leaves its line open
            continue
        if word.startswith("/"):
            raise TypeListError(f"TYPE: {word} IS NOT A FORMAT (/Fw.d /Ew.d /Iw /Hw /D /Xn /Cn /S)")
        items.append(Item(expr=compile_value(word), fmt=fmt))
    return items


NO_LINE_END = "S"  # the format of the item /S leaves: the line is not ended
# Below this a value is rounding noise of millimetre-sized arithmetic (1000 mm x 1.1e-16 per
# operation) and is typed as 0; SIN/COS/TAN are exact at whole multiples of 90 degrees
TINY = 1e-12


def format_number(value: float, fmt: str = "D") -> str:
    """A value as TYPE writes it in format ``fmt`` (D: the shortest form, as TYPE COL=).

    As V+ does, rounding noise is typed as 0 (never 6.12323e-17), and a fixed-point
    value that rounds to zero is never typed with a minus sign.
    """
    value = float(value)
    if abs(value) < TINY:
        value = 0.0
    if fmt == "D":
        if value.is_integer() and abs(value) < 1e15:
            return str(int(value))
        return f"{value:.6g}"
    match = re.fullmatch(r"([FEIH])(\d*)(?:\.(\d+))?", fmt)
    assert match is not None
    kind, width, digits = match.group(1), int(match.group(2) or 0), match.group(3)
    if kind == "F":
        text = f"{value:.{int(digits or 2)}f}"
        if text.startswith("-") and not text.strip("-0."):
            text = text[1:]  # -0.00 is 0.00
    elif kind == "E":
        text = f"{value:.{int(digits or 2)}E}"
    elif kind == "I":
        text = str(round(value))
    else:
        text = format(round(value) & 0xFFFFFFFF, "X")
    return text.rjust(width)
