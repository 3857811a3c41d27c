"""The VAL-II SIMULATOR app: the start screen, the menus and the model view (Chapters 2-4).

The app holds what the screens share: the session (workspace, cell, robot, interpreter),
the view options of KEYBOARD mode (FACES, AXES, ORIENT's view transform) and the one event
player (``valterm.ui.playback``). Motions are paced by elapsed time on an injectable clock;
no timer runs while nothing plays, so Pilot tests stay fast. Screens never import this
module: they read the app's state through one typed, read-only view (``ui.stage``), ask for
a run by message and hear what it does by message (``ui.messages``); none calls the player.
"""

from __future__ import annotations

import gc
import signal
import sys
import time
from collections.abc import Callable, Iterable
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any

from textual import events
from textual._styles_cache import StylesCache
from textual.app import App
from textual.binding import Keymap
from textual.message import Message
from textual.message_pump import MessagePump

from valterm.core.crashlog import EXIT_BUG, crash_line, write_crash_log
from valterm.core.errors import ValtermError
from valterm.core.events import Event
from valterm.core.render.clock import DEFAULT_RATE
from valterm.core.val.limits import RunLimits
from valterm.ui.bindings import APP_BINDINGS, cancel_keys, load_user_keymap
from valterm.ui.errors import bug_text, error_text
from valterm.ui.keyqueue import CANCEL, QUEUED, KeyQueue
from valterm.ui.messages import (
    Collided,
    PictureMoved,
    RunAbortRequested,
    RunEnded,
    RunEvent,
    RunPaused,
    RunRequested,
    RunResumed,
    SceneChanged,
    SceneShown,
    TranscriptLines,
)
from valterm.ui.playback import Player
from valterm.ui.screens.guard import Guarded
from valterm.ui.screens.main_menu import MainMenuScreen
from valterm.ui.terminal_writer import FrameGate
from valterm.ui.view.keys import ViewActions

if TYPE_CHECKING:
    from rich.console import RenderableType
    from textual.driver import Driver
    from textual.screen import Screen

    from valterm.core.files.record import SessionRecord
    from valterm.core.render.kept import KeptPicture
    from valterm.core.render.overlays import Trace
    from valterm.core.render.raster import Scene, ViewTransform
    from valterm.core.session import Session
    from valterm.core.simulator import Simulator
    from valterm.core.workspace import Workspace

RELEASE_EVERY = 10.0  # seconds between clearings of Textual's leaking style cache


def collect_from_now() -> None:
    """The cycle collector on again after the first frame, the start's objects kept out of it.

    Everything made while the collector was paused (some hundred thousand objects: Textual,
    the session, MAIN MENU's widgets) sits in its youngest generation; turned on as it is,
    its first pass walks them all (about 25 ms) while Textual's output thread waits to write
    the first frame (issue 25, the start). Frozen, they are never walked again: they live as
    long as the app, and the cycles among them that are already garbage (about 2 %) stay.
    """
    gc.freeze()
    gc.enable()


def release_styles_caches() -> None:
    """Textual 8.2's ``StylesCache.get_inner_outer`` is an ``lru_cache(1024)`` on an instance
    method, so it keeps up to 1024 removed widgets' render caches alive (Textualize/textual#6665):
    a kiosk's RSS grew by ~10 MB a demo round. Cleared now and then, it holds only what is shown."""
    clear = getattr(getattr(StylesCache, "get_inner_outer", None), "cache_clear", None)
    if clear is not None:
        clear()


class ValtermApp(Guarded, ViewActions, App[int]):
    """The whole simulator; ``setup`` skips the start screen (tests and ``--setup``)."""

    CSS_PATH = Path(__file__).with_name("app.tcss")  # absolute: subclasses (demo, tests) live elsewhere
    TITLE = "VAL-II SIMULATOR"
    ENABLE_COMMAND_PALETTE = False
    AUTO_FOCUS = None  # menus take single keys: nothing is focused unless a question asks
    BINDINGS = APP_BINDINGS  # CTRL-C and the view keys; every binding by id: ui/bindings.py

    def __init__(
        self,
        workspace: str | Path | None = None,
        setup: str | None = None,
        *,
        ascii: bool = False,
        clock: Callable[[], float] = time.monotonic,
        motion_rate: float = DEFAULT_RATE,
        session: Session | None = None,  # a ready Session (tests)
        rules: str | None = None,  # the joint-state rules (core/rules.py); None: the dialect's
        limits: RunLimits | None = None,  # every program's limits (valterm.core.val.limits)
        keys: str | None = None,  # "1985": the thesis's keys (None: $VALTERM_KEYS, else modern)
        robot: str | None = None,  # --robot (core/arms.py); None: the thesis's
    ) -> None:
        super().__init__()
        self.rules = rules
        self.robot = robot
        self.limits = limits
        self.workspace_root = workspace
        self.initial_setup = setup
        self._session: Session | None = session
        self._setup_to_open: str | None = None  # --setup's, read after the first frame (on_mount)
        self.ascii = ascii
        # KEYBOARD mode's view options, shared by every model view (view_transform and trace:
        # made when first asked, with the picture's modules)
        self.back_faces = False  # hidden surfaces removed until FACES (Table C-1)
        self.axes = False
        self.show_trace = True
        self.follow_clamp = False  # F4: the view follows the clamp
        self.player = Player(self, clock=clock, rate=motion_rate)
        self._runs_asked = 0  # RunRequested posted, not yet played (keys wait for them)
        self._run_ending: MessagePump | None = None  # the screen a RunEnded went to, until handled
        self.setup_modified = False  # the cell moved since the set-up file was read or saved
        self._workspace: Workspace | None = None  # the workspace before any session (start screen)
        self.crash: BaseException | None = None  # the bug that ended the app, if one did
        self.crash_log: Path | None = None
        # 1985: VAL-II mode and the editor go back to their menus after each command or
        # step, and keys typed while anything plays wait for it (the VS11's type-ahead)
        self.keys_1985 = keyboard_of(keys) == "1985"
        self.keymap_in_force: dict[str, str] = {}  # the keymap file's rebindings, by binding id
        # keys typed while a motion is drawn or a screen changes wait here
        self.cancel_keys = CANCEL  # ESC, or the keys the keymap file put the ESC bindings on
        # ESC aborts what runs, the open line takes a key now: as the screen on top says
        self.key_queue = KeyQueue(self, self._busy_playing, lambda: self.cancel_keys,
                                  lambda: self._screen_says("escape_aborts"),
                                  lambda event: self._screen_says("takes_typed_now", event))
        self.unsaid: list[tuple[str, str]] = []  # messages no screen could show yet (the next one does)
        self.survived: list[str] = []  # the bugs the app lived through (their lines, tests)
        self.collect_after_first_frame = False  # the collector waits for the first screen (run)
        self.recorder: SessionRecord | None = None  # --record: every key typed, every line shown
        # the last start's picture (core/render/kept.py), shown until --setup's set-up is read;
        # kept_path is where it is kept (run(): the user's cache; None: none kept, as in tests)
        self.kept_path: Path | None = None
        self.kept_picture: KeptPicture | None = None
        # the trace, pose and base the clamp's point was last traced at (scene())
        self._traced: tuple[object, ...] | None = None

    def _handle_exception(self, error: Exception) -> None:
        # A bug: its traceback goes to a log file and the terminal gets one line naming it
        # (see run), instead of Textual's screenful of traceback (Textual is pinned).
        if self.crash is None:
            self.crash, self.crash_log = error, write_crash_log(error)
        super()._handle_exception(error)
        self._exit_renderables.clear()

    def run(self, *args: Any, **kwargs: Any) -> int | None:
        result = super().run(*args, **kwargs)
        if self.crash is not None:  # the terminal is restored: now the one line
            print(crash_line(self.crash, self.crash_log), file=sys.stderr)
        return result

    # -- frames: dropped, not queued, for a terminal that does not read (ui.terminal_writer)
    def get_driver_class(self) -> type[Driver]:
        driver = super().get_driver_class()
        if driver.__name__ != "LinuxDriver":  # Windows, the web server's: as Textual has them
            return driver
        from valterm.ui.terminal_driver import gated

        return gated(driver)

    def _display(self, screen: Screen[Any], renderable: RenderableType | None) -> None:
        gate = getattr(self._driver, "gate", None)
        if not isinstance(gate, FrameGate) or renderable is None:
            super()._display(screen, renderable)
        elif gate.admit():
            mark = gate.handed
            super()._display(screen, renderable)
            gate.drawn(mark)

    # -- keys: none dropped (ui.keyqueue) --------------------------------------------
    def _busy_playing(self) -> bool:
        """Keys wait while a motion is drawn (1985: while anything plays, PAUSE aside), and
        while --setup's set-up is still to be read after the first frame."""
        if self.reading_setup or self._run_pending:
            return True  # a run asked for, or its end not yet seen by its screen: as if playing
        if self.keys_1985:
            return self.player.playing and not self.player.paused
        return self.player.drawing

    def _on_top(self, name: str) -> Callable[..., Any] | None:
        """The screen on top's method ``name``; None with no screen yet or no such method."""
        found = getattr(self.screen, name, None) if self.screen_stack else None
        return found if callable(found) else None

    def _screen_says(self, question: str, *args: object) -> bool:
        """The screen on top's answer to ``question`` (a method of its own); False where it has none."""
        ask = self._on_top(question)
        return bool(ask(*args)) if ask is not None else False

    @property
    def keys_waiting(self) -> int:
        """Keys typed while the app was busy, not yet handed on."""
        return len(self.key_queue)

    async def on_event(self, event: events.Event) -> None:
        if isinstance(event, events.Key) and not event.is_forwarded:
            if self.recorder is not None and not getattr(event, QUEUED, False):  # as typed, once
                self.recorder.key(event.key, event.character, self.moving or bool(self.keys_waiting))
            if self.key_queue.take(event):
                return  # handed on, in order, when the motion or the screen change is over
            await super().on_event(event)
            self.key_queue.handing_on(self.focused or self.screen)
            return
        if isinstance(event, events.Paste) and not event.is_forwarded and self.recorder is not None:
            self.recorder.paste(event.text, self.moving or bool(self.keys_waiting))
        await super().on_event(event)

    def on_descendant_focus(self, event: events.DescendantFocus) -> None:
        """Every line the app asks on has a steady cursor, served or not: Textual's blinks, a
        redraw twice a second, ~2 KB/s down every idle SSH session (issue 38 item 7)."""
        if hasattr(event.widget, "cursor_blink"):
            event.widget.cursor_blink = False

    # -- messages: to whatever screen is on top ---------------------------------------
    def say(self, text: str, level: str = "info") -> None:
        """A message for the user, on the screen on top (kept for the next screen while the
        one on top cannot show it: being mounted, or a help page without message lines)."""
        say_here = self._on_top("say_here")
        if say_here is not None and self.screen.is_mounted:
            say_here(text, level)
        else:
            self.unsaid = [*self.unsaid, (text, level)][-20:]

    def say_next(self, text: str, level: str = "info") -> None:
        """A message for the next screen that shows messages (the one a screen returns to)."""
        self.unsaid = [*self.unsaid, (text, level)][-20:]

    # -- what screens change of the app's state (they read it through ui.stage) ----------
    def show_back_faces(self, shown: bool) -> None:
        """FACES: back faces drawn (hidden surfaces not removed) in every model view."""
        self.back_faces = shown

    def show_axes(self, shown: bool) -> None:
        """AXES: coordinate frames drawn in every model view."""
        self.axes = shown

    def mark_setup_modified(self, modified: bool = True) -> None:
        """The cell moved since its set-up file was read or saved (or not, once saved)."""
        self.setup_modified = modified

    def take_unsaid(self) -> list[tuple[str, str]]:
        """What was said while no screen could show it, for the screen now shown to say."""
        unsaid, self.unsaid = self.unsaid, []
        return unsaid

    def survive(self, error: Exception) -> None:
        """A bug escaped a screen: logged with its traceback, said in one line, and the app
        goes on (the session, an unsaved set-up and the editor's journal are untouched)."""
        line = bug_text(error)
        self.survived.append(line)
        self.say(line, "error")

    def set_keymap(self, keymap: Keymap) -> None:
        """Textual's, and the record the legends read (ui/legends.py) and the key queue's
        cancel keys: whoever rebinds (the keymap file, a script), every legend follows."""
        self.keymap_in_force = dict(keymap)
        self.cancel_keys = cancel_keys(self.keymap_in_force)
        super().set_keymap(keymap)

    def on_mount(self) -> None:
        if self._session is None and self.initial_setup:
            # MAIN MENU first, its picture once the set-up is read: reading it loads numpy and
            # the core, which the menu does not need (issue 25, the start). A key typed
            # meanwhile waits (_busy_playing); anything that asks for the session sooner
            # reads it then (the session property).
            self._setup_to_open = self.initial_setup
        if self.collect_after_first_frame and not self.reading_setup:  # else once it is read
            self.call_after_refresh(collect_from_now)  # after the first screen's frame (see run)
        self.set_interval(RELEASE_EVERY, release_styles_caches, name="release-styles-caches")
        try:
            self.set_keymap(load_user_keymap())  # the user's rebindings, on every screen
        except ValtermError as error:  # a bad keymap file: said, the default keys kept
            self.say(f"KEYMAP: {error_text(error)}", "error")
        if self._session is not None:
            self.fit_view()
            self.push_screen(MainMenuScreen())
            return
        if self.reading_setup:
            self.kept_picture = self._kept_picture_found()
            self.push_screen(MainMenuScreen())
            self.call_after_refresh(self._open_setup_to_open)
            return
        self.push_screen(_start_screen())

    def on_unmount(self) -> None:
        self.player.close()  # a running program ends (and keeps its variables) before the exit

    def show_main_menu(self) -> None:
        """The start screen's way on: MAIN MENU in its place."""
        self.switch_screen(MainMenuScreen())

    def show_start(self, note: str = "") -> None:
        """B (BEGIN) at MAIN MENU: the start screen in its place (``note``: what it says first)."""
        self.switch_screen(_start_screen(note=note))

    @property
    def session(self) -> Session | None:
        """The open session; the set-up ``--setup`` named is read now if it has not been yet."""
        if self._setup_to_open is not None:
            self._open_setup_to_open()
        return self._session

    @session.setter
    def session(self, session: Session | None) -> None:
        self._setup_to_open = None
        self._session = session

    @property
    def session_read(self) -> Session | None:
        """The session if one is open, without reading a set-up still to be read (what the
        first frame shows: MAIN MENU before its picture)."""
        return self._session

    @property
    def reading_setup(self) -> bool:
        """--setup's set-up is still to be read (keys wait for it)."""
        return self._setup_to_open is not None

    def _open_setup_to_open(self) -> None:
        """Read --setup's set-up (after MAIN MENU's first frame, or when first asked for): the
        screen on top then draws the picture; a set-up that cannot be read shows the start
        screen with the reason, as a bad --setup always has."""
        setup, self._setup_to_open = self._setup_to_open, None
        if setup is None:
            return
        if self.collect_after_first_frame:  # once the session is made too (see run)
            self.call_after_refresh(collect_from_now)
        try:
            self.open_session(setup)
        except ValtermError as error:
            self.kept_picture = None  # no picture of this set-up: the start screen says why
            self.call_later(self.switch_screen, _start_screen(message=error_text(error)))
            return
        self.call_later(self._setup_read)

    def _setup_read(self) -> None:
        shown = self._on_top("setup_read")
        if shown is not None and self.screen.is_mounted:
            shown()
        if self.kept_path is not None:  # once this picture is on the screen
            self.call_after_refresh(self._keep_picture, self.kept_picture)
        self.kept_picture = None  # drawn now: no later view shows the kept one

    # -- the picture of the last start (core/render/kept.py) ---------------------------
    def _kept_options(self) -> dict[str, object]:
        """What, beside the set-up file and the code, the start's picture is drawn from."""
        return {"robot": self.robot, "rules": self.rules, "ascii": self.ascii, "keys_1985": self.keys_1985,
                "back_faces": self.back_faces, "axes": self.axes, "follow": self.follow_clamp}

    def _kept_picture_found(self) -> KeptPicture | None:
        """The last start's picture when it was drawn from what --setup's is drawn from now
        (read before the first frame: no numpy, no session)."""
        if self.kept_path is None or self.initial_setup is None:
            return None
        from valterm.core.render import kept
        from valterm.core.workspace import first_setup_bytes

        setup = first_setup_bytes(self.workspace_root, self.initial_setup)
        if setup is None:  # refused or missing: the session's reading says why
            return None
        return kept.read_kept(self.kept_path, kept.start_key(setup, **self._kept_options()))

    def _keep_picture(self, shown: KeptPicture | None) -> None:
        """Keep the picture the set-up's reading drew for the next start (unless it is the
        one kept already)."""
        from valterm.core.render import kept
        from valterm.ui.widgets.cell_view import CellView

        session = self._session
        view = self.screen.query_one_optional("#model", CellView) if self.screen_stack else None
        if self.kept_path is None or session is None or view is None or not session.setup_name:
            return
        from valterm.core.workspace import first_setup_bytes

        setup = first_setup_bytes(session.workspace.root, session.setup_name)
        if setup is None:
            return
        picture = view.painted(kept.start_key(setup, **self._kept_options()))
        if picture is not None and picture != shown:
            kept.write_kept(self.kept_path, picture)

    def open_session(self, setup: str | None) -> Session:
        """A fresh session on ``setup`` (raises the core's errors for the caller to show)."""
        from valterm.core.render.raster import ViewTransform
        from valterm.core.session import Session

        root = self.workspace_root if self._session is None else self._session.workspace.root
        session = Session(workspace_root=root, setup=setup, limits=self.limits, robot=self.robot)
        if self.rules is not None:
            session.simulator.set_rules(self.rules)
        self.session = session
        self.setup_modified = False
        self.view_transform = ViewTransform()
        self.trace.clear()
        self.player.goal = None
        self.fit_view()
        return session

    @cached_property
    def view_transform(self) -> ViewTransform:
        """ORIENT's view, shared by every model view (a new one with each session)."""
        from valterm.core.render.raster import ViewTransform

        return ViewTransform()

    @cached_property
    def trace(self) -> Trace:
        """The clamp's path over the last motions (F5 shows or hides it)."""
        from valterm.core.render.overlays import Trace

        return Trace()

    def fit_view(self) -> None:
        """The first view: the oblique three-quarter view of the whole cell (ORIENT's H
        turns it to the thesis's side view of the same box)."""
        from valterm.core.render import views
        from valterm.core.render.overlays import cell_points

        view = views.orient(self.view_transform, *views.preset_angles(views.DEFAULT_VIEW))
        if self.session is not None:
            views.fit_points(view, cell_points(self.session.simulator))

    def session_workspace(self) -> Workspace:
        """The workspace, also before a setup is read (the start screen's CAD files)."""
        if self.session is not None:
            return self.session.workspace
        if self._workspace is None:
            from valterm.core.workspace import Workspace

            self._workspace = Workspace.open(self.workspace_root)
        return self._workspace

    @property
    def active_session(self) -> Session:
        """The open session: screens that show a cell are opened only once there is one."""
        assert self.session is not None, "a cell screen without a session"
        return self.session

    @property
    def simulator(self) -> Simulator:
        return self.active_session.simulator

    # -- the picture -----------------------------------------------------------------
    def scene(self, part_axes: int | None = None) -> Scene | None:
        """The picture: cell, robot, LED line and the overlays (trace, ghost, collisions, axes);
        None (a blank view) while no set-up has been read."""
        if self._session is None:
            return None
        from valterm.core.render.overlays import Overlays, clamp_point, picture_scene

        sim = self._session.simulator
        for joints in self.player.passed_poses():  # every pose the motion went through
            self.trace.add(clamp_point(sim, joints))
        stands = (self.trace, tuple(sim.joints), sim.base.tobytes())
        if stands != self._traced or not len(self.trace):  # not at each in-between picture
            self._traced = stands
            self.trace.add(clamp_point(sim))
        if self.follow_clamp:
            self.frame_clamp()
        overlays = Overlays(
            trace=self.trace if self.show_trace else None,
            goal=self.player.goal,
            collided=frozenset(self.player.collided),
            axes=True,
            depth=self.view_transform,
            part_axes=part_axes,
            drawn=self.player.drawn(sim.joints),  # an in-between pose while a motion plays
            static_cell=True,  # the standing parts drawn once while they stand (issue 40)
        )
        return picture_scene(sim, overlays)

    def changed(self) -> None:
        """The cell or the robot changed outside a motion: tell the screen to redraw."""
        self.screen.post_message(SceneChanged())

    # -- playing events: asked for by message, played on the one player, told by message --
    @property
    def moving(self) -> bool:
        """A run is asked for, playing, or its end not yet handled by its screen."""
        return self.player.playing or self._run_pending

    @property
    def _run_pending(self) -> bool:
        """A run asked for and not yet played, or ended and its end not yet handled by its
        screen (one that went meanwhile never will: not waited for)."""
        ending = self._run_ending
        if ending is not None and not ending.is_attached:
            self._run_ending = ending = None
        return self._runs_asked > 0 or ending is not None

    def post_message(self, message: Message) -> bool:
        posted = super().post_message(message)
        if posted and isinstance(message, RunRequested):
            self._runs_asked += 1  # busy from now: the key typed next waits for the run
        return posted

    def on_run_requested(self, message: RunRequested) -> None:
        self._runs_asked = max(0, self._runs_asked - 1)
        self.run_events(message.events, message.origin)

    def on_run_resumed(self, message: RunResumed) -> None:
        self.player.resume()

    def on_run_abort_requested(self, message: RunAbortRequested) -> None:
        self.player.abort()

    def on_collided(self, message: Collided) -> None:
        """Bodies that still collide where a motion left the robot: marked, the picture again."""
        if not message.parties <= self.player.collided:
            self.player.collided.update(message.parties)
            self.changed()

    def run_events(self, events: Iterable[Event], origin: object = None) -> None:
        """Play what a simulator action or a command yields on the one player; what it does
        is posted to ``origin`` (default: the screen on top) while it is up, then to the
        screen on top (``_to_screen``). CTRL-C reaches a running program."""
        origin = origin if origin is not None else self.screen
        stop = self.session.abort_program if self.session is not None else None
        if self.session is not None:
            self.session.take_inputs_from_keyboard()  # the I/O panel (F10 in VAL-II mode) sets inputs
            self.player.rest_at(self.session.simulator.joints)  # where the first picture starts
        self.player.play(events, lambda message: self._to_screen(origin, message), stop)

    def _to_screen(self, origin: object, message: Message) -> None:
        """The player's message to the screen that asked while it is up (covered too: a
        program goes on under the I/O panel); once it is gone, to the screen on top, as that
        screen's news: its last lines said, a pause gone on (no one can type PROCEED where it
        paused), the end a redraw (nothing asks a screen that is gone for a widget)."""
        if isinstance(origin, MessagePump) and origin.is_attached:
            origin.post_message(message)
            if isinstance(message, RunEnded):  # keys wait until the screen has handled it
                self._run_ending = origin if origin.call_later(self._run_end_seen) else None
            return
        if isinstance(message, RunPaused):
            self.player.resume()
        elif isinstance(message, (TranscriptLines, RunEvent)):
            for line in message.lines[-3:]:
                self.say(line, "error" if line.startswith("***") else "info")
        elif self.screen_stack and self.screen.is_mounted:
            self.screen.post_message(message if isinstance(message, (SceneShown, PictureMoved)) else SceneShown())

    def _run_end_seen(self) -> None:
        self._run_ending = None

    def action_abort(self) -> None:
        """CTRL-C: abort the running program or motion (§6.4.10)."""
        self.player.abort()

    async def action_quit(self) -> None:
        """CTRL-Q: leave at once, or ask first when there is unsaved work (keymap rule 5)."""
        from valterm.ui.screens.quit import confirm_quit

        confirm_quit(self)

    def skip_motion(self) -> None:
        """Show the end of what is playing now (tests; an impatient user)."""
        self.player.skip_to_end()


def _start_screen(message: str = "", note: str = "") -> Any:
    """The start screen, its module loaded when it is first shown (``--setup`` goes straight
    to MAIN MENU without it: issue 25); ``message`` an error, ``note`` information."""
    from valterm.ui.screens.start import StartScreen

    return StartScreen(message=message, note=note)


KEYBOARDS = ("modern", "1985")
KEYS_ENV = "VALTERM_KEYS"


def keyboard_of(keys: str | None) -> str:
    """The keyboard asked for: ``keys``, else $VALTERM_KEYS, else modern (an unknown name
    is modern: the app must start)."""
    import os

    chosen = (keys or os.environ.get(KEYS_ENV) or "modern").strip().lower()
    return chosen if chosen in KEYBOARDS else "modern"


def run(workspace: str | Path | None = None, setup: str | None = None, ascii: bool = False,
        rules: str | None = None, limits: RunLimits | None = None, keys: str | None = None,
        robot: str | None = None, collect_after_first_frame: bool = False,
        recorder: SessionRecord | None = None) -> int:
    """The app until it ends; ``collect_after_first_frame``: the command line paused Python's
    cycle collector for the start (valterm.cli), and the app turns it on once its first
    screen is drawn; ``recorder``: --record's, closed with the exit status."""
    from valterm.core.render.kept import cache_path

    app = ValtermApp(workspace, setup, ascii=ascii, rules=rules, limits=limits, keys=keys, robot=robot)
    app.collect_after_first_frame = collect_after_first_frame
    app.kept_path = cache_path()
    app.recorder = recorder
    end_on_hangup()
    result = app.run()
    status = exit_status(app, result)
    if recorder is not None:
        recorder.close(status)
        if recorder.failure:
            print(f"valterm: {recorder.failure}", file=sys.stderr)
    return status


def end_on_hangup() -> None:
    """A terminal that hangs up (an SSH client gone) ends the simulator, even when whatever
    started it ignored SIGHUP (nohup, some supervisors and CI runners: the ignoring is inherited
    through exec). Then Textual's input thread reads end-of-file for ever, a core busy, and an
    abandoned simulator never ends (issue 37: the SSH cleanup test under such a parent)."""
    if hasattr(signal, "SIGHUP"):
        signal.signal(signal.SIGHUP, signal.SIG_DFL)


def exit_status(app: ValtermApp, result: object) -> int:
    """The app's exit status: non-zero, with one line naming the log, when it crashed."""
    if app.crash is not None:  # its one line is already on stderr
        return EXIT_BUG
    if app.return_code:
        return app.return_code
    return int(result) if isinstance(result, int) else 0


