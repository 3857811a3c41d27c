"""The v+ statement table: the 1985 builders where the meaning is the same, V+ ones otherwise."""

from __future__ import annotations

from valterm.core.val.builders import Builder
from valterm.core.val.dialects.val1985.builders import BUILDERS as BUILDERS_1985
from valterm.core.val.dialects.vplus.calls import CALLS
from valterm.core.val.dialects.vplus.control import CONTROL
from valterm.core.val.dialects.vplus.motions import MOTIONS
from valterm.core.val.dialects.vplus.settings import SETTINGS
from valterm.core.val.dialects.vplus.signals import SIGNALS

VPLUS_BUILDERS: dict[str, Builder] = {**BUILDERS_1985, **CONTROL, **CALLS, **MOTIONS, **SETTINGS, **SIGNALS}
"""The v+ instruction set: command -> builder."""
