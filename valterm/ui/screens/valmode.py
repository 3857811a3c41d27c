"""VAL-II mode (App. C §2, Fig. C-13): the command line, the optional VAL-II menu, the model.

It opens on the VAL-II MENU (two pages: N turns the page, V goes to the command line, R
returns). A typed line (label columns first, TAB to column 5) goes to the interpreter;
after each command the THEN PRESS keys of Fig. C-13 apply: C continue, W wipe, R return,
M model, D define locations (from a .LOC file, one at a time with the robot shown there:
A accept, R reject, E accept and end; or P to type a POINT by hand). Any other key starts
the next command line with that key, as the example session types ``LE`` then ``AB``.

A running program is played by the app's one player (``valterm.ui.playback``): its steps
scroll through the core's transcript renderer, motions are paced, the screen keeps updating
whatever the program does; PAUSE hands the line to the user until PROCEED; CTRL-C (the
app's key) aborts after the step being simulated, and the program can be run again.

The debugger (BPT, XSTEP, SSTEP, WATCH, TRACE: typed commands) pauses a program the same
way; while it is paused a panel beside the transcript lists the steps around it, that step
highlighted, and the watched variables; F5 PROCEED, F7 XSTEP, F8 SSTEP.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from enum import StrEnum

from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal, Vertical
from textual.events import Key
from textual.screen import Screen
from textual.widgets import RichLog, Static

from valterm.core.errors import ValtermError
from valterm.core.events import Error, Event, Help, Monitor, Pause
from valterm.core.files.locations import check_location_name, format_locations
from valterm.core.kinematics import Location
from valterm.core.monitor import listing_lines
from valterm.core.session import Session
from valterm.core.text.transcript import where_lines
from valterm.ui.errors import Refusal, problem_text
from valterm.ui.playback import TRANSCRIPT_LINES, Player, Transcript, show_at_once
from valterm.ui.screens.editor import EditorScreen, StepInput
from valterm.ui.screens.help import HelpScreen
from valterm.ui.screens.signals import SignalsScreen
from valterm.ui.view.model_view import ModelView
from valterm.ui.widgets.debugpanel import PAUSED_KEYS, DebugPanel
from valterm.ui.widgets.menus import (
    DEFINE_EACH,
    DEFINE_HOW,
    THEN_PRESS,
    VAL_MENU_1,
    VAL_MENU_2,
)
from valterm.ui.widgets.scene import simulator_scene


class Mode(StrEnum):
    """Where VAL-II mode's keys go."""

    MENU = "menu"  # the VAL-II MENU pages: N, V, R
    COMMAND = "command"  # the command line is open
    AFTER = "after"  # the THEN PRESS keys of Fig. C-13
    RUNNING = "running"  # the player plays a command or a program: only CTRL-C counts
    PAUSED = "paused"  # a program waits at PAUSE: the line takes commands and PROCEED
    MODEL = "model"  # the model alone: any key returns
    DEFINE = "define?"  # D: from a file or a typed POINT
    DEFINE_FILE = "define-file"  # the line asks the .LOC file name
    DEFINE_EACH = "define-each"  # A / R / E for the location shown
    POINT = "point"  # the line takes NAME, X, Y, Z, O, A, T


LOG_WRITE = 200  # lines written to the log at once (more scroll past unseen within a tick)

# modes in which the open line takes every key
LINE_MODES = (Mode.COMMAND, Mode.PAUSED, Mode.DEFINE_FILE, Mode.POINT, Mode.RUNNING)


class ValModeScreen(Screen[None]):
    """VAL-II mode."""

    AUTO_FOCUS = None
    DEFAULT_CSS = """
    ValModeScreen #val-left { width: 72; }
    ValModeScreen #val-left.model-only { display: none; }
    ValModeScreen #val-middle { height: 1fr; }
    ValModeScreen #val-menu { width: 1fr; height: 1fr; padding: 0 1; border: round $primary; }
    ValModeScreen #val-log { width: 1fr; height: 1fr; border: round $secondary; padding: 0 1; }
    ValModeScreen .hidden { display: none; }
    ValModeScreen #val-keys { height: auto; padding: 0 1; color: $accent; }
    ValModeScreen #val-where { height: 4; padding: 0 1; }
    ValModeScreen #val-prompt-row { height: 3; }
    ValModeScreen #val-prompt { width: auto; min-width: 5; padding: 1 1 0 1; }
    ValModeScreen #val-line { width: 1fr; }
    ValModeScreen #val-model { width: 1fr; height: 1fr; }
    """
    BINDINGS = [
        Binding("escape", "escape", "Back", id="valmode.escape"),
        # while a program is paused (the line has the focus: function keys pass it)
        Binding("f5", "paused_command('PROCEED')", "Proceed", show=False, id="valmode.proceed"),
        Binding("f7", "paused_command('XSTEP')", "Xstep", show=False, id="valmode.xstep"),
        Binding("f8", "paused_command('SSTEP')", "Sstep", show=False, id="valmode.sstep"),
        Binding("f6", "io_panel", "I/O panel", show=False, id="valmode.io"),  # screens/signals.py
    ]

    def __init__(self, session: Session | None = None, *, show_menu: bool = True) -> None:
        super().__init__()
        self._session = session
        self.show_menu = show_menu
        self.mode = Mode.MENU
        self.page = 1
        self._defining: list[tuple[str, Location]] = []
        self._defined: list[str] = []
        self._after_run: Callable[[], None] | None = None
        self._pause: Pause | None = None  # what the paused program stopped at (the debugger's panel)
        self.transcript = Transcript()  # the last lines the log showed (tests, the demo)

    # -- layout ---------------------------------------------------------------------
    def compose(self) -> ComposeResult:
        with Horizontal():
            with Vertical(id="val-left"):
                with Horizontal(id="val-middle"):
                    yield Static(VAL_MENU_1, id="val-menu")
                    yield RichLog(id="val-log", wrap=True, markup=False, max_lines=TRANSCRIPT_LINES)
                    yield DebugPanel(id="val-debug", classes="hidden")  # beside the transcript
                yield Static("", id="val-keys")
                yield Static("", id="val-where")
                with Horizontal(id="val-prompt-row"):
                    yield Static(".", id="val-prompt")
                    yield StepInput(id="val-line", placeholder="VAL-II COMMAND")
            yield ModelView(id="val-model")

    @property
    def session(self) -> Session:
        if self._session is None:
            self._session = self.app.session  # type: ignore[attr-defined]
        assert self._session is not None
        return self._session

    @property
    def simulator(self):  # type: ignore[no-untyped-def]
        return self.session.simulator

    @property
    def interpreter(self):  # type: ignore[no-untyped-def]
        return self.session.interpreter

    @property
    def player(self) -> Player:
        """The app's one event player."""
        player: Player = self.app.player  # type: ignore[attr-defined]
        return player

    def on_mount(self) -> None:
        self.redraw()
        self.query_one(ModelView).call_after_refresh(self._fit)
        if self.show_menu:
            self._show_menu(1)
        else:
            self.to_command()

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

    def log_line(self, text: str) -> None:
        self.show_lines(str(text).splitlines() or [""])

    def redraw(self) -> None:
        self.query_one(ModelView).update_scene(simulator_scene(self.simulator))
        self.query_one("#val-where", Static).update("\n".join(where_lines(self.simulator.where())))

    def _keys(self, text: str) -> None:
        self.query_one("#val-keys", Static).update(text)

    def _show_menu(self, page: int) -> None:
        self.mode, self.page = Mode.MENU, page
        menu = self.query_one("#val-menu", Static)
        menu.update(VAL_MENU_1 if page == 1 else VAL_MENU_2)
        menu.remove_class("hidden")
        self.query_one("#val-log").add_class("hidden")
        self._keys("")
        self._close_line()

    def _open_line(self, mode: Mode, prompt: str, start: str = "", placeholder: str = "VAL-II COMMAND") -> None:
        self.mode = mode
        self.query_one("#val-menu").add_class("hidden")
        self.query_one("#val-log").remove_class("hidden")
        self.query_one("#val-left").remove_class("model-only")
        self.query_one("#val-prompt-row").remove_class("hidden")
        self.query_one("#val-prompt", Static).update(prompt)
        field = self.query_one("#val-line", StepInput)
        field.disabled = False
        field.placeholder = placeholder
        field.value = start
        field.cursor_position = len(start)
        field.focus()

    def _close_line(self) -> None:
        self.query_one("#val-prompt-row").add_class("hidden")
        self.set_focus(None)

    def to_command(self, start: str = "") -> None:
        self._keys("")
        self._open_line(Mode.COMMAND, ".", start)

    def to_after(self) -> None:
        self.mode = Mode.AFTER
        self._close_line()
        self._keys(THEN_PRESS)

    # -- keys ----------------------------------------------------------------------------
    def on_key(self, event: Key) -> None:
        char = (event.character or "").upper()
        mode = self.mode
        if mode in LINE_MODES or event.key in ("escape", "ctrl+c", "f6"):  # F6: the I/O panel
            return  # the line takes the keys; while running only CTRL-C (the app's) counts
        event.stop()
        event.prevent_default()
        if mode == Mode.MENU:
            if char == "N":
                self._show_menu(2 if self.page == 1 else 1)
            elif char == "V" or event.key == "enter":
                self.to_command()
            elif char == "R":
                self.dismiss(None)
        elif mode == Mode.MODEL:
            self.query_one("#val-left").remove_class("model-only")
            self.to_after()
        elif mode == Mode.AFTER:
            self._after_key(char, event)
        elif mode == Mode.DEFINE:
            if char == "D":
                self._open_line(Mode.DEFINE_FILE, "LOCATION FILE NAME:", "", "e.g. PROCESS.LOC")
            elif char == "P":
                self._open_line(Mode.POINT, "POINT", "", "NAME, X, Y, Z, O, A, T")
            elif char == "R":
                self.to_after()
        elif mode == Mode.DEFINE_EACH:
            if char in ("A", "R", "E"):
                self._define_answer(char)

    def _after_key(self, char: str, event: Key) -> None:
        if char == "C":
            self.to_command()
        elif char == "W":
            self.query_one("#val-log", RichLog).clear()
            self.to_command()
        elif char == "R":
            self.dismiss(None)
        elif char == "M":
            self.mode = Mode.MODEL
            self.query_one("#val-left").add_class("model-only")
            self._keys("")
        elif char == "D":
            self.mode = Mode.DEFINE
            self._keys(DEFINE_HOW)
        elif event.key == "enter":
            self.to_command()
        elif event.key == "tab":
            self.to_command("    ")
        elif event.character and event.character.isprintable():
            self.to_command(event.character)  # the next command starts with this key

    def action_escape(self) -> None:
        if self.mode in (Mode.RUNNING, Mode.PAUSED):
            return  # CTRL-C ends a program, not ESCAPE
        if self.mode in (Mode.COMMAND, Mode.AFTER, Mode.MENU):
            self.dismiss(None)
        elif self.mode in (Mode.DEFINE, Mode.DEFINE_FILE, Mode.POINT, Mode.MODEL):
            self.to_after()

    # -- typed lines -----------------------------------------------------------------------
    def on_input_submitted(self, event) -> None:  # type: ignore[no-untyped-def]
        event.stop()
        text = event.value
        self.query_one("#val-line", StepInput).value = ""
        if self.mode == Mode.DEFINE_FILE:
            self._define_from_file(text)
        elif self.mode == Mode.POINT:
            self._define_point(text)
        elif self.mode == Mode.PAUSED:
            self.action_paused_command(text)
        elif self.mode == Mode.COMMAND:
            if not text.strip():
                return
            self.log_line(f". {text}")
            self.run_events(self.session.command(text))

    def action_io_panel(self) -> None:
        """F6: the I/O panel over VAL-II mode (a running program goes on beneath it)."""
        self.app.push_screen(SignalsScreen(self.session))

    def action_paused_command(self, text: str) -> None:
        """A command while a program is paused (typed, or F5 / F7 / F8)."""
        if self.mode != Mode.PAUSED:
            return
        self.log_line(f". {text}")
        show_at_once(self.session.command(text), self)
        if not self.session.program_paused:  # PROCEED, XSTEP, SSTEP
            self._show_running()
            self.player.resume()
        elif self._pause is not None:
            self._show_pause(self._pause)  # WATCH, X=5 ... show at once

    # -- playing events (the player's audience) --------------------------------------------
    def run_events(self, events: Iterator[Event], after: Callable[[], None] | None = None) -> None:
        """Play a stream of core events on the app's player; ``after`` when it has ended."""
        self._after_run = after
        self._show_running()
        self.app.run_events(events, self)  # type: ignore[attr-defined]

    def _show_running(self) -> None:
        self._pause = None
        self.query_one(DebugPanel).hide()
        self.mode = Mode.RUNNING
        self._close_line()
        self._keys("RUNNING   CTRL-C: ABORT   F6: I/O PANEL")

    def show_scene(self) -> None:
        self.redraw()

    def show_lines(self, lines: list[str]) -> None:
        if not lines:
            return  # a command with nothing to say (PROCEED) leaves no blank line
        self.transcript.extend(lines)
        # one write a tick, of what a screen can show: a TYPE loop scrolls, it does not stall
        self.query_one("#val-log", RichLog).write("\n".join(lines[-LOG_WRITE:]))

    def take_event(self, event: Event) -> bool:
        if isinstance(event, Help):
            self.app.push_screen(HelpScreen(event.topic))
            return True
        if isinstance(event, Monitor):
            self._monitor(event)
            return True
        return False

    def paused(self, pause: Pause) -> None:
        self._keys(f"PAUSED: TYPE COMMANDS  {PAUSED_KEYS}")
        self._open_line(Mode.PAUSED, "PAUSED .")
        self._pause = pause
        self._show_pause(pause)

    def _show_pause(self, pause: Pause) -> None:
        """The debugger's panel: the steps around the paused one, the watched variables."""
        debugger = self.interpreter.debugger
        listing = debugger.listing(pause.program, pause.step)
        self.query_one(DebugPanel).show_pause(pause.program, pause.step, listing, debugger.watched())

    def played(self, aborted: bool) -> None:
        self._pause = None
        self.query_one(DebugPanel).hide()
        self.redraw()
        after, self._after_run = self._after_run, None
        if after is not None:
            after()
        else:
            self.to_after()

    def _monitor(self, event: Monitor) -> None:
        workspace = self.session.workspace
        command, argument = event.command, event.argument.strip()
        try:
            lines = listing_lines(self.session, command, argument)  # LISTF, LISTL, LISTP
            if lines is not None:
                self.show_lines(lines)
            elif command == "EDIT":
                self.app.push_screen(EditorScreen(workspace, argument))
            elif command == "POINT":
                self._after_run = lambda: self._open_line(Mode.POINT, "POINT", f"{argument}, " if argument else "",
                                                          "NAME, X, Y, Z, O, A, T")
        except Exception as error:  # a missing or damaged file: say so, stay in VAL-II mode
            self.log_line(problem_text(error))

    # -- D_DEFINE: locations ----------------------------------------------------------------------
    def _define_from_file(self, typed: str) -> None:
        name = typed.strip().upper().removesuffix(".LOC")
        if not name:
            self.to_after()
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
            self._keys(f"{name}: {DEFINE_EACH}")

        def motion() -> Iterator[Event]:
            try:
                yield from self.simulator.move(location)
            except ValtermError as error:
                yield Error("", 0, f"THE ROBOT CANNOT REACH {name}: {error}")

        self.run_events(motion(), after=moved)

    def _define_answer(self, key: str) -> None:
        name, location = self._defining.pop(0)
        if key in ("A", "E"):
            self.session.define_location(name, location)
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
        self.to_after()

    def _define_point(self, typed: str) -> None:
        """POINT typed in by hand: NAME, X, Y, Z, O, A, T."""
        parts = [p for p in typed.replace(",", " ").split()]
        try:
            if len(parts) != 7:
                raise Refusal("TYPE: NAME, X, Y, Z, O, A, T (SIX NUMBERS)")
            name = check_location_name(parts[0])
            numbers = [_number(p) for p in parts[1:]]
        except ValtermError as error:
            self.log_line(f"*** {problem_text(error)}")
            self._open_line(Mode.POINT, "POINT", typed, "NAME, X, Y, Z, O, A, T")
            return
        x, y, z, o, a, t = numbers
        self.session.define_location(name, Location((x, y, z), (o, a, t)))
        self.log_line(f"POINT {name} DEFINED")
        self.to_after()


def _number(text: str) -> float:
    try:
        return float(text)
    except ValueError:  # float()'s refusal of a word
        raise Refusal(f"{text} IS NOT A NUMBER") from None
