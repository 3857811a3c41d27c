"""VAL-II mode (App. C §2, Fig. C-13): the command line, the optional VAL-II menu, the model.

It opens on the VAL-II MENU (two pages: N turns the page, V goes to the command line, R
returns). A typed line (label columns first, TAB to column 5) goes to the interpreter;
after each command the THEN PRESS keys of Fig. C-13 apply: C continue, W wipe, R return,
M model, D define locations (from a .LOC file, one at a time with the robot shown there:
A accept, R reject, E accept and end; or P to type a POINT by hand). Any other key starts
the next command line with that key, as the example session types ``LE`` then ``AB``.

A running program scrolls its steps; motions are paced by the view's MotionPlayer (no timer
runs when nothing moves); PAUSE hands the line to the user until PROCEED; CTRL-C aborts
after the step being simulated, and the program can be run again.
"""

from __future__ import annotations

import math
import time
from typing import Callable, Iterator

from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal, Vertical
from textual.events import Key
from textual.screen import Screen
from textual.timer import Timer
from textual.widgets import RichLog, Static

from valterm.core.events import (
    Collision,
    Delay,
    End,
    Error,
    Event,
    Help,
    Message,
    Monitor,
    Motion,
    Near,
    Pause,
    PoseEvent,
    Status,
    Step,
    TypeOut,
    Where,
)
from valterm.core.files.locations import check_location_name, format_locations
from valterm.core.kinematics import Location
from valterm.ui.screens.editor import StepInput
from valterm.core.render.clock import DEFAULT_RATE, MotionPlayer
from valterm.ui.view.model_view import ModelView
from valterm.ui.widgets.readouts import format_where
from valterm.ui.widgets.scene import simulator_scene

VAL_MENU_1 = """VAL-II MENU

ENTER COMMANDS BY TYPING IN:

READY        - VERTICAL CONFIGURATION
HERE P       - DEFINE CONFIGURATION P
MOVE P       - JOINT COORDINATE TO P
MOVES P      - STRAIGHT-LINE TO P
OPENI(X)     - OPEN CLAMP BY X%
CLOSEI(X)    - CLOSE CLAMP BY X%
SPEED S      - PERCENT OF FULL SPEED
WHERE        - DISPLAY POSITIONAL INFORMATION
APPRO P, D   - JOINT COORDINATE APPROACH
APPROS P, D  - STRAIGHT LINE APPROACH
STOP         - END VAL-II PROGRAM
HALT         - LIKE STOP (SEE CTRL_C)
DEPART D     - JOINT COORDINATE
DEPARTS D    - STRAIGHT LINE DEPART
DELAY N      - DELAY PROGRAM N SECONDS
PAUSE        - RETURN CONTROL TO USER
RIGHTY       - RIGHT HANDED ROBOT
LEFTY        - LEFT HANDED ROBOT
ABOVE        - ELBOW ABOVE WRIST
BELOW        - ELBOW BELOW WRIST
FLIP         - NEGATIVE JOINT 5 ANGLES
NOFLIP       - POSITIVE JOINT 5 ANGLES

N: NEXT PAGE   V: TO VAL-II MODE   R: RETURN"""

VAL_MENU_2 = """VAL-II MENU CONTINUED

ENTER COMMANDS BY TYPING IN:

;                - BEFORE COMMENTS
TYPE X=          - WRITES THE VALUE OF X
STATUS           - WRITES ROBOT STATUS (SPEED, PROG. LOOP NO.)
SET P1=P2        - EQUATE P1 TO P2
DRAW X, Y, Z     - STRAIGHT LINE INCREMENT
DRIVE J, A, S    - MOVE JT. J, A DEG. AT SP. S
BASE X, Y, Z, R  - SHIFT AND ROTATE ROBOT
SHIFT P, X, Y, Z - SHIFT POSITION P
EXECUTE NAME, N  - EXECUTE NAME, N TIMES
CTRL_C           - TO ABORT A VAL-II PROGRAM
GRASP X, NUM     - CLOSE CLAMP BY X%. ELSE GO TO STATEMENT NO. (NUM)
ALIGN            - ALIGNS THE TOOL Z-AXIS WITH NEAREST WORLD COORDS. Z-AXIS
VAR 1 = VAR 2    - SETS VAR. ON THE LEFT EQUAL TO ONE ON THE RIGHT OF EQUAL SIGN
HELP             - DISPLAYS HELP MENU

THEN PRESS:

C_CONTINUE : TO CONTINUE TYPING IN VAL COMMANDS
W_WIPE     : TO WIPE THE VT100 CHARACTERS FROM THE SCREEN
R_RETURN   : TO RETURN TO THE TOP OF A MENU
M_MODEL    : TO DISPLAY THE MODEL
D_DEFINE   : TO DEFINE ORIENTATIONS

N: FIRST PAGE   V: TO VAL-II MODE   R: RETURN"""

THEN_PRESS = "C_CONTINUE  W_WIPE  R_RETURN  M_MODEL  D_DEFINE"
DEFINE_HOW = "D_DATA FILE (.LOC)  P_POINT TYPED IN  R_RETURN"
DEFINE_EACH = "A_ACCEPT AND CONTINUE  R_REJECT  E_ACCEPT AND END"


class ValModeScreen(Screen[None]):
    """VAL-II mode."""

    AUTO_FOCUS = None
    DEFAULT_CSS = """
    ValModeScreen #val-left { width: 72; }
    ValModeScreen #val-left.model-only { display: none; }
    ValModeScreen #val-menu { height: 1fr; padding: 0 1; border: round $primary; }
    ValModeScreen #val-log { height: 1fr; border: round $secondary; padding: 0 1; }
    ValModeScreen .hidden { display: none; }
    ValModeScreen #val-keys { height: auto; padding: 0 1; color: $accent; }
    ValModeScreen #val-where { height: 4; padding: 0 1; }
    ValModeScreen #val-prompt-row { height: 3; }
    ValModeScreen #val-prompt { width: auto; min-width: 5; padding: 1 1 0 1; }
    ValModeScreen #val-line { width: 1fr; }
    ValModeScreen #val-model { width: 1fr; height: 1fr; }
    """
    BINDINGS = [
        Binding("ctrl+c", "abort", "Abort", priority=True, id="valmode.abort"),
        Binding("escape", "escape", "Back", id="valmode.escape"),
    ]

    def __init__(self, session=None, *, rate: float | None = None,  # type: ignore[no-untyped-def]
                 clock: Callable[[], float] | None = None, show_menu: bool = True) -> None:
        super().__init__()
        self._session = session
        # poses per second (math.inf: every motion at once, for tests); default: the app's
        self.rate: float = rate if rate is not None else DEFAULT_RATE
        self._rate_given = rate is not None
        self.clock: Callable[[], float] = clock or time.monotonic
        self._clock_given = clock is not None
        self.show_menu = show_menu
        self.mode = "menu"  # menu | command | after | running | paused | model | define? | define-file | define-each | point
        self.page = 1
        self._run: Iterator[Event] | None = None
        self._player: MotionPlayer[PoseEvent] | None = None
        self._motion_tail: list[Event] = []
        self._timer: Timer | None = None
        self._resume_at: float | None = None
        self._defining: list[tuple[str, Location]] = []
        self._defined: list[str] = []
        self._after_run: Callable[[], None] | None = None
        self.transcript: list[str] = []  # every line the log showed (tests, the demo)

    # -- layout ---------------------------------------------------------------------
    def compose(self) -> ComposeResult:
        with Horizontal():
            with Vertical(id="val-left"):
                yield Static(VAL_MENU_1, id="val-menu")
                yield RichLog(id="val-log", wrap=True, markup=False, max_lines=2000)
                yield Static("", id="val-keys")
                yield Static("", id="val-where")
                with Horizontal(id="val-prompt-row"):
                    yield Static(".", id="val-prompt")
                    yield StepInput(id="val-line", placeholder="VAL-II COMMAND")
            yield ModelView(id="val-model")

    @property
    def session(self):  # type: ignore[no-untyped-def]
        if self._session is None:
            self._session = self.app.session  # type: ignore[attr-defined]
        return self._session

    @property
    def simulator(self):  # type: ignore[no-untyped-def]
        return self.session.simulator

    @property
    def interpreter(self):  # type: ignore[no-untyped-def]
        return self.session.interpreter

    def on_mount(self) -> None:
        if not self._rate_given:
            self.rate = float(getattr(self.app, "motion_rate", DEFAULT_RATE))
        if not self._clock_given:
            self.clock = getattr(self.app, "clock", time.monotonic)
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
        for line in str(text).splitlines() or [""]:
            self.transcript.append(line)
            self.query_one("#val-log", RichLog).write(line)

    def redraw(self) -> None:
        self.query_one(ModelView).update_scene(simulator_scene(self.simulator))
        self.query_one("#val-where", Static).update("\n".join(format_where(self.simulator.where())))

    def _keys(self, text: str) -> None:
        self.query_one("#val-keys", Static).update(text)

    def _show_menu(self, page: int) -> None:
        self.mode, self.page = "menu", page
        menu = self.query_one("#val-menu", Static)
        menu.update(VAL_MENU_1 if page == 1 else VAL_MENU_2)
        menu.remove_class("hidden")
        self.query_one("#val-log").add_class("hidden")
        self._keys("")
        self._close_line()

    def _open_line(self, mode: str, prompt: str, start: str = "", placeholder: str = "VAL-II COMMAND") -> None:
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
        self._open_line("command", ".", start)

    def to_after(self) -> None:
        self.mode = "after"
        self._close_line()
        self._keys(THEN_PRESS)

    # -- keys ----------------------------------------------------------------------------
    def on_key(self, event: Key) -> None:
        char = (event.character or "").upper()
        mode = self.mode
        if mode in ("command", "paused", "define-file", "point", "running") or event.key in ("escape", "ctrl+c"):
            return  # the line takes the keys; while running only CTRL-C counts
        event.stop()
        event.prevent_default()
        if mode == "menu":
            if char == "N":
                self._show_menu(2 if self.page == 1 else 1)
            elif char == "V" or event.key == "enter":
                self.to_command()
            elif char == "R":
                self.dismiss(None)
        elif mode == "model":
            self.query_one("#val-left").remove_class("model-only")
            self.to_after()
        elif mode == "after":
            self._after_key(char, event)
        elif mode == "define?":
            if char == "D":
                self._open_line("define-file", "LOCATION FILE NAME:", "", "e.g. PROCESS.LOC")
            elif char == "P":
                self._open_line("point", "POINT", "", "NAME, X, Y, Z, O, A, T")
            elif char == "R":
                self.to_after()
        elif mode == "define-each":
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
            self.mode = "model"
            self.query_one("#val-left").add_class("model-only")
            self._keys("")
        elif char == "D":
            self.mode = "define?"
            self._keys(DEFINE_HOW)
        elif event.key == "enter":
            self.to_command()
        elif event.key == "tab":
            self.to_command("    ")
        elif event.character and event.character.isprintable():
            self.to_command(event.character)  # the next command starts with this key

    def action_escape(self) -> None:
        if self.mode in ("running",):
            return
        if self.mode in ("command", "after", "menu"):
            self.dismiss(None)
        elif self.mode in ("define?", "define-file", "point", "model"):
            self.to_after()

    def action_abort(self) -> None:
        """CTRL-C: the program stops after the step being simulated (§6.4.10)."""
        if self._run is not None:
            self.interpreter.abort()
            if self.mode == "paused":
                self._resume()

    # -- typed lines -----------------------------------------------------------------------
    def on_input_submitted(self, event) -> None:  # type: ignore[no-untyped-def]
        event.stop()
        text = event.value
        self.query_one("#val-line", StepInput).value = ""
        if self.mode == "define-file":
            self._define_from_file(text)
        elif self.mode == "point":
            self._define_point(text)
        elif self.mode == "paused":
            self.log_line(f". {text}")
            was_paused = self.interpreter.paused
            self._drain(self.interpreter.command(text))
            if was_paused and not self.interpreter.paused:
                self._resume()
        elif self.mode == "command":
            if not text.strip():
                return
            self.log_line(f". {text}")
            self.run_events(self.interpreter.command(text))

    # -- running events ----------------------------------------------------------------------
    def run_events(self, events: Iterator[Event], after: Callable[[], None] | None = None) -> None:
        """Play a stream of core events: steps scroll, motions move, PAUSE waits."""
        self._run = events
        self._after_run = after
        self.mode = "running"
        self._close_line()
        self._keys("RUNNING   CTRL-C: ABORT")
        self._pump()

    def _drain(self, events: Iterator[Event]) -> None:
        """A command typed while paused: shown at once (its motions jump to the end)."""
        for event in events:
            if isinstance(event, PoseEvent):
                continue
            self._show_event(event)
        self.redraw()

    def _pump(self) -> None:
        """Pull events until a motion must be paced, a DELAY waits, a PAUSE stops, or the end."""
        while self._run is not None:
            now = self.clock()
            if self._resume_at is not None:
                if now < self._resume_at:
                    self._schedule(self._resume_at - now)
                    return
                self._resume_at = None
            if self._player is not None:
                pose = self._player.poll(now)
                if pose is not None:
                    self.redraw()
                if not self._player.finished:
                    self._schedule(self._player.next_due_in(now) or 1.0 / max(1.0, min(self.rate, 60.0)))
                    return
                self._player = None
                for event in self._motion_tail:
                    self._show_event(event)
                self._motion_tail = []
                continue
            try:
                event = next(self._run)
            except StopIteration:
                self._finish_run()
                return
            if event is None:
                continue
            if isinstance(event, PoseEvent):
                if math.isinf(self.rate):
                    continue  # drawn once the motion ends
                self._player = MotionPlayer(self._motion(event), self.rate, clock=self.clock)
                continue
            if isinstance(event, Motion):
                self.redraw()
                continue
            if isinstance(event, Delay) and not math.isinf(self.rate):
                self.log_line(f"DELAY {event.seconds:g}")
                self._resume_at = self.clock() + float(event.seconds)
                continue
            if isinstance(event, Pause):
                self._show_event(event)
                self.redraw()
                self._stop_timer()
                self._keys("PROGRAM PAUSED: TYPE COMMANDS, PROCEED TO GO ON, CTRL-C TO ABORT")
                self._open_line("paused", "PAUSED .")
                return
            self._show_event(event)

    def _motion(self, first: PoseEvent) -> Iterator[PoseEvent]:
        """The poses of one motion, pulled from the run as the clock wants them; what comes
        between poses (collision messages) is shown as it comes; the end is kept for later."""
        yield first
        assert self._run is not None
        for event in self._run:
            if isinstance(event, PoseEvent):
                yield event
            elif isinstance(event, (Near, Collision, Message)):
                self._show_event(event)
            else:
                self._motion_tail.append(event)
                return

    def _schedule(self, delay: float) -> None:
        self._stop_timer()
        self._timer = self.set_timer(max(0.005, delay), self._pump, name="valmode-run")

    def _stop_timer(self) -> None:
        if self._timer is not None:
            self._timer.stop()
            self._timer = None

    def _resume(self) -> None:
        self.mode = "running"
        self._close_line()
        self._keys("RUNNING   CTRL-C: ABORT")
        self._pump()

    def _finish_run(self) -> None:
        self._stop_timer()
        self._run = None
        self._player = None
        self.redraw()
        after, self._after_run = self._after_run, None
        if after is not None:
            after()
        else:
            self.to_after()

    def _show_event(self, event: Event) -> None:
        if isinstance(event, Step):
            self.log_line(f"{event.step:>4}. {event.text}")
        elif isinstance(event, TypeOut):
            self.log_line(event.text)
        elif isinstance(event, (Message, Near, Collision)):
            self.log_line(event.text or f"{event.a} {event.event.upper()} {event.b}")  # type: ignore[union-attr]
        elif isinstance(event, Error):
            where = event.where
            self.log_line(f"*** {where}{event.message}")
        elif isinstance(event, Where):
            for line in format_where(event):
                self.log_line(line)
        elif isinstance(event, Status):
            self.log_line(f"SPEED {event.speed:g}%   PROGRAM {event.program or '-'}   "
                          f"LOOPS DONE {event.loops_done}   LEFT {event.loops_left}")
        elif isinstance(event, Pause):
            self.log_line(f"PAUSE {event.text}".rstrip())
        elif isinstance(event, Delay):
            self.log_line(f"DELAY {event.seconds:g}")
        elif isinstance(event, Help):
            from valterm.ui.screens.help import HelpScreen

            self.app.push_screen(HelpScreen(event.topic))
        elif isinstance(event, Monitor):
            self._monitor(event)
        elif isinstance(event, End):
            pass
        else:
            text = getattr(event, "text", "") or getattr(event, "message", "")
            if text:
                self.log_line(text)

    def _monitor(self, event: Monitor) -> None:
        workspace = self.session.workspace
        command, argument = event.command, event.argument.strip()
        try:
            if command == "LISTF":
                self.log_line("PROGRAMS: " + "  ".join(workspace.list_programs()))
            elif command == "LISTL":
                self.log_line("LOCATION FILES: " + "  ".join(workspace.list_locations()))
                if self.simulator.locations:
                    self.log_line(format_locations(dict(self.simulator.locations)).rstrip())
            elif command == "LISTP":
                program = workspace.read_program(argument)
                self.log_line(f"PROGRAM {program.name}")
                for number, step in enumerate(program.steps, start=1):
                    label = "" if step.label is None else str(step.label)
                    self.log_line(f"{number:>4}. {label:<4}{step.text}")
            elif command == "EDIT":
                from valterm.ui.screens.editor import EditorScreen

                self.app.push_screen(EditorScreen(workspace, argument))
            elif command == "POINT":
                self._after_run = lambda: self._open_line("point", "POINT", f"{argument}, " if argument else "",
                                                          "NAME, X, Y, Z, O, A, T")
        except Exception as error:  # a missing or damaged file: say so, stay in VAL-II mode
            self.log_line(f"*** {error}")

    # -- D_DEFINE: locations ----------------------------------------------------------------------
    def _define_from_file(self, typed: str) -> None:
        name = typed.strip().upper().removesuffix(".LOC")
        if not name:
            self.to_after()
            return
        try:
            points = self.session.workspace.read_locations(name)
        except Exception as error:
            self.log_line(f"*** {error}")
            self._open_line("define-file", "LOCATION FILE NAME:", "", "e.g. PROCESS.LOC")
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
            self.mode = "define-each"
            self._keys(f"{name}: {DEFINE_EACH}")

        def motion() -> Iterator[Event]:
            from valterm.core.motion import MotionRefused

            try:
                yield from self.simulator.move(location)
            except (MotionRefused, ValueError) as error:
                yield Error("", 0, f"THE ROBOT CANNOT REACH {name}: {error}")

        self.run_events(motion(), after=moved)

    def _define_answer(self, key: str) -> None:
        name, location = self._defining.pop(0)
        if key in ("A", "E"):
            self.simulator.locations[name] = location
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
                raise ValueError("TYPE: NAME, X, Y, Z, O, A, T (SIX NUMBERS)")
            name = check_location_name(parts[0])
            numbers = [float(p) for p in parts[1:]]
        except ValueError as error:
            self.log_line(f"*** {str(error).upper()}")
            self._open_line("point", "POINT", typed, "NAME, X, Y, Z, O, A, T")
            return
        self.simulator.locations[name] = Location(tuple(numbers[:3]), tuple(numbers[3:]))  # type: ignore[arg-type]
        self.log_line(f"POINT {name} DEFINED")
        self.to_after()
