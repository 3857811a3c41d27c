"""The one question when a save finds its file changed on disk (another session saved it).

The core raises FileChanged and writes nothing; this screen asks what to do:
O overwrite the other session's save, R reload (take it, dropping this session's changes),
A save as another name (typed here), ESC nothing now (the changes stay, unsaved).
The editor's and MANIPULATION's saves both use it; the answer is ("overwrite", ""),
("reload", ""), ("save as", NAME) or None.
"""

from __future__ import annotations

from textual import events
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Vertical
from textual.widgets import Input, Static

from valterm.ui import keymap, legends
from valterm.ui.screens.keyed import KeyedModalScreen

Answer = tuple[str, str] | None

QUESTION = ("{changed.overwrite} OVERWRITE IT   {changed.reload} RELOAD IT (YOUR CHANGES GO)   "
            "{changed.save_as} SAVE AS ANOTHER NAME   {changed.cancel} NOT NOW")  # keys as bound now


class FileChangedScreen(KeyedModalScreen[Answer]):
    """NAME CHANGED ON DISK: overwrite, reload or save as."""

    DEFAULT_CSS = """
    FileChangedScreen { align: center middle; }
    FileChangedScreen > Vertical { width: 80; max-width: 100%; height: auto; border: heavy $warning;
                                   padding: 0 1; background: $surface; }
    FileChangedScreen Static { width: 100%; height: auto; }
    FileChangedScreen Input { display: none; }
    FileChangedScreen Input.asking { display: block; }
    """
    AUTO_FOCUS = ""
    BINDINGS = [
        Binding("o,O", "answer('overwrite')", "Overwrite it", id="changed.overwrite"),
        Binding("r,R", "answer('reload')", "Reload it", id="changed.reload"),
        Binding("a,A", "save_as", "Save as another name", id="changed.save_as"),
        Binding("escape", "cancel", "Not now / back to the question", id="changed.cancel"),
    ]
    STATES = {"answer": frozenset({"question"}), "save_as": frozenset({"question"})}

    def __init__(self, file_name: str, kind: str = "file") -> None:
        super().__init__()
        self.file_name = file_name
        self.kind = kind

    def compose(self) -> ComposeResult:
        with Vertical():
            yield Static(f"{self.file_name} CHANGED ON DISK SINCE YOU READ IT: ANOTHER SESSION SAVED IT.\n"
                         f"SAVING NOW WOULD LOSE ITS CHANGES.", id="changed-what")
            yield Static(legends.fill(self, QUESTION), id="changed-question")
            yield Input(placeholder=f"NEW {self.kind.upper()} NAME, RETURN TO SAVE", id="changed-name")

    @property
    def question(self) -> str:
        return str(self.query_one("#changed-question", Static).content)

    @property
    def key_state(self) -> str:
        return "name" if self.query_one("#changed-name", Input).has_class("asking") else "question"

    def line_taking_keys(self) -> Input | None:
        name = self.query_one("#changed-name", Input)
        return name if name.has_class("asking") else None

    def action_answer(self, answer: str) -> None:
        self.close((answer, ""))

    def action_save_as(self) -> None:
        name = self.query_one("#changed-name", Input)
        name.add_class("asking")
        name.focus()
        back = legends.fill(self, "({changed.cancel}: BACK TO THE QUESTION)")
        self.query_one("#changed-question", Static).update(f"SAVE AS: TYPE A NEW {self.kind.upper()} NAME {back}")

    def action_cancel(self) -> None:
        name = self.query_one("#changed-name", Input)
        if name.has_class("asking"):
            name.remove_class("asking")
            self.set_focus(None)
            self.query_one("#changed-question", Static).update(legends.fill(self, QUESTION))
        else:
            self.close(None)

    def wrong_key(self, event: events.Key) -> None:
        answers = legends.keys_of(self, "changed.overwrite", "changed.reload", "changed.save_as")
        wrong = keymap.wrong_answer(event, answers, legends.key_for(self, "cancel", "ESC"))
        self.query_one("#changed-question", Static).update(f"{legends.fill(self, QUESTION)}\n{wrong}")

    def on_input_submitted(self, event: Input.Submitted) -> None:
        event.stop()
        if event.value.strip():
            self.close(("save as", event.value.strip()))

    def close(self, answer: Answer) -> None:
        """Dismiss this screen if it is still the one on top (keys typed ahead)."""
        if self.app.screen is self:
            self.dismiss(answer)
