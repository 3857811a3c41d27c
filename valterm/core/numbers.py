"""Numbers as a user writes them, in files, programs and arguments: one parser for all.

``parse_number("465.")`` -> 465.0; ``parse_number("1.5D+02")`` -> 150.0 (Fortran's D
exponent, as the thesis's files may have it). What it refuses, with the reason as the
message of a :class:`NumberError` (a ValtermError and a ValueError):

* anything that is not a plain decimal number (no ``nan``, ``inf``, ``0x10``, ``1_000``,
  no digits other than ASCII 0-9);
* more than :data:`MAX_NUMBER_CHARS` characters (no 5 000-digit numbers);
* a value that is not finite or whose size is over ``limit`` (default
  :data:`MAX_MAGNITUDE`): such numbers overflow in the arithmetic that follows.

The caller adds where the number was: the file readers wrap the reason into
``NAME.SET:12: object 1 vertex 3: ...``; an expression parser wraps it into its own
located error. ``parse_count`` is the same for whole numbers with an upper bound (the
number of objects, a step label). ``finite`` checks a computed value the same way, and
``numpy_errors()`` turns numpy's floating-point warnings into FloatingPointError at a
boundary so they become messages, never text on stderr.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator
from contextlib import contextmanager

from valterm.core.errors import ValtermError

MAX_NUMBER_CHARS = 64      # "-123456.789E+05" is 15; a double has 17 significant digits
MAX_MAGNITUDE = 1e15       # whole numbers up to here are exact in a double; mm, degrees, counts
MAX_FINITE = float("1.7976931348623157e308")  # any finite double (VAL-II variables)

# A number as Fortran and VAL-II write it: `465.`, `-.27`, `1.5E+02`, `1.5D+02`. ASCII only.
_NUMBER = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[EeDd][+-]?[0-9]+)?", re.ASCII)
_COUNT = re.compile(r"[0-9]+", re.ASCII)


class NumberError(ValtermError, ValueError):
    """A number refused; ``str()`` says why, without saying where (the caller knows that)."""


def two_decimals(value: float) -> str:
    """A readout number as Fig. 2-8 prints it: two decimals, never ``-0.00``."""
    text = f"{value:.2f}"
    return "0.00" if text == "-0.00" else text


def angle_text(value: float) -> str:
    """An angle of the (-180, 180] convention (O, A, T; a joint under the 1985 rules) in two
    decimals: never ``-0.00``, and a value that rounds to -180 is 180.00, the end the
    convention keeps (T -179.999 is shown 180.00, never ``T -180.00``)."""
    text = two_decimals(value)
    return "180.00" if text == "-180.00" else text


def parse_number(text: str, limit: float = MAX_MAGNITUDE) -> float:
    """The value of one written number, or NumberError saying why it is not one."""
    field = text.strip()
    if len(field) > MAX_NUMBER_CHARS:
        raise NumberError(f"a number of {len(field)} characters is too long (at most {MAX_NUMBER_CHARS})")
    if not _NUMBER.fullmatch(field):
        raise NumberError(f"{field!r} is not a number")
    value = float(field.replace("D", "E").replace("d", "e"))
    return finite(value, limit, field)


def parse_count(text: str, limit: int, what: str = "the number") -> int:
    """A whole number 0..limit written with ASCII digits, or NumberError."""
    field = text.strip()
    if not _COUNT.fullmatch(field):
        shown = field if len(field) <= 40 else field[:40] + "..."
        raise NumberError(f"{what} must be a whole number, not {shown!r}")
    digits = field.lstrip("0") or "0"
    if len(digits) > len(str(limit)) or int(digits) > limit:  # no int() of 5 000 digits
        raise NumberError(f"{what} {_short(digits)} is too large (at most {limit})")
    return int(digits)


def finite(value: float, limit: float = MAX_MAGNITUDE, written: str | None = None) -> float:
    """``value`` if it is finite and its size at most ``limit``, else NumberError."""
    shown = written if written is not None else repr(value)
    if not math.isfinite(value):
        raise NumberError(f"{_short(shown)} is out of range (not a finite number)")
    if abs(value) > limit:
        raise NumberError(f"{_short(shown)} is out of range (at most {limit:g} in size)")
    return value + 0.0  # no -0.0


@contextmanager
def numpy_errors() -> Iterator[None]:
    """Inside: numpy's overflow, invalid and divide-by-zero raise FloatingPointError instead of
    printing a RuntimeWarning; the boundary that uses it turns that into a message."""
    import numpy as np  # here: the command line and the app's first frame run without numpy

    with np.errstate(all="raise"):
        yield


def _short(text: str) -> str:
    return text if len(text) <= 24 else text[:20] + "..."
