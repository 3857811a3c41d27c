"""The debugger's panel beside VAL-II mode's transcript while a program is paused.

It shows the steps around the one the program is paused at (a breakpoint's or a single
step's next step, or the PAUSE step), that step highlighted, and the watched variables with
their values.  It only draws what it is given: the listing and the values come from the
core's ``Debugger`` (``listing``, ``watched``).
"""

from __future__ import annotations

from collections.abc import Sequence

from rich.text import Text
from textual.widgets import Static

from valterm.core.text.transcript import watched_value

PAUSED_KEYS = "^P PROCEED  ^O XSTEP  ^S SSTEP  CTRL-C ABORT"


class DebugPanel(Static):
    """The paused program's listing and the watched variables."""

    DEFAULT_CSS = """
    DebugPanel { width: 30; height: 1fr; border: round $warning; padding: 0 1;
                 text-wrap: nowrap; text-overflow: ellipsis; }
    DebugPanel.hidden { display: none; }
    """

    def show_pause(self, program: str, step: int, listing: Sequence[tuple[int, str, bool]],
                   watched: Sequence[tuple[str, float | None]]) -> None:
        text = Text(no_wrap=True, overflow="ellipsis")
        for number, line, here in listing:
            marker = ">" if here else " "
            text.append(f"{marker}{number:>4}  {line}\n", style="reverse bold" if here else "")
        text.append("\nWATCH\n", style="bold")
        if not watched:
            text.append("  (WATCH <VARIABLE> ADDS ONE)\n")
        for name, value in watched:
            text.append(f"  {name} = {watched_value(value)}\n")
        self.border_title = f"{program} STEP {step}"
        self.update(text)
        self.remove_class("hidden")

    def hide(self) -> None:
        self.add_class("hidden")

    @property
    def text(self) -> str:
        """What the panel shows, as plain text (tests)."""
        content = self.content
        return content.plain if isinstance(content, Text) else str(content)
