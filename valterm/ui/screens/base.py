"""What every menu screen has: the menu text, the model view beside it (or in its place on a
narrow terminal), a readout, the message lines and the prompt line.

Menu keys are screen bindings (with ids) and nothing is focused while a menu waits, so a
key is never swallowed by an input; an input is focused only while a typed answer is asked.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable, ClassVar

from textual import events
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal
from textual.widgets import Input

from valterm.core.errors import ValtermError
from valterm.core.events import Collision, Contact, Event, Help, Message, Monitor
from valterm.core.numbers import two_decimals
from valterm.core.rules import RULES_1985
from valterm.core.text.transcript import figure_lines, finding_line
from valterm.ui import keymap, legends
from valterm.ui.errors import problem_text
from valterm.ui.messages import (
    Collided,
    PictureMoved,
    RunEnded,
    RunEvent,
    RunPaused,
    RunRequested,
    RunResumed,
    SceneChanged,
    SceneShown,
    TranscriptLines,
)
from valterm.ui.screens.keyed import KeyedScreen, action_name
from valterm.ui.view.model_view import ModelView
from valterm.ui.widgets.cell_view import CellView
from valterm.ui.widgets.menu_text import MenuText
from valterm.ui.widgets.message_log import COLLISION, NEAR, MessageLog
from valterm.ui.widgets.prompt import Prompt
from valterm.ui.widgets.status import StatusLine

if TYPE_CHECKING:  # annotations only
    from valterm.core.simulator import Simulator

WIDE = 100  # columns from which the model is shown beside the menu
PROMPT_PARTS_AFTER = 0.1  # seconds after a menu screen's first frame (see after_first_frame)


@dataclass(frozen=True)
class Question:
    """What a screen asks (its one state value besides the menu): a typed line, or a single
    key among ``keys``; ``then`` takes the answer, ``cancel`` runs on ESC (None: the menu)."""

    then: Callable[[str], None]
    cancel: Callable[[], None] | None = None
    keys: str = ""  # the single-key answers; "" for a typed line

    @property
    def single_key(self) -> bool:
        return bool(self.keys)


MENU, LINE, KEY = "menu", "line", "key"  # a menu screen's states: at its menu, or asking


class MenuScreen(KeyedScreen[None]):
    """A menu of the thesis with the model; subclasses set MENU and their bindings (each works
    at the menu only, unless the subclass's STATES says otherwise)."""

    AUTO_FOCUS = ""  # nothing focused: "" disables auto focus (None would inherit the app's)
    MENU = ""
    SCREEN_NAME = ""  # HELP's name for the screen (the menu's title when empty)
    LETTERS_START_A_COMMAND = False  # a letter that is no menu key opens V's command line with it
    MENU_KEYS_BOUND = True  # MENU's key letters are this screen's bindings (shown as bound now)
    BINDINGS = [
        Binding("escape", "cancel", "Cancel the prompt; at the menu: back", show=False, id="menu.cancel"),
        Binding("pagedown", "page(1)", "More of the menu", show=False, id="menu.page_down"),
        Binding("pageup", "page(-1)", "Back in the menu", show=False, id="menu.page_up"),
        # a motion's findings that do not fit the message area (VAL-II mode's transcript keys)
        Binding("shift+up", "messages(-1)", "Back a page in the messages", show=False, id="menu.messages_back"),
        Binding("shift+down", "messages(1)", "On a page in the messages", show=False, id="menu.messages_on"),
    ]
    ANY_STATE: ClassVar[frozenset[str]] = frozenset({"cancel", "help"})  # ESC, ? and F1

    def __init_subclass__(cls, **kwargs: Any) -> None:
        """Each subclass's own menu keys work at its menu only (one place: STATES)."""
        super().__init_subclass__(**kwargs)
        at_menu = {action_name(binding): frozenset({MENU}) for binding in cls.BINDINGS
                   if isinstance(binding, Binding) and action_name(binding) not in cls.ANY_STATE}
        cls.STATES = {**at_menu, **cls.__dict__.get("STATES", {})}

    def __init__(self) -> None:
        super().__init__()
        self.question: Question | None = None  # the screen's state: at its menu, or asking this
        self.part_axes: int | None = None  # a part whose frame is drawn (MANIPULATION)
        self._moved = False  # the robot or the cell changed in the stream now playing

    # -- layout ----------------------------------------------------------------------
    def compose(self) -> ComposeResult:
        # wide or narrow before the first styling, not a second styling of every widget after
        # it (issue 25, the start)
        self._layout(self.app.size.width, update=False)
        with Horizontal(id="body"):  # no pane around either: each is a widget less to draw (issue 25)
            yield MenuText(self.live_menu(self.MENU) if self.MENU_KEYS_BOUND else self.MENU, id="menu")
            yield CellView(id="model")
        yield from self.compose_readout()
        log = MessageLog(id="messages")
        log.scroll_keys = lambda: "/".join(legends.keys_of(self, "menu.messages_back", "menu.messages_on"))
        log.grouped = lambda: self.stage.simulator.rules != RULES_1985
        yield log
        yield Prompt(id="prompt")
        yield StatusLine(id="status")

    def after_first_frame(self) -> None:
        # the prompt's parts, hidden until asked, a moment later: mounted at once, they held
        # the interpreter while Textual's output thread was still writing the first frame
        # (8 ms more before it was all on the terminal, issue 25); a question mounts them sooner
        self.set_timer(PROMPT_PARTS_AFTER, self.query_one(Prompt).mount_parts, name="prompt parts")

    def live_menu(self, text: str, state: str | None = None) -> str:
        """A menu of the thesis with its keys as they are bound now (the keymap file), as
        they work in ``state`` (the menu's, by default)."""
        return legends.live_menu(self, text, state or MENU)  # MENU: the state, not the class's text

    def compose_readout(self) -> ComposeResult:
        """The readout under the body (none by default)."""
        return iter(())

    def on_mount(self) -> None:
        view = self.query_one_optional("#model", ModelView)
        if view is None:  # the app is closing: its widgets went before this mount was handled (CI)
            return
        if self.stage.session_read is not None:  # no view before a set-up is read (the start)
            view.set_view(self.stage.view_transform)
        view.ascii = self.stage.ascii
        self._sync_view_options()
        self._layout(self.app.size.width)
        # no redraw here: the screen's resume, which follows its mount before the first frame,
        # draws it (the picture was built twice for every screen shown, issue 25)

    def on_screen_resume(self) -> None:
        self._show_view()
        self.call_later(self._say_unsaid)  # after the screen's own first words (also when first shown)

    def setup_read(self) -> None:
        """--setup's set-up has been read after the first frame: the picture and the status."""
        self._show_view()

    def _show_view(self) -> None:
        if self.stage.session_read is not None:  # no view before a set-up is read (the start)
            self.model_view.set_view(self.stage.view_transform)
        self._sync_view_options()
        self.redraw()

    def _say_unsaid(self) -> None:
        """What was said while no screen could show it (the last one left mid-motion)."""
        for text, level in self.app.take_unsaid():
            self.say_here(text, level)

    def on_resize(self, event: events.Resize) -> None:
        self._layout(event.size.width)

    def _layout(self, width: int, update: bool = True) -> None:
        self.set_class(width >= WIDE, "-wide", update=update)
        self.set_class(width < WIDE, "-narrow", update=update)

    def _sync_view_options(self) -> None:
        view = self.model_view
        view.back_faces = self.stage.back_faces
        view.axes = self.stage.axes

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
        if not self.is_attached:
            return  # left while a motion was drawn: the screen on top draws it
        self.model_view.update_scene(self.stage.scene(self.part_axes))
        if self.stage.session_read is not None:  # none at the first frame, or while the demo starts a round
            self.update_readout()
        self.update_status()

    def update_status(self) -> None:
        """The status line again (a change of the arm's configuration is the core's message,
        ARM CONFIGURATION CHANGED, said after the motion that made it)."""
        self.query_one("#status", StatusLine).refresh_if_changed()

    def update_readout(self) -> None:
        """Subclasses keep their readout current here."""

    # -- what a run does: the player's messages (valterm.ui.messages) ----------------------
    def on_scene_shown(self, message: SceneShown) -> None:
        self._moved = True
        self.redraw()

    def on_picture_moved(self, message: PictureMoved) -> None:
        """A pose between two of a motion's: the model alone (the readout says the poses')."""
        self._moved = True
        if self.is_attached:
            self.model_view.update_scene(self.stage.scene(self.part_axes))

    def on_transcript_lines(self, message: TranscriptLines) -> None:
        self.show_lines(message.lines)

    def on_run_event(self, message: RunEvent) -> None:
        if not self.take_event(message.event):
            self.show_lines(message.lines)

    def show_lines(self, lines: list[str]) -> None:
        for line in lines[-self.messages.max_lines:]:
            self.say(line, "error" if line.startswith("***") else "info")

    def take_event(self, event: Event) -> bool:
        if isinstance(event, Contact):  # a finding: kept with the motion's others, by kind
            for line, level in self._finding_lines(event):
                self.say(line, level)
            return True
        if isinstance(event, Help):
            from valterm.ui.screens.help import HelpScreen  # on first use (issue 25: start)

            self.app.push_screen(HelpScreen(event.topic))
            return True
        if isinstance(event, Monitor):
            self._monitor(event.command, event.argument.strip())
            return True
        return False

    def _monitor(self, command: str, argument: str) -> None:
        """LISTF, LISTL, LISTP, POINT and EDIT typed at a menu's V line (VAL-II mode's own
        transcript shows whole listings; three message lines show their gist here)."""
        from valterm.core.monitor import listing_lines  # the session's: after the first frame
        from valterm.ui.screens.points import define_point

        session = self.stage.active_session
        try:
            if command == "LISTL":
                files = (listing_lines(session, command, argument) or [""])[0]
                names = " ".join(session.simulator.locations) or "NONE"
                self.show_lines([files, f"LOCATIONS: {names} (WHERE EACH IS: LISTL IN VAL-II MODE)"])
            elif (lines := listing_lines(session, command, argument)) is not None:
                self.show_lines(lines)
            elif command == "EDIT":
                from valterm.ui.screens.editor import EditorScreen  # on first use (issue 25: start)

                self.app.push_screen(EditorScreen(session.workspace, argument))
            elif command == "POINT" and "," in argument:
                name = define_point(session, argument)
                self.say(f"POINT {name} DEFINED")
            else:
                self.say(f"{command} {argument}: TYPE NAME, X, Y, Z, O, A, T (POINT A, 465, -45, -245, 89, 91, 0)",
                         "warning")
        except (OSError, ValtermError) as error:  # a missing file, a refused value: said
            self.say(problem_text(error) if isinstance(error, ValtermError) else str(error).upper(), "error")

    def on_run_paused(self, message: RunPaused) -> None:
        """A menu has no PROCEED line: the program goes on (VAL-II mode waits)."""
        self.app.post_message(RunResumed())

    def on_run_ended(self, message: RunEnded) -> None:
        aborted = message.aborted
        moved, self._moved = self._moved, False
        if self.is_attached:
            self.messages.end_turn(self._findings_holding() if moved else None)
        self.redraw()
        if aborted:
            self.say("*** ABORTED ***", "warning")
        self.after_motion(aborted)

    def _findings_holding(self) -> list[tuple[str, str]]:
        """The findings (line, level) that hold where the motion left the robot; the bodies
        of those that collide stay marked in the picture (the core said them once, before)."""
        found = self.stage.simulator.findings_now()
        self.app.post_message(Collided(party for event in found if isinstance(event, Collision)
                                       for party in (event.a, event.b)))
        # once each: under the 1985 words the clamp and a finger near one part are one line
        return list(dict.fromkeys(item for event in found for item in self._finding_lines(event)))

    def _finding_lines(self, event: Contact) -> list[tuple[str, str]]:
        """A finding's lines (line, level): its words, or as the 1985 screen printed them
        (Fig. C-12) with the thesis's keys under the 1985 rules."""
        simulator = self.stage.simulator
        if getattr(self.app, "keys_1985", False) and simulator.rules == RULES_1985:
            from valterm.core.collision.world import bodies  # loaded with the checks that found it

            numbers = {body: n for n, body in enumerate(bodies(simulator.model.names), start=1)}
            return [(line, COLLISION if " COLLIDES WITH " in line else NEAR)
                    for line in figure_lines(event, numbers)]
        return [(finding_line(event), COLLISION if isinstance(event, Collision) else NEAR)]

    def after_motion(self, aborted: bool) -> None:
        """Subclasses' hook after a motion (or a command) ends."""

    def on_scene_changed(self, message: SceneChanged) -> None:
        self._sync_view_options()
        self.redraw()

    def say(self, text: str, level: str = "info") -> None:
        """A message: on this screen while it is shown, else through the app on the one on top."""
        if self.is_attached and self.is_mounted:
            self.say_here(text, level)
        else:
            self.app.say(text, level)

    def say_here(self, text: str, level: str = "info") -> None:
        self.messages.say(text, level)
        self.query_one("#status", StatusLine).refresh()

    # -- shared keys: V (one VAL-II command) and ? (help) ------------------------------
    def action_val(self) -> None:
        self.ask_line("VAL-II COMMAND:", self.run_command)

    def run_command(self, text: str) -> None:
        """One VAL-II command typed at a menu, run through the session's interpreter."""
        if not text:
            return
        try:
            events_ = self.stage.active_session.command(text)
        except Exception as error:
            self.say(problem_text(error), "error")
            return
        self.say(f"    {text.upper()}")
        self.show_model_if_narrow()
        self.app.post_message(RunRequested(_confirm_here(self.stage.simulator, text, events_), self))

    def action_help(self) -> None:
        from valterm.ui.screens.help import HelpScreen  # on first use (issue 25: start)

        title = self.SCREEN_NAME or (self.MENU.splitlines()[0] if self.MENU else "")
        self.app.push_screen(HelpScreen(screen=title, keys=legends.legend(self)))

    # -- questions --------------------------------------------------------------------
    @property
    def asking(self) -> bool:
        return self.question is not None

    def ask_line(self, question: str, then: Callable[[str], None], default: str = "",
                 cancel: Callable[[], None] | None = None, typed: bool = False) -> None:
        """Ask a typed answer (RETURN ends it, ESCAPE cancels); ``typed``: the default is the
        user's first key, kept rather than replaced by what they type next."""
        self.question = Question(then, cancel)
        self.query_one(Prompt).open_line(question, default, typed)

    def ask_key(self, question: str, then: Callable[[str], None], keys: str = "YN",
                cancel: Callable[[], None] | None = None) -> None:
        """Ask a single-key answer among ``keys`` (upper case is passed to ``then``)."""
        self.question = Question(then, cancel, keys.upper())
        self.query_one(Prompt).open_key(question)

    def _close_prompt(self) -> None:
        self.question = None
        self.query_one(Prompt).close()

    def on_input_submitted(self, event: Input.Submitted) -> None:
        event.stop()
        question = self.question
        if question is None or question.single_key:
            return
        self._close_prompt()
        self.messages.clear()   # what was said about the last answer goes, even if this one says nothing
        question.then(event.value.strip())

    # -- the one key path (KeyedScreen.on_key) -----------------------------------------------
    @property
    def key_state(self) -> str:
        question = self.question
        return MENU if question is None else KEY if question.single_key else LINE

    def before_key(self, event: events.Key) -> None:
        self.messages.new_turn()

    def line_taking_keys(self) -> Input | None:
        if self.key_state != LINE:
            return None
        return self.query_one(Prompt).field

    def other_key(self, event: events.Key) -> bool:
        """A one-key answer, or (KEYBOARD, PENDANT) a letter that opens V's command line."""
        question = self.question
        if question is not None:
            self._answer_key(question, event)
            return True
        if self.LETTERS_START_A_COMMAND and event.character and event.character.isalpha():
            self.ask_line("VAL-II COMMAND:", self.run_command, event.character.upper(), typed=True)
            return True  # HERE P1 typed without V: the line takes it all
        return False

    def _answer_key(self, question: Question, event: events.Key) -> None:
        char = (event.character or "").upper()
        keys = question.keys
        if event.key == "enter" and keys:
            char = keys[0] if "\n" in keys else ""
        if char and char in keys:
            self._close_prompt()
            question.then(char)
        elif not keymap.is_silent(event) and event.key != "ctrl+c":
            self.say(keymap.wrong_answer(event, keys, legends.key_for(self, "cancel", "ESC")), "warning")

    def say_wrong_key(self, text: str) -> None:
        self.say(text, "warning")

    def action_cancel(self) -> None:
        """ESC: the open prompt closes (its own way back, or the menu); at the menu, back."""
        question = self.question
        if question is None:
            self.escape_menu()
            return
        self._close_prompt()
        (question.cancel or self.prompt_cancelled)()

    def action_messages(self, direction: int) -> None:
        """SHIFT+UP / SHIFT+DOWN: the message lines a page back or on (a motion's findings)."""
        self.messages.page(direction)

    def action_page(self, direction: int) -> None:
        """PGDN / PGUP: the rest of a menu that does not fit (80x24)."""
        if not self.menu.page(direction):
            self.say("THE WHOLE MENU IS SHOWN")

    def prompt_cancelled(self) -> None:
        """ESC closed a prompt that names no way back: the screen's menu is shown again."""

    def escape_menu(self) -> None:
        """ESC at this screen's menu: back to the MAIN MENU (MAIN itself stays)."""
        self.leave()

    def leave(self) -> None:
        """Back to the screen below, if this one is on top (a key typed ahead of a screen change
        must not close another screen) and never below the first menu screen."""
        if self.app.screen is self and len(self.app.screen_stack) > 2:
            self.app.pop_screen()


def _confirm_here(simulator: Simulator, text: str, events_: Iterator[Event]) -> Iterator[Event]:
    """HERE name: after it is done, say what was taught (the VS11 said nothing)."""
    words = text.upper().replace(",", " ").split()
    yield from events_
    if len(words) == 2 and words[0] == "HERE" and words[1] in simulator.locations:
        taught = simulator.locations[words[1]]
        xyz = ", ".join(map(two_decimals, taught.xyz))
        config = f" {' '.join(taught.config.words)}" if taught.config is not None else ""
        yield Message(f"LOCATION {words[1]} TAUGHT HERE ({xyz}){config}")
