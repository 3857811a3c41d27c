"""The readouts: the clamp position of Fig. 2-8 and the part position of Fig. 4-2.

The ``format_part`` lines and the core's ``where_lines`` are plain text (the hardcopy and the tests use them too); the
widgets show them.
"""

from __future__ import annotations

from typing import Sequence

from rich.segment import Segment
from rich.style import Style
from textual.geometry import Region, Size
from textual.strip import Strip
from textual.widget import Widget
from textual.widgets import Static

from valterm.core.events import Where
from valterm.core.text.transcript import number as readout_number
from valterm.core.text.transcript import where_lines
from valterm.ui.compositor import coded_runs, content_only_filtered, narrow, plain_codes, written_past

SCS_H = 26.0  # SPEC §1: Y_s = Z_w + H
COLUMN = 9


def _shape(text: str) -> tuple[int, int]:
    lines = text.split("\n")
    return len(lines), max(len(line) for line in lines)


def show_text(widget: Static, text: str) -> None:
    """``widget`` reads ``text``: repainted only when that changes, laid out again only when
    its lines' number or length does (a motion redraws its screen at every pose; issue 40)."""
    shown = widget.content
    if isinstance(shown, str) and shown == text:
        return
    widget.update(text, layout=not isinstance(shown, str) or _shape(shown) != _shape(text))


class ReadoutLines(Widget):
    """Lines of text drawn a line at a time: new lines repaint only those that read
    differently (the WHERE lines' numbers change at every pose of a motion, their heads
    never; a Static lays out and renders all of its text again; issue 40)."""

    DEFAULT_CSS = "ReadoutLines { height: auto; }"

    def __init__(self, *, id: str | None = None, classes: str | None = None) -> None:
        super().__init__(id=id, classes=classes)
        self.lines: list[str] = []
        self._strips: dict[int, Strip] = {}
        self._style: Style | None = None  # rich_style walks the ancestors: once a style
        # the lines' terminal codes (span_text); False: not looked at since the style changed
        self._codes: tuple[str, str] | bool | None = False

    @property
    def text(self) -> str:
        return "\n".join(self.lines)

    def show_lines(self, lines: Sequence[str]) -> None:
        new = list(lines)
        if len(new) != len(self.lines):
            self.lines, self._strips = new, {}
            self.refresh(layout=True)
            return
        changed = [y for y, (old, line) in enumerate(zip(self.lines, new)) if old != line]
        self.lines = new
        for y in changed:
            self._strips.pop(y, None)
        width = self.size.width
        if changed and not written_past(self, [(y, 0, width) for y in changed]):
            self.refresh(*(Region(0, y, width, 1) for y in changed))

    def get_content_height(self, container: Size, viewport: Size, width: int) -> int:
        return len(self.lines)

    def notify_style_update(self) -> None:
        super().notify_style_update()
        self._strips.clear()  # drawn in the old style
        self._style, self._codes = None, False

    def span_text(self, spans: Sequence[tuple[int, int, int]], x: int, y: int) -> str | None:
        """The ``spans`` (row, first column, end column of the widget's outer region, placed
        at (x, y) on the screen; within its content) as terminal sequences, cell for cell
        what Textual's pipeline makes of the rows (``compositor.colour_runs`` of its strips),
        made with no strip; None when that pipeline does more than filter the content."""
        if self._codes is False:
            if self._style is None:
                self._style = self.rich_style
            self._codes = plain_codes(self, self._style) if content_only_filtered(self) else None
        codes = self._codes
        if not isinstance(codes, tuple):
            return None
        left, top = self.content_offset
        width = self.size.width
        out: list[str] = []
        for row, a, b in spans:
            line = self.lines[row - top] if 0 <= row - top < len(self.lines) else ""
            if not narrow(line):
                return None  # a wide character: Textual crops it
            cells = line[:width].ljust(width)[a - left:b - left]
            runs = coded_runs([(cells, codes)])
            assert runs is not None  # the codes are the line's own
            out += (f"\x1b[{y + row + 1};{x + a + 1}H", runs)
        return "".join(out)

    def render_line(self, y: int) -> Strip:
        width = self.size.width
        strip = self._strips.get(y)
        if strip is None or strip.cell_length != width:
            text = self.lines[y] if y < len(self.lines) else ""
            if self._style is None:
                self._style = self.rich_style
            strip = Strip([Segment(text, self._style)]).crop_extend(0, width, self._style)
            self._strips[y] = strip
        return strip


def world_to_screen(xyz: Sequence[float]) -> tuple[float, float, float]:
    """SCS of a world point: X_s = Y_w, Y_s = Z_w + 26, Z_s = X_w."""
    x, y, z = (float(v) for v in xyz)
    return y, z + SCS_H, x


def format_part(number: int, reference: Sequence[float]) -> list[str]:
    """Fig. 4-2: the part's reference corner in world and in screen coordinates."""
    head = 32
    world = [readout_number(v) for v in reference]
    screen = [readout_number(v) for v in world_to_screen(reference)]
    return [
        f"WORLD COORDINATES FOR PART NO. {number}".ljust(head) + "".join(c.rjust(COLUMN) for c in ("XW", "YW", "ZW")),
        " " * head + "".join(c.rjust(COLUMN) for c in world),
        f"SCREEN COORDINATES FOR PART NO. {number}".ljust(head) + "".join(c.rjust(COLUMN) for c in ("X", "Y", "Z")),
        " " * head + "".join(c.rjust(COLUMN) for c in screen),
    ]


class PositionReadout(Static):
    """Fig. 2-8, kept current by the screen after every pose."""

    DEFAULT_CSS = "PositionReadout { height: auto; }"

    def show_where(self, where: Where, extra: str = "") -> None:
        lines = where_lines(where)
        if extra:
            lines.append(extra)
        show_text(self, "\n".join(lines))


class PartReadout(Static):
    """Fig. 4-2, kept current while a part is repositioned."""

    DEFAULT_CSS = "PartReadout { height: auto; }"

    def show_part(self, number: int, reference: Sequence[float]) -> None:
        show_text(self, "\n".join(format_part(number, reference)))
