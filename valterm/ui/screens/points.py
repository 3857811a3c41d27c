"""POINT NAME, X, Y, Z, O, A, T: a location typed in by hand (VAL-II mode's POINT line, the
one-line POINT typed at any V line; HELP POINT shows the form)."""

from __future__ import annotations

from valterm.core.files.locations import check_location_name
from valterm.core.kinematics import Location
from valterm.core.session import Session
from valterm.ui.errors import Refusal


def define_point(session: Session, typed: str) -> str:
    """Define the typed location in ``session``; its name. Refusal (a ValtermError) when the
    text is not a name and six numbers."""
    parts = typed.replace(",", " ").split()
    if len(parts) != 7:
        raise Refusal("TYPE: NAME, X, Y, Z, O, A, T (SIX NUMBERS)")
    name = check_location_name(parts[0])
    x, y, z, o, a, t = (_number(p) for p in parts[1:])
    session.define_location(name, Location((x, y, z), (o, a, t)))
    return name


def _number(text: str) -> float:
    try:
        return float(text)
    except ValueError:  # float()'s refusal of a word
        raise Refusal(f"{text} IS NOT A NUMBER") from None
