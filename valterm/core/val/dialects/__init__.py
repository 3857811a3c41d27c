"""The dialects of VAL, one package each (docs/ARCHITECTURE.md, "Adding a dialect").

``NAMES`` lists them as ``--dialect`` and ``Program.dialect`` spell them; ``dialect(name)``
loads the package of one (only when it is first asked for: the start loads none).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from valterm.core.errors import RefusedValue

if TYPE_CHECKING:
    from valterm.core.val.dialect import Dialect

DEFAULT = "1985"
NAMES = (DEFAULT, "v+")


def _val1985() -> Dialect:
    from valterm.core.val.dialects.val1985 import DIALECT

    return DIALECT


def _vplus() -> Dialect:
    from valterm.core.val.dialects.vplus import DIALECT

    return DIALECT


_PACKAGES = {DEFAULT: _val1985, "v+": _vplus}


def check_dialect(name: str) -> str:
    """'1985' or 'v+' (any case; 'vplus' too), else RefusedValue saying which there are."""
    wanted = name.strip().lower().replace("vplus", "v+")
    if wanted not in NAMES:
        raise RefusedValue(f"{name!r} is not a dialect: use {' or '.join(NAMES)}")
    return wanted


def dialect(name: str) -> Dialect:
    """The dialect of that name (as ``check_dialect`` accepts it)."""
    return _PACKAGES[check_dialect(name)]()
