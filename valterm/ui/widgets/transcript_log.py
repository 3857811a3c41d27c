"""The VAL-II mode's transcript on screen: Textual's RichLog with bounded memory. Its own
module, loaded with VAL-II mode: RichLog brings rich.pretty (and attrs), which MAIN MENU does
without (issue 25, the start).

Every line is wrapped by the core's ``wrap_line`` at the width the log has now, and written
at exactly that width: RichLog left alone renders a line at least ``min_width`` (78) wide and
crops it to the log, so beside the picture (68 columns) each wrapped line lost its end (issue
35). The lines are kept as typed, so a change of width (the terminal resized, the picture or
the debugger's panel shown or hidden) wraps them again."""

from __future__ import annotations

from collections import deque
from collections.abc import Iterable
from typing import Self

from textual.cache import LRUCache
from textual.events import Resize
from textual.geometry import Region
from textual.widgets import RichLog

from valterm.core.text.transcript import wrap_line
from valterm.ui.playback import LOG_CACHE, LOG_LINES


class TranscriptLog(RichLog):
    """The transcript as the screen shows it: the last ``LOG_LINES`` lines, wrapped, and a
    render cache of ``LOG_CACHE`` lines (the memory of a long run levels off in minutes)."""

    def __init__(self, *, id: str | None = None, classes: str | None = None) -> None:
        super().__init__(id=id, classes=classes, wrap=True, markup=False, max_lines=LOG_LINES,
                         min_width=1)
        # RichLog keys its cache by the line's number since the start, so every line ever
        # shown takes a place there until 1024 are held (textual is pinned: the name holds)
        self._line_cache = LRUCache(LOG_CACHE)
        self.source: deque[str] = deque(maxlen=LOG_LINES)  # the lines as written, unwrapped
        self._wrapped_at = 0  # the width the rows on screen were wrapped at (0: none yet)

    @property
    def room(self) -> int:
        """The columns a row has: inside the border, the padding and any scroll bar."""
        return self.scrollable_content_region.width

    def write_lines(self, lines: Iterable[str]) -> None:
        """Add transcript lines: kept as they are, shown wrapped at the log's width."""
        new = list(lines)
        self.source.extend(new)
        if (recorder := getattr(self.app, "recorder", None)) is not None:
            recorder.shown(new)  # --record: the session's transcript
        if self.room != self._wrapped_at:
            self._rewrap()  # the width changed since the last rows: all of them again
        elif self.room > 0:
            self._show(new[-LOG_LINES:])

    def _show(self, lines: Iterable[str]) -> None:
        room = self.room
        rows = [row for line in lines for row in wrap_line(line, room)]
        if rows:  # at exactly the room: rich wraps again only what wrap_line counted short (wide glyphs)
            self.write("\n".join(rows), width=room)

    def _rewrap(self) -> None:
        super().clear()
        self._wrapped_at = self.room
        if self.room > 0:  # hidden (no width yet): wrapped when it is laid out
            self._show(self.source)

    def on_resize(self, event: Resize) -> None:
        if self.room != self._wrapped_at:
            self._rewrap()

    # the log grew: its scroll bars are updated where it stands, and the screen is laid out
    # again only when they come or go (Textual lays the whole screen out, and then writes all
    # of it, whenever a log's virtual size changes: every line a running program says; issue 40)
    _grown = False

    def watch_virtual_size(self) -> None:
        self._grown = True

    def refresh(self, *regions: Region, repaint: bool = True, layout: bool = False,
                recompose: bool = False) -> Self:
        grown, self._grown = self._grown, False
        if layout and grown and not recompose and self.is_mounted and self.container_size:
            # the bars for the new size; showing or hiding one asks for the layout itself
            self._scroll_update(self.virtual_size)
            layout = False
        return super().refresh(*regions, repaint=repaint, layout=layout, recompose=recompose)

    def clear(self) -> Self:
        """W_WIPE: the lines go, not only their rows (a resize must not bring them back)."""
        self.source.clear()
        return super().clear()
