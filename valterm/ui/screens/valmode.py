"""VAL-II mode (App. C §2, Fig. C-13): the command line, the optional VAL-II menu, the model.

The keyboard (issue 17): keys go either to the open command line or to the menu, never both.

- The VAL-II MENU (two pages, the line closed): the thesis's single keys. N turns the page,
  V / C / RETURN open the command line, W wipes the log and opens the line, M shows the model,
  D defines locations, R or ESC return to MAIN; PAGE UP/DOWN scroll a page
  that does not fit (80x24). Any other letter opens the line with it typed (LOAD typed at
  the menu is taken whole).
- The command line stays open between commands, as on the real terminal: every printable
  key is text, so READY, WHERE, MOVE, DEPART, CLOSEI are typed as themselves. The THEN PRESS
  actions of Fig. C-13 are keys that mean nothing else anywhere (issue 27): CTRL-L wipe,
  F8 model (on every screen), CTRL-T define, CTRL-N the VAL-II menu, F9 return to MAIN,
  F10 the I/O panel; F1 is help; F2-F7, the arrows, + and - are the view keys of every
  screen. The thesis's letters work on the VAL-II menu, one ESC away. C ("continue") is
  simply the open line.
  SHIFT+UP / SHIFT+DOWN page the transcript back and on.
- Keys typed while a command plays, or before the line has focus, go into the line (type
  ahead); RETURN typed while a command plays runs the line when it has ended.
- ESC cancels the innermost prompt (D's questions, the .LOC file name, POINT, A/R/E, a
  running or paused program: aborted) and shows the VAL-II menu; ESC there returns to MAIN.
- D defines locations: from a .LOC file, one at a time with the robot shown there (A accept,
  R reject, E accept and end; answers typed during the motion count), or P to type a POINT.
- Narrower than ``WIDE`` columns the text and the model cannot both be readable: the text
  takes the width and M / F8 toggle the model (the thesis's R-like toggle); any other key
  brings the text back.

A running program is played by the app's one player (``valterm.ui.playback``): its steps
scroll through the core's transcript renderer, motions are paced, the screen keeps updating
whatever the program does; PAUSE hands the line to the user until PROCEED; CTRL-C (the
app's key) aborts after the step being simulated, and the program can be run again.

The debugger (BPT, XSTEP, SSTEP, WATCH, TRACE: typed commands) pauses a program the same
way; while it is paused a panel beside the transcript lists the steps around it, that step
highlighted, and the watched variables; CTRL-P PROCEED, CTRL-O XSTEP, CTRL-S SSTEP.
"""

from __future__ import annotations

import re
import time
from collections.abc import Callable, Iterator, Mapping
from enum import StrEnum
from typing import TYPE_CHECKING, ClassVar

from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal, Vertical, VerticalScroll
from textual.events import Key, Resize
from textual.widgets import Input, RichLog, Static

from valterm.core.errors import ValtermError
from valterm.core.events import Error, Event, Help, Monitor, Pause
from valterm.core.files.locations import format_locations
from valterm.core.kinematics import Location
from valterm.core.monitor import listing_lines
from valterm.core.session import Session
from valterm.core.simulator import ConfigMismatch, Simulator
from valterm.core.text.transcript import where_lines, wrap_line
from valterm.ui import legends
from valterm.ui.errors import problem_text
from valterm.ui.keyqueue import typed_at
from valterm.ui.messages import (
    PictureMoved,
    RunAbortRequested,
    RunEnded,
    RunEvent,
    RunPaused,
    RunRequested,
    RunResumed,
    SceneShown,
    TranscriptLines,
)
from valterm.ui.playback import Transcript, show_at_once
from valterm.ui.screens.editor import EditorScreen, StepInput
from valterm.ui.screens.help import HelpScreen
from valterm.ui.screens.keyed import KeyedScreen
from valterm.ui.screens.points import define_point
from valterm.ui.screens.signals import SignalsScreen
from valterm.ui.view.model_view import ModelView
from valterm.ui.widgets.debugpanel import DebugPanel
from valterm.ui.widgets.menus import VAL_MENU_1, VAL_MENU_2
from valterm.ui.widgets.prompt import typed_after
from valterm.ui.widgets.readouts import ReadoutLines
from valterm.ui.widgets.status import StatusLine
from valterm.ui.widgets.transcript_log import TranscriptLog

if TYPE_CHECKING:  # annotations only: the interpreter loads when the screen first runs one
    from valterm.core.val.interpreter import Interpreter


class Mode(StrEnum):
    """Where VAL-II mode's keys go."""

    MENU = "menu"  # the VAL-II MENU pages, the line closed: the thesis's single keys
    COMMAND = "command"  # the command line is open: every printable key is text
    RUNNING = "running"  # the player plays a command or a program (the line takes type-ahead)
    PAUSED = "paused"  # a program waits at PAUSE: the line takes commands and PROCEED
    DEFINE = "define?"  # D: from a file or a typed POINT
    DEFINE_FILE = "define-file"  # the line asks the .LOC file name
    DEFINE_EACH = "define-each"  # A / R / E for the location shown
    POINT = "point"  # the line takes NAME, X, Y, Z, O, A, T
    DEFINE_AHEAD = "define-ahead"  # running to a .LOC file's location: A / R / E answer ahead


LOG_WRITE = 200  # lines written to the log at once (more scroll past unseen within a tick)
LEFT_WIDTH = 72  # columns of the text side when the model is shown beside it
WIDE = LEFT_WIDTH + 40  # narrower than this, the model is toggled instead (80x24)
MENU_FRAME = 6  # the menu's border, padding and scroll bar, in columns

# the key legend under the log, one per mode (F-keys work wherever the line is open); each
# {binding.id} is the key bound now (ui/legends.fill): the keymap file's, else these
LINE_KEYS = ("{valmode.wipe:^} W_WIPE  {view.model} M_MODEL  {valmode.define:^} D_DEFINE  {valmode.menu:^} MENU  "
             "{valmode.leave} R_RETURN  {valmode.io} I/O  {screen.help|F1} HELP  {valmode.escape}: MENU")
MENU_KEYS = ("{valmode.menu.page} PAGE  {valmode.menu.line} LINE  {valmode.menu.wipe} WIPE  "
             "{valmode.menu.model} MODEL  {valmode.menu.define} DEFINE  {valmode.menu.return}/{valmode.escape} RETURN  "
             "{valmode.menu.page_up}/{valmode.menu.page_down} SCROLL  {valmode.io} I/O  {screen.help} HELP")
RUNNING_KEYS = ("RUNNING   {app.abort} OR {valmode.escape}: ABORT   {valmode.io}: I/O PANEL   "
                "(KEYS TYPED NOW GO TO THE LINE)")
# D_DEFINE's question and its answers for each location (menus.DEFINE_HOW, DEFINE_EACH)
DEFINE_KEYS = ("{valmode.define.file}_DATA FILE (.LOC)  {valmode.define.point}_POINT TYPED IN  "
               "{valmode.define.store}_STORE (STOREL)  {valmode.define.line}_RETURN  {valmode.escape}: MENU")
EACH_KEYS = ("{valmode.each.accept}_ACCEPT AND CONTINUE  {valmode.each.reject}_REJECT  "
             "{valmode.each.end}_ACCEPT AND END  {valmode.escape}: MENU")
THEN_PRESS = ("THEN PRESS: {valmode.menu.line|C} CONTINUE  {valmode.menu.wipe} WIPE  "
              "{valmode.menu.return} RETURN  {valmode.menu.model} MODEL  {valmode.menu.define} DEFINE  "
              "{valmode.menu.page} VAL-II MENU  {screen.help} HELP")
PAUSED_KEYS = ("PAUSED: TYPE COMMANDS, {valmode.escape} TO ABORT  {valmode.proceed:^} PROCEED  "
               "{valmode.xstep:^} XSTEP  {valmode.sstep:^} SSTEP  {app.abort} ABORT")

_MENU_ROW = re.compile(r"^(\S.*?\s+[-:] )")  # "TYPE X=          - " : the description column


def wrap_menu(text: str, width: int) -> str:
    """The menu's lines wrapped to ``width`` with the description column kept (hanging indent)."""
    if width < 20:
        return text
    rows: list[str] = []
    for line in text.splitlines():
        head = _MENU_ROW.match(line)
        indent = " " * (len(head.group(1)) if head and len(head.group(1)) < width // 2 else 2)
        rows.extend(wrap_line(line, width, indent))
    return "\n".join(rows)


class ValModeScreen(KeyedScreen[None]):
    """VAL-II mode."""

    AUTO_FOCUS = None
    DEFAULT_CSS = f"""
    ValModeScreen #val-left {{ width: {LEFT_WIDTH}; }}
    ValModeScreen.narrow #val-left {{ width: 1fr; }}
    ValModeScreen.narrow #val-model {{ display: none; }}
    ValModeScreen.model-only #val-left {{ display: none; }}
    ValModeScreen.model-only #val-model {{ display: block; }}
    ValModeScreen #val-menu-scroll {{ height: 1fr; border: round $primary; }}
    ValModeScreen #val-menu {{ padding: 0 1; }}
    ValModeScreen #val-middle {{ height: 1fr; }}
    ValModeScreen #val-log {{ width: 1fr; height: 1fr; border: round $secondary; padding: 0 1;
                             scrollbar-visibility: hidden; }}
    ValModeScreen .hidden {{ display: none; }}
    ValModeScreen #val-keys {{ height: auto; padding: 0 1; color: $accent; }}
    ValModeScreen #val-where {{ height: 4; padding: 0 1; }}
    ValModeScreen #val-prompt-row {{ height: 3; }}
    ValModeScreen #val-prompt {{ width: auto; min-width: 5; padding: 1 1 0 1; }}
    ValModeScreen #val-line {{ width: 1fr; }}
    ValModeScreen #val-model {{ width: 1fr; height: 1fr; }}
    """
    BINDINGS = [
        Binding("escape", "escape", "Back", id="valmode.escape"),
        # none of these is a view key (F2-F7, arrows, + -) or a key of the focused line
        Binding("ctrl+l", "wipe", "Wipe", id="valmode.wipe"),
        Binding("ctrl+t", "define", "Define", id="valmode.define"),
        Binding("ctrl+n", "menu", "Menu", id="valmode.menu"),
        Binding("f9", "leave", "Return", id="valmode.leave"),
        # while a program is paused (the line has the focus: these keys pass it)
        Binding("ctrl+p", "paused_command('PROCEED')", "Proceed", show=False, id="valmode.proceed"),
        Binding("ctrl+o", "paused_command('XSTEP')", "Xstep", show=False, id="valmode.xstep"),
        Binding("ctrl+s", "paused_command('SSTEP')", "Sstep", show=False, id="valmode.sstep"),
        Binding("f10", "io_panel", "I/O panel", show=False, id="valmode.io"),  # screens/signals.py
        # the transcript read back from the keyboard (PGUP/PGDN zoom the view; terminals keep
        # SHIFT+PGUP and CTRL+PGUP for themselves)
        Binding("shift+up", "transcript(-1)", "Back a page in the transcript", show=False,
                id="valmode.transcript_back"),
        Binding("shift+down", "transcript(1)", "On a page in the transcript", show=False,
                id="valmode.transcript_on"),
        # the VAL-II MENU's single keys (Fig. C-13), the line closed
        Binding("n,N", "at_menu('menu')", "Next menu page", show=False, id="valmode.menu.page"),
        Binding("v,V,c,C,enter", "at_menu('line')", "The command line", show=False, id="valmode.menu.line"),
        Binding("w,W", "at_menu('wipe')", "Wipe", show=False, id="valmode.menu.wipe"),
        Binding("m,M", "at_menu('model')", "Model", show=False, id="valmode.menu.model"),
        Binding("d,D", "at_menu('define')", "Define", show=False, id="valmode.menu.define"),
        Binding("r,R", "at_menu('leave')", "Return", show=False, id="valmode.menu.return"),
        Binding("pageup", "at_menu('scroll_page_up')", "Menu page up", show=False, id="valmode.menu.page_up"),
        Binding("pagedown", "at_menu('scroll_page_down')", "Menu page down", show=False,
                id="valmode.menu.page_down"),
        Binding("home", "at_menu('scroll_home')", "Menu top", show=False, id="valmode.menu.home"),
        Binding("end", "at_menu('scroll_end')", "Menu end", show=False, id="valmode.menu.end"),
        # D_DEFINE's question: from a file, a POINT, STOREL, or the line again
        Binding("d,D", "define_how('file')", "From a .LOC file", show=False, id="valmode.define.file"),
        Binding("p,P", "define_how('point')", "Type a POINT", show=False, id="valmode.define.point"),
        Binding("s,S", "define_how('store')", "STOREL: save them", show=False, id="valmode.define.store"),
        Binding("r,R", "define_how('line')", "The command line", show=False, id="valmode.define.line"),
        # each location of a .LOC file (answered while the robot moves there too)
        Binding("a,A", "define_each('A')", "Accept", show=False, id="valmode.each.accept"),
        Binding("r,R", "define_each('R')", "Reject", show=False, id="valmode.each.reject"),
        Binding("e,E", "define_each('E')", "Accept and end", show=False, id="valmode.each.end"),
    ]
    # which keys work in which state: the one place (KeyedScreen.check_action reads it)
    STATES: ClassVar[Mapping[str, frozenset[str]]] = {
        "at_menu": frozenset({Mode.MENU}),
        "define_how": frozenset({Mode.DEFINE}),
        "define_each": frozenset({Mode.DEFINE_EACH, Mode.DEFINE_AHEAD}),
        "paused_command": frozenset({Mode.PAUSED}),
    }

    def __init__(self, session: Session | None = None, *, show_menu: bool = True) -> None:
        super().__init__()
        self._session = session
        self.show_menu = show_menu
        self.mode = Mode.MENU
        self.page = 1
        self._defining: list[tuple[str, Location]] = []
        self._defined: list[str] = []
        self._after_run: Callable[[], None] | None = None
        # A / R / E typed while the robot moved to the location, in order: each answers the
        # next location shown (a key reaches the screen between a motion's end and its stream's
        # when a loaded machine cuts the tick there; one slot lost all but the last)
        self._answers_ahead: list[str] = []
        self._lines_ahead: list[str] = []  # lines entered while a command played, to run next
        self._legend = ""  # the keys line of the mode (shown again after a wrong key)
        self._to_menu = False  # ESC aborted what played: the VAL-II menu when it has ended
        self._pause: Pause | None = None  # what the paused program stopped at (the debugger's panel)
        self._model_for_motion = False  # the model was brought up by a motion (80x24)
        self._menu_since: float | None = None  # --keys 1985: the menu came back after a typed command
        self.transcript = Transcript()  # the last lines the log showed (tests, the demo)

    # -- layout ---------------------------------------------------------------------
    def compose(self) -> ComposeResult:
        with Horizontal():
            with Vertical(id="val-left"):
                yield from self.compose_text()
            yield ModelView(id="val-model")
        yield StatusLine(id="status")  # the lasting status line of every screen (issue 17)

    def compose_text(self) -> ComposeResult:
        """The text side, top to bottom (panels are added here)."""
        with VerticalScroll(id="val-menu-scroll"):
            yield Static(VAL_MENU_1, id="val-menu")
        with Horizontal(id="val-middle"):
            yield TranscriptLog(id="val-log")
            yield DebugPanel(id="val-debug", classes="hidden")  # beside the transcript
        yield Static("", id="val-keys")
        yield ReadoutLines(id="val-where")
        with Horizontal(id="val-prompt-row"):
            yield Static(".", id="val-prompt")
            yield StepInput(id="val-line", placeholder="VAL-II COMMAND")

    @property
    def session(self) -> Session:
        if self._session is None:
            self._session = self.stage.active_session
        return self._session

    @property
    def simulator(self) -> Simulator:
        return self.session.simulator

    @property
    def interpreter(self) -> Interpreter:
        return self.session.interpreter

    def on_mount(self) -> None:
        self.query_one(ModelView).set_view(self.stage.view_transform)  # the app's shared view
        self._fit_width(self.app.size.width)
        self.redraw()
        self.query_one(ModelView).call_after_refresh(self._fit)
        if self.show_menu:
            self._show_menu(1)
        else:
            self.to_command()

    def on_resize(self, event: Resize) -> None:
        self._fit_width(event.size.width)

    def _fit_width(self, width: int) -> None:
        self.set_class(width < WIDE, "narrow")
        self._render_menu()
        self.query_one(ModelView).call_after_refresh(self._fit)

    def _fit(self) -> None:
        view = self.query_one(ModelView)
        view.fit()

    # -- what the screen shows ---------------------------------------------------------
    @property
    def keys_text(self) -> str:
        return str(self.query_one("#val-keys", Static).content)

    @property
    def prompt(self) -> str:
        return str(self.query_one("#val-prompt", Static).content)

    @property
    def menu_text(self) -> str:
        return str(self.query_one("#val-menu", Static).content)

    @property
    def model_only(self) -> bool:
        return self.has_class("model-only")

    def log_line(self, text: str) -> None:
        self.show_lines(str(text).splitlines() or [""])

    def redraw(self) -> None:
        self.query_one(ModelView).update_scene(self.stage.scene())  # with the view's overlays
        self.query_one("#status", StatusLine).refresh_if_changed()  # the arm's configuration, SPEED, ...
        self.query_one("#val-where", ReadoutLines).show_lines(where_lines(self.simulator.where()))

    def _keys(self, text: str) -> None:
        text = legends.fill(self, text)  # the keys as they are bound now
        self._legend = text
        self.query_one("#val-keys", Static).update(text)

    def _render_menu(self) -> None:
        width = (self.app.size.width if self.has_class("narrow") else LEFT_WIDTH) - MENU_FRAME
        menu = legends.live_menu(self, VAL_MENU_1 if self.page == 1 else VAL_MENU_2, Mode.MENU)  # keys bound now
        for page in ("NEXT", "FIRST"):  # the pages' last line: "N: NEXT PAGE   V: TO VAL-II MODE   R: RETURN"
            menu = menu.replace(f"N: {page} PAGE   V: TO VAL-II MODE   R: RETURN", legends.fill(self, (
                f"{{valmode.menu.page}}: {page} PAGE   {{valmode.menu.line}}: TO VAL-II MODE   "
                "{valmode.menu.return}: RETURN")))
        self.query_one("#val-menu", Static).update(wrap_menu(menu, width))

    def _show_menu(self, page: int) -> None:
        self.mode, self.page = Mode.MENU, page
        self._render_menu()
        menu = self.query_one("#val-menu-scroll", VerticalScroll)
        menu.remove_class("hidden")
        menu.scroll_home(animate=False)
        self.query_one("#val-middle").add_class("hidden")
        self._keys(MENU_KEYS)
        self._close_line()

    def _open_line(self, mode: Mode, prompt: str, start: str = "", placeholder: str = "VAL-II COMMAND") -> None:
        self.mode = mode
        self.query_one("#val-menu-scroll").add_class("hidden")
        self.query_one("#val-middle").remove_class("hidden")
        self.query_one("#val-prompt-row").remove_class("hidden")
        self.query_one("#val-prompt", Static).update(prompt)
        field = self.query_one("#val-line", StepInput)
        field.disabled = False
        field.placeholder = placeholder
        field.select_on_focus = False    # what is in the line was typed: typing goes on after it
        field.value = start
        field.cursor_position = len(start)
        field.focus()

    def _close_line(self) -> None:
        self.query_one("#val-prompt-row").add_class("hidden")
        field = self.query_one("#val-line", StepInput)
        field.value = ""
        field.disabled = True  # a closed line never takes a key (type_ahead leaves it alone)
        self.set_focus(None)

    def to_command(self, start: str = "") -> None:
        self._keys(LINE_KEYS)
        self._open_line(Mode.COMMAND, ".", start)

    # -- keys: the one key path (KeyedScreen.on_key) -----------------------------------------
    @property
    def key_state(self) -> str:
        if self.mode == Mode.RUNNING and self._defining:
            return Mode.DEFINE_AHEAD
        return self.mode

    def before_key(self, event: Key) -> None:
        """The model alone (80x24): a typed key or one that means nothing here brings the text
        back (and still counts); ESC, CTRL-C and the keys that turn or toggle the view do not."""
        key = event.key
        if not self.model_only or key in ("escape", "ctrl+c") or (key[0] == "f" and key[1:].isdigit()):
            return
        if event.is_printable or not self.bound_here(key):
            self.remove_class("model-only")

    def line_taking_keys(self) -> StepInput | None:
        field = self.query_one("#val-line", StepInput)
        return None if field.disabled else field  # the open line takes every key, typed ahead too

    def other_key(self, event: Key) -> bool:
        if self.mode == Mode.MENU and event.is_printable and (event.character or "").isalpha():
            self.to_command(event.character.upper())  # type: ignore[union-attr]  # LOAD at the menu
            return True
        return self.mode == Mode.RUNNING  # while the robot moves to a location: nothing else

    def say_wrong_key(self, text: str) -> None:
        legend = self._legend
        self._keys(f"{text}   {legend}")
        self._legend = legend

    def action_at_menu(self, what: str) -> None:
        """A key of the VAL-II MENU: its action, or the menu scrolled (80x24)."""
        if what.startswith("scroll_"):
            getattr(self.query_one("#val-menu-scroll", VerticalScroll), what)(animate=False)
        elif what == "line":
            self.to_command()
        else:
            getattr(self, f"action_{what}")()

    def action_define_how(self, how: str) -> None:
        """D_DEFINE's answer: a .LOC file, a typed POINT, STOREL, or the line again."""
        if how == "store":  # the locations to a .LOC file: STOREL on the line, the name to type
            self.to_command("STOREL ")
            self._keys("TYPE THE .LOC FILE NAME, RETURN (STOREL NAME WRITES NAME.LOC)   {valmode.escape}: MENU")
        elif how == "file":
            self._open_line(Mode.DEFINE_FILE, "LOCATION FILE NAME:", "", "e.g. PROCESS.LOC")
            self._keys("TYPE THE .LOC FILE NAME, RETURN   {valmode.escape}: MENU")
        elif how == "point":
            self._open_line(Mode.POINT, "POINT", "", "NAME, X, Y, Z, O, A, T")
            self._keys("TYPE NAME, X, Y, Z, O, A, T   RETURN   {valmode.escape}: MENU")
        else:
            self.to_command()

    def action_define_each(self, key: str) -> None:
        """A, R or E for the location shown (or typed while the robot still moves there)."""
        if self.mode == Mode.DEFINE_EACH:
            self._define_answer(key)
        else:
            self._answers_ahead.append(key)

    def action_help(self) -> None:
        """? (at the menu and its questions) and F1 (everywhere): this screen's keys, then HELP."""
        self.app.push_screen(HelpScreen(screen="VAL-II MODE", keys=legends.legend(self)))

    def toggle_model(self) -> None:
        """F8, the model key of every screen."""
        self.action_model()

    def action_transcript(self, direction: int) -> None:
        """SHIFT+UP / SHIFT+DOWN: the transcript a page back or on (the next line written
        scrolls it to the end again)."""
        log = self.query_one("#val-log", RichLog)
        page = max(1, log.scrollable_content_region.height - 1)
        log.scroll_to(y=log.scroll_y + direction * page, animate=False)

    def action_wipe(self) -> None:
        """W_WIPE: the log cleared, the line open."""
        if self.mode in (Mode.MENU, Mode.COMMAND):
            self.query_one("#val-log", RichLog).clear()
            self.to_command(self._typed() if self.mode == Mode.COMMAND else "")

    def action_model(self) -> None:
        """M_MODEL: the model alone (toggles); any other key brings the text back."""
        self.toggle_class("model-only")
        self.query_one(ModelView).call_after_refresh(self._fit)

    def action_define(self) -> None:
        """D_DEFINE: locations from a .LOC file or a typed POINT."""
        if self.mode in (Mode.MENU, Mode.COMMAND):
            self.query_one("#val-menu-scroll").add_class("hidden")
            self.query_one("#val-middle").remove_class("hidden")
            self._close_line()
            self.mode = Mode.DEFINE
            self._keys(DEFINE_KEYS)

    def action_menu(self) -> None:
        """The VAL-II menu (its next page when it is shown)."""
        if self.mode == Mode.MENU:
            self._show_menu(2 if self.page == 1 else 1)
        elif self.mode not in (Mode.RUNNING, Mode.PAUSED):
            self._cancel_to_menu()

    def action_leave(self) -> None:
        """R_RETURN: back to MAIN (a running program is aborted first)."""
        if self.mode in (Mode.RUNNING, Mode.PAUSED):
            self._to_menu = True
            self.app.post_message(RunAbortRequested())
            return
        self.dismiss(None)

    def takes_typed_now(self, event: Key) -> bool:
        """While a command or a program runs, the open line takes text, BACKSPACE and RETURN
        as they are typed, a motion drawn or not (``ui.keyqueue``): the RUNNING line says KEYS
        TYPED NOW GO TO THE LINE, and RETURN queues the line (QUEUED). Not the model alone
        (80x24), whose line is hidden, nor under --keys 1985 (its type-ahead waits)."""
        if self.mode != Mode.RUNNING or self.model_only or self.keys_1985:
            return False
        line = self.line_taking_keys()
        if line is None or not line.has_focus:
            return False
        return event.is_printable or event.key in ("backspace", "enter")

    def escape_aborts(self) -> bool:
        """ESC now aborts the program or command that runs (the RUNNING and PAUSED key lines
        say so): the key queue lets it past the keys typed during the run (``ui.keyqueue``)."""
        return self.mode in (Mode.RUNNING, Mode.PAUSED) and not (self.model_only and not self._model_for_motion)

    def action_escape(self) -> None:
        """ESC: cancel the innermost prompt and show the VAL-II menu; on the menu, MAIN."""
        if self.escape_aborts():
            self._to_menu = True
            self.app.post_message(RunAbortRequested())
        elif self.model_only and not self._model_for_motion:  # the model asked for: ESC leaves it
            self.remove_class("model-only")
        elif self.mode == Mode.MENU:
            self.dismiss(None)
        else:
            self._cancel_to_menu()

    def _cancel_to_menu(self) -> None:
        if self._defining or self._defined:  # reading a .LOC file: what was accepted stays
            self.log_line(f"LOCATIONS DEFINED: {', '.join(self._defined) or 'NONE'}")
        self._defining, self._defined, self._answers_ahead = [], [], []
        self._discard_queued()
        self._show_menu(self.page)

    def _typed(self) -> str:
        return self.query_one("#val-line", StepInput).value

    # -- typed lines -----------------------------------------------------------------------
    def on_input_submitted(self, event: Input.Submitted) -> None:
        event.stop()
        text = event.value
        field = self.query_one("#val-line", StepInput)
        field.value = typed_after(field, text)  # keys typed after RETURN start the next line
        field.cursor_position = len(field.value)
        if self.mode == Mode.RUNNING:
            self._queue(text)
            return
        if self.mode == Mode.DEFINE_FILE:
            self._define_from_file(text)
        elif self.mode == Mode.POINT:
            self._define_point(text)
        elif self.mode == Mode.PAUSED:
            self.action_paused_command(text)
        elif self.mode == Mode.COMMAND:
            self.run_command(text)

    def action_io_panel(self) -> None:
        """F10: the I/O panel over VAL-II mode (a running program goes on beneath it)."""
        self.app.push_screen(SignalsScreen(self.session))

    def action_paused_command(self, text: str) -> None:
        """A command while a program is paused (typed, or F5 / F7 / F8)."""
        if self.mode != Mode.PAUSED:
            return
        self.log_line(f". {text}")
        self.show_lines(show_at_once(self.session.command(text), self.take_event))
        self.redraw()
        if not self.session.program_paused:  # PROCEED, XSTEP, SSTEP
            self._show_running(keep_line=True)
            self.app.post_message(RunResumed())
        elif self._pause is not None:
            self._show_pause(self._pause)  # WATCH, X=5 ... show at once

    def run_command(self, text: str) -> None:
        """A typed command line: echoed, then played (the line stays open for type-ahead)."""
        if not text.strip():
            return
        self.log_line(f". {text}")
        if self.keys_1985:  # the VAL-II menu after it (Fig. C-13): C continues on the line
            self.run_events(self.session.command(text), after=self._menu_after_command)
        else:
            self.run_events(self.session.command(text))

    @property
    def keys_1985(self) -> bool:
        """The thesis's keyboard (``valterm --keys 1985``): the menu after each command."""
        return self.stage.keys_1985

    def _menu_after_command(self) -> None:
        """--keys 1985: the menu after a typed command; what was typed while it played is the
        next line's (``on_key``)."""
        self._after_command()
        self._menu_since = time.monotonic()

    def on_key(self, event: Key) -> None:
        """--keys 1985: a letter typed while the command played, before the menu came back
        (READY typed at once), opens the line with it; the rest follows it there (issue 35).
        Any other key goes the one key path (KeyedScreen.on_key)."""
        since = self._menu_since
        if since is None or self.mode != Mode.MENU or not event.is_printable or not event.character:
            return
        if typed_at(event) >= since:
            self._menu_since = None  # typed at the menu: the menu's keys
            return
        event.stop()
        event.prevent_default()
        self.to_command(event.character)

    def _after_command(self) -> None:
        """A command, a POINT or the .LOC file's locations are done: the line again (1985:
        the VAL-II menu, whose C continues on the line)."""
        if self.keys_1985:  # Fig. C-13's THEN PRESS: the transcript stays in sight
            self.mode = Mode.MENU
            self._close_line()
            self._keys(THEN_PRESS)
        else:
            self.to_command()
            self._run_queued()

    # -- commands typed while one plays -----------------------------------------------------
    def _queue(self, text: str) -> None:
        """A line entered while a command or a program plays: said, and run when it has ended."""
        if text.strip():
            self._lines_ahead.append(text)
            self.log_line(f"QUEUED: {text}")

    def _run_queued(self) -> None:
        """The lines queued meanwhile, in order, once the line is open again."""
        while self._lines_ahead and self.mode == Mode.COMMAND:
            self.run_command(self._lines_ahead.pop(0))

    def _discard_queued(self) -> None:
        """An abort (CTRL-C, ESC, F9) drops the queued lines, and says which: what was typed
        to follow the program's end must not run after the user stopped it (a MOVE would move
        the arm right after the stop), as a terminal drops its type-ahead at CTRL-C."""
        lines, self._lines_ahead = self._lines_ahead, []
        if lines:
            many = "S" if len(lines) > 1 else ""
            self.log_line(f"{len(lines)} QUEUED COMMAND{many} DISCARDED: {', '.join(line.strip() for line in lines)}")

    # -- playing events: asked of the app by message (ui.messages) -------------------------
    def run_events(self, events: Iterator[Event], after: Callable[[], None] | None = None) -> None:
        """Ask the app to play a stream of core events (RunRequested); ``after`` when it has ended.

        Without ``after`` the command line stays open and takes what is typed meanwhile."""
        self._after_run = after
        self._to_menu = False
        self._show_running(keep_line=after is None)
        self.app.post_message(RunRequested(events, self))

    def _show_running(self, keep_line: bool) -> None:
        self._pause = None
        self.query_one(DebugPanel).hide()
        self.mode = Mode.RUNNING
        if not keep_line:
            self._close_line()
        elif self.query_one("#val-line", StepInput).disabled:
            self._open_line(Mode.RUNNING, ".")
        self.query_one("#val-prompt", Static).update(".")
        self._keys(RUNNING_KEYS)

    # -- what a run does: the player's messages (valterm.ui.messages) ----------------------
    def on_scene_shown(self, message: SceneShown) -> None:
        if self.has_class("narrow") and not self.model_only and self.mode == Mode.RUNNING:
            self.add_class("model-only")  # 80x24: the robot is on screen whenever it moves
            self._model_for_motion = True
            self.query_one(ModelView).call_after_refresh(self._fit)
        self.redraw()

    def on_picture_moved(self, message: PictureMoved) -> None:
        """A pose between two of a motion's: the model alone (WHERE says the poses')."""
        self.query_one(ModelView).update_scene(self.stage.scene())

    def on_transcript_lines(self, message: TranscriptLines) -> None:
        self.show_lines(message.lines)

    def on_run_event(self, message: RunEvent) -> None:
        if not self.take_event(message.event):
            self.show_lines(message.lines)

    def _text_after_motion(self) -> None:
        """The text again once what moved the robot has ended or paused (80x24)."""
        if self._model_for_motion:
            self._model_for_motion = False
            self.remove_class("model-only")

    def show_lines(self, lines: list[str]) -> None:
        if not lines:
            return  # a command with nothing to say (PROCEED) leaves no blank line
        self.transcript.extend(lines)
        # one write a tick, of what a screen can show: a TYPE loop scrolls, it does not stall
        self.query_one("#val-log", TranscriptLog).write_lines(lines[-LOG_WRITE:])

    def take_event(self, event: Event) -> bool:
        if isinstance(event, Help):
            self.app.push_screen(HelpScreen(event.topic))
            return True
        if isinstance(event, Monitor):
            self._monitor(event)
            return True
        return False

    def on_run_paused(self, message: RunPaused) -> None:
        pause = message.pause
        self._text_after_motion()
        self._keys(PAUSED_KEYS)
        self._open_line(Mode.PAUSED, "PAUSED .", self._typed())
        self._pause = pause
        self._show_pause(pause)

    def _show_pause(self, pause: Pause) -> None:
        """The debugger's panel: the steps around the paused one, the watched variables."""
        debugger = self.interpreter.debugger
        listing = debugger.listing(pause.program, pause.step)
        self.query_one(DebugPanel).show_pause(pause.program, pause.step, listing, debugger.watched())

    def on_run_ended(self, message: RunEnded) -> None:
        aborted = message.aborted
        self._text_after_motion()
        self._pause = None
        self.query_one(DebugPanel).hide()
        self.redraw()
        after, self._after_run = self._after_run, None
        if aborted:  # CTRL-C or ESC: what was typed ahead goes too, said (as on a terminal)
            self._discard_queued()
        if self._to_menu:  # ESC (or F9) stopped it: the VAL-II menu
            self._to_menu = False
            self._cancel_to_menu()
        elif after is not None:
            after()
        else:
            self.to_command(self._typed())  # what is being typed stays in the line
            self._run_queued()

    def _monitor(self, event: Monitor) -> None:
        workspace = self.session.workspace
        command, argument = event.command, event.argument.strip()
        try:
            lines = listing_lines(self.session, command, argument)  # LISTF, LISTL, LISTP
            if lines is not None:
                self.show_lines(lines)
            elif command == "EDIT":
                self.app.push_screen(EditorScreen(workspace, argument))
            elif command == "POINT" and "," in argument:  # the one-line form: defined now
                self._after_run = lambda: self._define_point(argument)
            elif command == "POINT":
                self._after_run = lambda: self._open_line(Mode.POINT, "POINT", f"{argument}, " if argument else "",
                                                          "NAME, X, Y, Z, O, A, T")
                self._keys("TYPE NAME, X, Y, Z, O, A, T   RETURN   {valmode.escape}: MENU")
        except Exception as error:  # a missing or damaged file: say so, stay in VAL-II mode
            self.log_line(problem_text(error))

    # -- D_DEFINE: locations ----------------------------------------------------------------------
    def _define_from_file(self, typed: str) -> None:
        name = typed.strip().upper().removesuffix(".LOC")
        if not name:
            self.to_command()
            return
        try:
            points = self.session.workspace.read_locations(name)
        except Exception as error:
            self.log_line(f"*** {problem_text(error)}")
            self._open_line(Mode.DEFINE_FILE, "LOCATION FILE NAME:", "", "e.g. PROCESS.LOC")
            return
        self.log_line(f"READING {name}.LOC: {len(points)} LOCATIONS")
        self._defining = list(points.items())
        self._defined = []
        self._define_next()

    def _define_next(self) -> None:
        if not self._defining:
            self._define_done()
            return
        name, location = self._defining[0]
        self.log_line(format_locations({name: location}).rstrip())

        def moved() -> None:
            self.mode = Mode.DEFINE_EACH
            self._keys(f"{name}: {EACH_KEYS}")
            if self._answers_ahead:
                self._define_answer(self._answers_ahead.pop(0))

        def motion() -> Iterator[Event]:
            try:
                yield from self.simulator.move(location, name=name)
            except ConfigMismatch as error:  # reachable, in the other configuration: say that
                yield Error("", 0, str(error))
            except ValtermError as error:
                yield Error("", 0, f"THE ROBOT CANNOT REACH {name}: {error}")

        self.run_events(motion(), after=moved)

    def _define_answer(self, key: str) -> None:
        name, location = self._defining.pop(0)
        if key in ("A", "E"):
            self.session.define_location(name, location, stored=True)  # as its file holds it
            self._defined.append(name)
            self.log_line(f"{name} ACCEPTED")
        else:
            self.log_line(f"{name} REJECTED")
        if key == "E":
            self._defining = []
        self._define_next()

    def _define_done(self) -> None:
        names = ", ".join(self._defined) or "NONE"
        self.log_line(f"LOCATIONS DEFINED: {names}")
        self._defined, self._answers_ahead = [], []
        self._after_command()

    def _define_point(self, typed: str) -> None:
        """POINT typed in by hand: NAME, X, Y, Z, O, A, T."""
        try:
            name = define_point(self.session, typed)
        except ValtermError as error:
            self.log_line(f"*** {problem_text(error)}")
            self._open_line(Mode.POINT, "POINT", typed, "NAME, X, Y, Z, O, A, T")
            return
        self.log_line(f"POINT {name} DEFINED")
        self._after_command()
