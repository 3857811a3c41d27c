"""The VAL-II mode's transcript on screen: Textual's RichLog with bounded memory. Its own
module, loaded with VAL-II mode: RichLog brings rich.pretty (and attrs), which MAIN MENU does
without (issue 25, the start)."""

from __future__ import annotations

from textual.cache import LRUCache
from textual.widgets import RichLog

from valterm.ui.playback import LOG_CACHE, LOG_LINES


class TranscriptLog(RichLog):
    """The transcript as the screen shows it: the last ``LOG_LINES`` lines, wrapped, and a
    render cache of ``LOG_CACHE`` lines (the memory of a long run levels off in minutes)."""

    def __init__(self, *, id: str | None = None, classes: str | None = None) -> None:
        super().__init__(id=id, classes=classes, wrap=True, markup=False, max_lines=LOG_LINES)
        # RichLog keys its cache by the line's number since the start, so every line ever
        # shown takes a place there until 1024 are held (textual is pinned: the name holds)
        self._line_cache = LRUCache(LOG_CACHE)
