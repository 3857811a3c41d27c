"""The prompt line: a question and, for typed answers, an input field.

Single-key answers (Y/N) are taken by the screen (see ``MenuScreen.ask_key``); the input is
shown only for typed answers, so menu keys never go to a focused input by accident.
"""

from __future__ import annotations

from textual import events
from textual.containers import Horizontal
from textual.widgets import Input, Label


class Prompt(Horizontal):
    """Hidden until a question opens it. Its question and input field are mounted after the
    screen's first frame (``mount_parts``, or by the first question if one comes sooner): a
    menu screen shows without them, a tenth of MAIN MENU's first frame (issue 25, the start)."""

    DEFAULT_CSS = """
    Prompt { height: 1; display: none; }
    Prompt.-active { display: block; }
    Prompt > Label { width: auto; margin-right: 1; }
    Prompt > Input { border: none; height: 1; width: 1fr; padding: 0; }
    Prompt > Input:focus { border: none; }
    Prompt.-key > Input { display: none; }
    """

    def mount_parts(self) -> None:
        # Textual mounts nothing on a widget that is going or gone: the screen's timer can
        # fire as the app closes, the prompt already detached (CI, test_demo's hand-over)
        if self.is_attached and not (self._closing or self._pruning):
            self._parts()

    def _parts(self) -> tuple[Label, Input]:
        """The question and the input field, mounted now if they are not yet."""
        if not self.children:
            # disabled while closed, so a hidden input can never take a menu key
            self.mount(Label("", id="question"), Input(id="answer", compact=True, disabled=True))
        return self.query_one("#question", Label), self.query_one("#answer", Input)

    @property
    def question(self) -> str:
        return str(self._parts()[0].content)

    def open_line(self, question: str, default: str = "", typed: bool = False) -> None:
        """Open the typed answer with ``default`` in it: selected, so typing replaces it, or
        when ``typed`` (the user's own first key) kept, so typing goes on after it."""
        label, answer = self._parts()
        self.remove_class("-key")
        self.add_class("-active")
        label.update(question)
        answer.disabled = False
        answer.select_on_focus = not typed
        answer.value = default
        answer.cursor_position = len(default)
        answer.focus()

    def open_key(self, question: str) -> None:
        self.add_class("-active", "-key")
        self._parts()[0].update(question)

    def close(self) -> None:
        self.remove_class("-active", "-key")
        answer = self._parts()[1]
        answer.value = ""
        if answer.has_focus:
            self.screen.set_focus(None)
        answer.disabled = True

    @property
    def field(self) -> Input:
        """The input field (mounted now if it is not yet)."""
        return self._parts()[1]


def type_ahead(event: events.Key, field: Input) -> bool:
    """Give the open line a key that reached the screen instead of it.

    Textual moves focus after the current message, so keys typed quickly after the one that
    opened a question (or pasted) reach the screen; they belong to the field. The field may
    have the focus by the time the screen handles such a key: it is still the field's, and
    taken here, in order (left to the app, a RETURN would run after the keys typed after it,
    which went straight to the focused field). A RETURN or BACKSPACE typed into the focused
    field bubbles here before the field's own bindings run: taken here once, and stopped.
    Returns True when the key was taken (the caller stops the event).
    """
    if field.disabled:
        return False
    if event.key == "enter":
        field.post_message(Input.Submitted(field, field.value))
    elif event.key == "backspace":
        field.action_delete_left()
    elif event.is_printable and event.character:
        field.insert_text_at_cursor(event.character)
    else:
        return False
    event.stop()
    event.prevent_default()
    return True


def typed_after(field: Input, submitted: str) -> str:
    """What was typed into ``field`` after RETURN submitted ``submitted`` and before the
    screen took it (Textual posts the submission; keys typed quickly get in between): the
    start of the next line, never lost."""
    now = field.value
    return now[len(submitted):] if now.startswith(submitted) else ""
