"""The message lines under a menu: warnings, collision messages, listings (a few at a time)."""

from __future__ import annotations

from rich.text import Text
from textual.widgets import Static


class MessageLog(Static):
    """The last few messages; a new key press starts afresh (``clear``)."""

    DEFAULT_CSS = "MessageLog { height: auto; max-height: 8; }"

    def __init__(self, *, max_lines: int = 6, id: str | None = None) -> None:
        super().__init__("", id=id)
        self.max_lines = max_lines
        self.lines: list[tuple[str, str]] = []

    @property
    def text(self) -> str:
        return "\n".join(line for line, _ in self.lines)

    def say(self, line: str, level: str = "info") -> None:
        for part in str(line).splitlines() or [""]:
            self.lines.append((part, level))
        self.lines = self.lines[-200:]
        self._show()

    def clear(self) -> None:
        self.lines = []
        self._show()

    def _show(self) -> None:
        text = Text(no_wrap=False)
        shown = self.lines[-self.max_lines:]
        for i, (line, level) in enumerate(shown):
            if i:
                text.append("\n")
            text.append(line, style="bold yellow" if level == "warning" else ("bold red" if level == "error" else ""))
        self.update(text)
