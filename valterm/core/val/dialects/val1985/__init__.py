"""The 1985 dialect: the thesis's VAL-II, its statements read from COMMAND.DAT (``builders``:
the statement table)."""

from __future__ import annotations

from valterm.core.val.compiler import COMMAND_DAT
from valterm.core.val.dialect import Dialect
from valterm.core.val.dialects.val1985.builders import BUILDERS

DIALECT = Dialect(COMMAND_DAT, "1985 (COMMAND.DAT)", BUILDERS)
