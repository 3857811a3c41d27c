"""What every menu screen has: the menu text, the model view beside it (or in its place on a
narrow terminal), a readout, the message lines and the prompt line.

Menu keys are screen bindings (with ids) and nothing is focused while a menu waits, so a
key is never swallowed by an input; an input is focused only while a typed answer is asked.
"""

from __future__ import annotations

from typing import Callable

from textual import events
from textual.app import ComposeResult
from textual.containers import Horizontal, Vertical
from textual.screen import Screen
from textual.widgets import Input

from valterm.core.events import Event, Help, Pause
from valterm.ui.errors import problem_text
from valterm.ui.messages import SceneChanged
from valterm.ui.screens.help import HelpScreen
from valterm.ui.view.keys import VIEW_KEYS
from valterm.ui.view.model_view import ModelView
from valterm.ui.widgets.cell_view import CellView
from valterm.ui.widgets.menu_text import MenuText
from valterm.ui.widgets.message_log import MessageLog
from valterm.ui.widgets.prompt import Prompt, type_ahead

WIDE = 100  # columns from which the model is shown beside the menu


class MenuScreen(Screen):
    """A menu of the thesis with the model; subclasses set MENU and their bindings."""

    AUTO_FOCUS = ""  # nothing focused: "" disables auto focus (None would inherit the app's)
    MENU = ""

    def __init__(self) -> None:
        super().__init__()
        self._line_answer: Callable[[str], None] | None = None
        self._key_answer: Callable[[str], None] | None = None
        self._keys = ""
        self._cancel_answer: Callable[[], None] | None = None
        self.part_axes: int | None = None  # a part whose frame is drawn (MANIPULATION)

    # -- layout ----------------------------------------------------------------------
    def compose(self) -> ComposeResult:
        with Horizontal(id="body"):
            with Vertical(id="menu-pane"):
                yield MenuText(self.MENU, id="menu")
            with Vertical(id="model-pane"):
                yield CellView(id="model")
        yield from self.compose_readout()
        yield MessageLog(id="messages")
        yield Prompt(id="prompt")

    def compose_readout(self) -> ComposeResult:
        """The readout under the body (none by default)."""
        return iter(())

    def on_mount(self) -> None:
        view = self.model_view
        view.set_view(self.app.view_transform)
        view.ascii = self.app.ascii
        self._sync_view_options()
        self._layout(self.app.size.width)
        self.redraw()

    def on_screen_resume(self) -> None:
        self.model_view.set_view(self.app.view_transform)
        self._sync_view_options()
        self.redraw()

    def on_resize(self, event: events.Resize) -> None:
        self._layout(event.size.width)

    def _layout(self, width: int) -> None:
        self.set_class(width >= WIDE, "-wide")
        self.set_class(width < WIDE, "-narrow")

    def _sync_view_options(self) -> None:
        view = self.model_view
        view.back_faces = self.app.back_faces
        view.axes = self.app.axes

    @property
    def model_view(self) -> ModelView:
        return self.query_one("#model", ModelView)

    @property
    def messages(self) -> MessageLog:
        return self.query_one("#messages", MessageLog)

    @property
    def menu(self) -> MenuText:
        return self.query_one("#menu", MenuText)

    @property
    def model_shown(self) -> bool:
        """True when the model has the screen (R / M toggle; beside the menu when wide)."""
        return self.has_class("-model")

    def show_model(self, shown: bool = True) -> None:
        self.set_class(shown, "-model")

    def toggle_model(self) -> None:
        self.show_model(not self.model_shown)

    def show_model_if_narrow(self) -> None:
        """A motion on a narrow terminal brings the model up: the user wants to see it move."""
        if self.has_class("-narrow"):
            self.show_model(True)

    # -- drawing -----------------------------------------------------------------------
    def redraw(self) -> None:
        self.model_view.update_scene(self.app.scene(self.part_axes))
        self.update_readout()

    def update_readout(self) -> None:
        """Subclasses keep their readout current here."""

    # -- the player's audience (valterm.ui.playback) -------------------------------------
    def show_scene(self) -> None:
        self.redraw()

    def show_lines(self, lines: list[str]) -> None:
        for line in lines[-self.messages.max_lines:]:
            self.say(line, "error" if line.startswith("***") else "info")

    def take_event(self, event: Event) -> bool:
        if isinstance(event, Help):
            self.app.push_screen(HelpScreen(event.topic))
            return True
        return False

    def paused(self, pause: Pause) -> None:
        """A menu has no PROCEED line: the program goes on (VAL-II mode waits)."""
        self.app.player.resume()

    def played(self, aborted: bool) -> None:
        self.redraw()
        if aborted:
            self.say("*** ABORTED ***", "warning")
        self.after_motion(aborted)

    def after_motion(self, aborted: bool) -> None:
        """Subclasses' hook after a motion (or a command) ends."""

    def on_scene_changed(self, message: SceneChanged) -> None:
        self._sync_view_options()
        self.redraw()

    def say(self, text: str, level: str = "info") -> None:
        self.messages.say(text, level)

    # -- shared keys: V (one VAL-II command) and ? (help) ------------------------------
    def action_val(self) -> None:
        self.ask_line("VAL-II COMMAND:", self.run_command)

    def run_command(self, text: str) -> None:
        """One VAL-II command typed at a menu, run through the session's interpreter."""
        if not text:
            return
        try:
            events_ = self.app.session.command(text)
        except Exception as error:
            self.say(problem_text(error), "error")
            return
        self.say(f"    {text.upper()}")
        self.show_model_if_narrow()
        self.app.run_events(events_, self)

    def action_help(self) -> None:
        self.app.push_screen(HelpScreen())

    # -- questions --------------------------------------------------------------------
    @property
    def asking(self) -> bool:
        return self._line_answer is not None or self._key_answer is not None

    def ask_line(self, question: str, then: Callable[[str], None], default: str = "",
                 cancel: Callable[[], None] | None = None) -> None:
        """Ask a typed answer (RETURN ends it, ESCAPE cancels)."""
        self._key_answer = None
        self._line_answer = then
        self._cancel_answer = cancel
        self.query_one(Prompt).open_line(question, default)

    def ask_key(self, question: str, then: Callable[[str], None], keys: str = "YN",
                cancel: Callable[[], None] | None = None) -> None:
        """Ask a single-key answer among ``keys`` (upper case is passed to ``then``)."""
        self._line_answer = None
        self._key_answer = then
        self._keys = keys.upper()
        self._cancel_answer = cancel
        self.query_one(Prompt).open_key(question)

    def _close_prompt(self) -> None:
        self._line_answer = self._key_answer = None
        self._cancel_answer = None
        self.query_one(Prompt).close()

    def on_input_submitted(self, event: Input.Submitted) -> None:
        event.stop()
        then = self._line_answer
        if then is None:
            return
        self._close_prompt()
        then(event.value.strip())

    def on_key(self, event: events.Key) -> None:
        """While a question waits, its keys (and ESCAPE) go to it, not to the menu."""
        if not self.asking:
            return
        if event.key == "escape":
            event.stop()
            event.prevent_default()
            cancel = self._cancel_answer
            self._close_prompt()
            if cancel is not None:
                cancel()
            return
        if self._key_answer is None:
            type_ahead(event, self.query_one(Prompt).query_one("#answer", Input))
            return
        if event.key in VIEW_KEYS:
            return  # the view keys still turn the model while a one-key answer waits
        event.stop()
        event.prevent_default()
        char = (event.character or "").upper()
        if event.key == "enter" and self._keys:
            char = self._keys[0] if "\n" in self._keys else ""
        if char and char in self._keys:
            then = self._key_answer
            self._close_prompt()
            then(char)
