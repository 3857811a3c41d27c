"""A menu as text: the thesis's lines, squeezed (blank lines first) when the pane is short,
and paged (PGUP / PGDN) when even the squeezed menu does not fit (80x24, issue 17)."""

from __future__ import annotations

from rich.text import Text
from textual.geometry import Size
from textual.widget import Widget

from valterm.ui.legends import MENU_KEY

_KEY = MENU_KEY  # a line's key: one letter, or a rebound F12, CTRL-B ...
MORE = "-- MORE: PGDN (PGUP BACK) --"


class MenuText(Widget):
    """Shows one menu of the thesis; the first line (the title) in bold, key letters marked."""

    DEFAULT_CSS = """
    MenuText { width: auto; height: 1fr; }
    """

    def __init__(self, text: str, *, id: str | None = None, classes: str | None = None) -> None:
        super().__init__(id=id, classes=classes)
        self._lines = text.splitlines()
        self.top = 0  # the first line shown after the title when the menu is paged

    @property
    def text(self) -> str:
        return "\n".join(self._lines)

    def set_text(self, text: str) -> None:
        self._lines = text.splitlines()
        self.top = 0
        self.refresh(layout=True)

    def get_content_width(self, container: Size, viewport: Size) -> int:
        return max((len(line) for line in self._lines), default=0)

    def get_content_height(self, container: Size, viewport: Size, width: int) -> int:
        return len(self._lines)

    def _squeezed(self, height: int) -> list[str]:
        lines = list(self._lines)
        if len(lines) > height:
            lines = [line for line in lines if line.strip()]
        return lines

    def paged(self, height: int) -> bool:
        return len(self._squeezed(height)) > height

    def page(self, direction: int) -> bool:
        """PGDN (+1) / PGUP (-1); False when the whole menu is shown already."""
        height = self.size.height
        lines = self._squeezed(height)
        if len(lines) <= height:
            return False
        body = max(height - 2, 1)  # the title and the MORE line stay
        last = max(len(lines) - 1 - body, 0)
        self.top = min(max(self.top + direction * body, 0), last)
        self.refresh()
        return True

    def visible_lines(self, height: int) -> list[str]:
        """The lines that fit ``height`` rows: blank lines go first, then the menu is paged."""
        lines = self._squeezed(height)
        if len(lines) <= height:
            return lines
        body = max(height - 2, 1)
        top = min(self.top, max(len(lines) - 1 - body, 0))
        shown = lines[1 + top: 1 + top + body]
        more = MORE if 1 + top + body < len(lines) else "-- END: PGUP BACK --"
        return [lines[0], *shown, more][: max(height, 0)]

    def render(self) -> Text:
        lines = self.visible_lines(self.size.height)
        text = Text(no_wrap=True, overflow="crop")
        for number, line in enumerate(lines):
            if number:
                text.append("\n")
            if number == 0 or line.startswith("-- "):
                text.append(line, style="bold")
                continue
            match = _KEY.match(line)
            if match and not line.startswith("ENTER"):
                text.append(match.group(1))
                text.append(match.group(2), style="bold reverse")
                text.append(line[match.end(2):])
            else:
                text.append(line)
        return text
