"""The on-line HELP (§6.8.5): the HELP MENU, then topics looked up in HELPER.DAT.

"The operator is then asked whether he needs more information on a specific topic. If the
answer is yes, the user will then be asked to input the topic ... the user is frequently
asked whether it is necessary to display the HELP MENU or not."
"""

from __future__ import annotations

from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import VerticalScroll
from textual.events import Key
from textual.widgets import Input, Static

from valterm.core.files.helpfile import HelpTopics, NoHelpTopic, default_help
from valterm.ui import keymap, legends
from valterm.ui.screens.keyed import KeyedScreen
from valterm.ui.widgets.status import StatusLine

ASK_TOPIC = "DO YOU NEED MORE INFORMATION ON A SPECIFIC TOPIC (Y/N) ?"
ASK_MENU = "DO YOU WANT THE HELP MENU DISPLAYED AGAIN (Y/N) ?"
ENTER_TOPIC = "ENTER THE TOPIC FOR WHICH HELP IS NEEDED:"


class HelpScreen(KeyedScreen[None]):
    """HELP, reachable from every mode; Esc (or N to the first question) returns."""

    AUTO_FOCUS = None
    DEFAULT_CSS = """
    HelpScreen #help-text { height: 1fr; padding: 0 1; }
    HelpScreen #help-question { height: auto; padding: 0 1; color: $accent; }
    HelpScreen #help-topic { display: none; }
    HelpScreen #help-topic.asking { display: block; }
    """
    BINDINGS = [
        Binding("escape", "leave", "Return", id="help.return"),
        Binding("y,Y", "answer('Y')", "Yes", show=False, id="help.yes"),
        Binding("n,N", "answer('N')", "No", show=False, id="help.no"),
    ]
    STATES = {"answer": frozenset({"topic?", "menu?"})}
    SCROLL_KEYS = frozenset({"up", "down", "pageup", "pagedown", "home", "end"})  # the text scrolls

    def __init__(self, topic: str = "", topics: HelpTopics | None = None, *, screen: str = "",
                 keys: list[tuple[str, str]] | None = None) -> None:
        super().__init__()
        self.topics = topics or default_help()
        self.first_topic = topic.strip()
        self.screen_name = screen  # the screen HELP was asked from: its keys come first
        self.keys = keys or []
        self.state = "topic?"  # topic? | topic | menu?

    def compose(self) -> ComposeResult:
        with VerticalScroll(id="help-scroll"):
            yield Static(id="help-text")
        yield Static(id="help-question")
        yield Input(id="help-topic", placeholder="TOPIC (e.g. MOVE)")
        yield StatusLine(id="status")

    def on_mount(self) -> None:
        if self.first_topic:
            self.show_topic(self.first_topic)
        else:
            self.show_menu()

    # -- what is shown -----------------------------------------------------------
    @property
    def text(self) -> str:
        return str(self.query_one("#help-text", Static).content)

    @property
    def question(self) -> str:
        return str(self.query_one("#help-question", Static).content)

    def _show(self, lines: list[str] | tuple[str, ...]) -> None:
        if not self.query("#help-text"):
            return  # closed again before it was shown (ESC typed ahead of the screen)
        self.query_one("#help-text", Static).update("\n".join(lines))
        self.query_one("#help-scroll", VerticalScroll).scroll_home(animate=False)

    def _ask(self, state: str, question: str) -> None:
        self.state = state
        if not self.query("#help-question"):
            return
        self.query_one("#help-question", Static).update(question)
        field = self.query_one("#help-topic", Input)
        asking = state == "topic"
        field.set_class(asking, "asking")
        if asking:
            field.value = ""
            field.focus()
        else:
            self.set_focus(None)

    def key_legend(self) -> list[str]:
        """The keys that work on the screen HELP was opened from."""
        if not self.keys:
            return []
        width = max(len(k) for k, _ in self.keys)
        head = f"KEYS OF THE {self.screen_name} SCREEN" if self.screen_name else "KEYS"
        return [head, *(f"  {k.ljust(width)}  {what}" for k, what in self.keys), ""]

    def show_menu(self) -> None:
        self._show([*self.key_legend(), *self.topics.menu()])
        self._ask("topic?", ASK_TOPIC)

    def show_topic(self, word: str) -> None:
        try:
            lines = self.topics.find(word).lines()
        except NoHelpTopic as error:
            self._show([str(error), "", *self.topics.menu()])
            self._ask("topic?", ASK_TOPIC)
            return
        self._show(lines)
        self._ask("menu?", ASK_MENU)

    # -- answers -------------------------------------------------------------------
    @property
    def key_state(self) -> str:
        return self.state

    def line_taking_keys(self) -> Input | None:
        return self.query_one("#help-topic", Input) if self.state == "topic" else None

    def other_key(self, event: Key) -> bool:
        return event.key in self.SCROLL_KEYS  # the help text's scroll keys

    def wrong_key(self, event: Key) -> None:
        answers = legends.keys_of(self, "help.yes", "help.no")
        answer = keymap.wrong_answer(event, answers, legends.key_for(self, "leave", "ESC"))
        self.query_one("#help-question", Static).update(f"{self.question.splitlines()[0]}\n{answer}")

    def action_answer(self, key: str) -> None:
        if self.state == "topic?":
            if key == "Y":
                self._ask("topic", ENTER_TOPIC)
            else:
                self.action_leave()
        elif self.state == "menu?":
            if key == "Y":
                self.show_menu()
            else:
                self._ask("topic?", ASK_TOPIC)

    def on_input_submitted(self, event: Input.Submitted) -> None:
        event.stop()
        word = event.value.strip()
        if not word:
            self.show_menu()
        else:
            self.show_topic(word)

    def action_leave(self) -> None:
        if self.state == "topic":
            self._ask("topic?", ASK_TOPIC)
            return
        self.close()

    def close(self) -> None:
        """Dismiss this screen if it is still the one on top: keys typed ahead reach a screen's
        queue before it closes, and a second close must not close the screen below."""
        if self.app.screen is self:
            self.dismiss(None)
