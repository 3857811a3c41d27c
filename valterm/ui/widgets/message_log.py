"""The message lines under a menu: warnings, collision findings, listings.

Messages replace rather than pile up: the first message after a key press (``new_turn``)
clears the old ones, so "MOTION REFUSED" and its hint go as soon as the next thing happens,
and a typed answer that is taken clears them even when it says nothing
(``MenuScreen.on_input_submitted``). A warning already shown since the last key press is not
repeated (a collision pair found again at every step of a motion).

A motion's collision findings are the answer this program exists to give (Fig. C-12): every
one of them is kept under a count (``8 COLLISIONS, 3 NEAR``): collisions before near misses, or
under the 1985 rules interleaved in the order said, as Fig. C-12 shows them;
of the other lines the last ``max_lines`` are shown after them. The area grows to fit, up to
a share of the screen (the model keeps the rest), and scrolls when they do not fit (the count
line then names the keys that scroll it). Long lines wrap.
"""

from __future__ import annotations

from collections.abc import Callable

from rich.text import Text
from textual.app import ComposeResult
from textual.containers import VerticalScroll
from textual.widgets import Static

from valterm.ui.errors import upper_case

MAX_LINES = 3  # of the lines that are no finding, the last few are shown
KEPT = 200  # lines a turn keeps (a runaway TYPE loop cannot grow it)
COLLISION, NEAR = "collision", "near"  # the levels of a collision check's findings
FINDINGS = (COLLISION, NEAR)
STYLES = {"warning": "bold yellow", "error": "bold red", COLLISION: "bold red", NEAR: "yellow"}


def count_line(collisions: int, near: int) -> str:
    """``8 COLLISIONS, 3 NEAR``: how many findings the motion had, of each kind."""
    def plural(n: int, word: str) -> str:
        return f"{n} {word}" if n == 1 else f"{n} {word}S"

    return f"{plural(collisions, 'COLLISION')}, {near} NEAR"


class MessageLog(VerticalScroll):
    """What the current key press said: every finding, and the last few other lines."""

    DEFAULT_CSS = """
    MessageLog { height: auto; max-height: 40%; overflow-y: auto; }
    MessageLog > Static { height: auto; }
    """
    can_focus = False  # never takes the arrows from the model view, nor a menu key

    def __init__(self, *, max_lines: int = MAX_LINES, id: str | None = None) -> None:
        super().__init__(id=id)
        self._lines_shown = Static("")
        self.max_lines = max_lines
        self.lines: list[tuple[str, str]] = []
        self._fresh = False  # the next message starts afresh
        # the keys that scroll the area, for the count line's legend (the screen's live keys)
        self.scroll_keys: Callable[[], str] = lambda: ""
        self._legend = False  # the count line names the scroll keys (the lines do not fit)
        # collisions before near misses (the controller rules); False: in the order said, as
        # Fig. C-12 interleaves them (the 1985 rules; the core says them in the figure's order)
        self.grouped: Callable[[], bool] = lambda: True

    def compose(self) -> ComposeResult:
        yield self._lines_shown

    @property
    def text(self) -> str:
        """The lines as shown, top to bottom (also those scrolled out of view)."""
        return "\n".join(line for line, _ in self.shown())

    def shown(self) -> list[tuple[str, str]]:
        """(line, level) in the order shown: the count, the collisions, the near misses (each
        in the order found), then the other lines (the command typed, a refusal)."""
        collisions = [item for item in self.lines if item[1] == COLLISION]
        near = [item for item in self.lines if item[1] == NEAR]
        if not collisions and not near:
            return self._others(self.lines)
        count = count_line(len(collisions), len(near))
        if self._legend and (keys := self.scroll_keys()):
            count = f"{count}   {keys}: SCROLL THE MESSAGES"
        found = [*collisions, *near] if self.grouped() else [item for item in self.lines if item[1] in FINDINGS]
        return [(count, "error" if collisions else "warning"), *found, *self._others(self.lines)]

    def _others(self, lines: list[tuple[str, str]]) -> list[tuple[str, str]]:
        others = [item for item in lines if item[1] not in FINDINGS]
        return others[-self.max_lines:] if self.max_lines else []

    def new_turn(self) -> None:
        """A key was pressed: the next message replaces what is shown."""
        self._fresh = True

    def end_turn(self, still: list[tuple[str, str]] | None = None) -> None:
        """A motion or a command ended. Having said nothing, the last key's refusals, hints
        and other lines go (an old MOTION REFUSED must not stand beside a move that was
        made). ``still``: after a motion, the findings (line, level) of its last step; the
        core says each once, as it starts, so those it did not say again are added (None:
        the findings shown stay)."""
        if self._fresh:
            kept = [item for item in self.lines if item[1] in FINDINGS] if still is None else []
        else:
            kept = list(self.lines)
        if still and not self.grouped():  # the findings that hold first, in the order said
            kept = [*still, *(item for item in kept if item not in still)]
        kept += [item for item in still or () if item not in kept]
        if kept != self.lines or self._fresh:
            self.lines = kept
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
            if (recorder := getattr(self.app, "recorder", None)) is not None:
                recorder.shown([part])  # --record: the session's transcript
        self.lines = self.lines[-KEPT:]
        self._show()

    def clear(self) -> None:
        self.lines = []
        self._show()

    def _show(self) -> None:
        self._legend = False
        self._render_lines()
        self.scroll_home(animate=False)
        # said while the screen is being shown (mount, resume), the new height would be lost:
        # the lines are laid out again once that refresh is done (no message is cut); then
        # the count line names the scroll keys if the lines do not all fit
        self.call_after_refresh(self._laid_out)

    def _render_lines(self) -> None:
        text = Text(no_wrap=False, overflow="fold")
        for i, (line, level) in enumerate(self.shown()):
            if i:
                text.append("\n")
            text.append(line, style=STYLES.get(level, ""))
        self._lines_shown.update(text)

    def _laid_out(self) -> None:
        self._lines_shown.refresh(layout=True)
        self.call_after_refresh(self._name_scroll_keys)

    def _name_scroll_keys(self) -> None:
        hidden = self.max_scroll_y > 0
        if hidden != self._legend and any(level in FINDINGS for _, level in self.lines):
            self._legend = hidden
            self._render_lines()

    def page(self, direction: int) -> None:
        """A page back (-1) or on (+1) in the lines."""
        page = max(1, self.scrollable_content_region.height - 1)
        self.scroll_to(y=self.scroll_y + direction * page, animate=False)
