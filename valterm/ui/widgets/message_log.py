"""The message lines under a menu: warnings, collision messages, listings (a few at a time).

Messages replace rather than pile up: the first message after a key press (``new_turn``)
clears the old ones, so "MOTION REFUSED" goes as soon as the next thing happens, and a typed
answer that is taken clears them even when it says nothing (``MenuScreen.on_input_submitted``). At most
``max_lines`` lines are kept on screen; long lines wrap. A warning already shown since the
last key press is not repeated (a collision pair found again at every step of a motion).
"""

from __future__ import annotations

from rich.text import Text
from textual.widgets import Static

from valterm.ui.errors import upper_case

MAX_LINES = 3


class MessageLog(Static):
    """The last few messages of the current key press."""

    DEFAULT_CSS = "MessageLog { height: auto; max-height: 4; }"

    def __init__(self, *, max_lines: int = MAX_LINES, id: str | None = None) -> None:
        super().__init__("", id=id)
        self.max_lines = max_lines
        self.lines: list[tuple[str, str]] = []
        self._fresh = False  # the next message starts afresh

    @property
    def text(self) -> str:
        return "\n".join(line for line, _ in self.lines[-self.max_lines:])

    def new_turn(self) -> None:
        """A key was pressed: the next message replaces what is shown."""
        self._fresh = True

    def end_turn(self) -> None:
        """A motion or a command ended having said nothing: the last key's refusals go (an old
        MOTION REFUSED must not stand beside a move that was made); warnings such as a
        collision that goes on stay, as they are said once."""
        if self._fresh:
            self.lines = [(line, level) for line, level in self.lines
                          if level != "error" and not line.startswith(("MOTION REFUSED", "***"))]
            self._show()

    def say(self, line: str, level: str = "info") -> None:
        if self._fresh:
            self.lines = []
            self._fresh = False
        for part in str(line).splitlines() or [""]:
            if level != "info":
                part = upper_case(part)  # the VS11's messages are upper case
                if (part, level) in self.lines:
                    continue  # the same collision pair, step after step
            self.lines.append((part, level))
        self.lines = self.lines[-200:]
        self._show()

    def clear(self) -> None:
        self.lines = []
        self._show()

    def _show(self) -> None:
        text = Text(no_wrap=False, overflow="fold")
        shown = self.lines[-self.max_lines:]
        for i, (line, level) in enumerate(shown):
            if i:
                text.append("\n")
            text.append(line, style="bold yellow" if level == "warning" else ("bold red" if level == "error" else ""))
        self.update(text)
        # said while the screen is being shown (mount, resume), the new height would be lost:
        # the lines are laid out again once that refresh is done (no message is cut)
        self.call_after_refresh(self.refresh, layout=True)
