"""Programs in another descendant of VAL (issue 36): recognised and named in one message.

Kawasaki's AS language keeps VAL's ``.PROGRAM`` ... ``.END`` blocks but moves with ``JMOVE``,
``LMOVE``, ``JAPPRO`` ... and waits with ``TWAIT``; its files hold ``.TRANS``/``.JOINTS``/
``.AUXDATA`` sections and headers like ``.PROGRAM main()#0``. Staubli's VAL3 keeps programs
in XML (``<Programs>``, ``<Program name=...>``, ``<Code>``, a ``.pgx`` file) and moves with
``movej(``/``movel(``. Neither is VAL-II or V+: a file in one is refused with one message that
names the language and the line that shows it, never a page of per-line errors.
"""

from __future__ import annotations

import re
from pathlib import Path

from valterm.core.files.errors import FileFormatError

KAWASAKI_AS = "Kawasaki AS"
STAUBLI_VAL3 = "Staubli VAL3"

# The first word of an AS step that no VAL-II or V+ instruction has (not an assignment to it).
_AS_STEP = re.compile(
    r"^\s*(?:\d+\s+)?(JMOVE|LMOVE|JAPPRO|LAPPRO|JDEPART|LDEPART|HMOVE|XMOVE|C1MOVE|C2MOVE|TWAIT|SWAIT"
    r"|ACCURACY)\b(?!\s*=)", re.IGNORECASE)
_AS_FILE = re.compile(r"^\s*(\.TRANS|\.JOINTS|\.AUXDATA|\.PROGRAM\s+\S+\s*\([^)]*\)\s*#\d+)", re.IGNORECASE)
_VAL3 = re.compile(r"^\s*(<Programs\b|<Program\s+name=|<Code>|(movej|movel|movec)\s*\()", re.IGNORECASE)

_LANGUAGES = ((_VAL3, STAUBLI_VAL3), (_AS_STEP, KAWASAKI_AS), (_AS_FILE, KAWASAKI_AS))


def foreign_language(text: str) -> tuple[str, int, str] | None:
    """The other VAL descendant ``text`` is written in, the first line that shows it and what
    shows it (``("Kawasaki AS", 3, "JMOVE")``); None for VAL-II and V+."""
    for number, line in enumerate(text.splitlines(), start=1):
        for pattern, language in _LANGUAGES:
            match = pattern.match(line)
            if match is not None:
                return language, number, match.group(1).strip()[:30]
    return None


def refuse_foreign(text: str, where: str | Path) -> None:
    """FileFormatError naming the language when ``text`` is in another VAL descendant."""
    found = foreign_language(text)
    if found is not None:
        language, number, shown = found
        raise FileFormatError(where, number, f"a {language} program ({shown}): valterm runs VAL-II and V+")
