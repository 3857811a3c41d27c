"""The VAL-II SIMULATOR app: the start screen, the menus and the model view (Chapters 2-4).

The app holds what the screens share: the session (workspace, cell, robot, interpreter),
the view options of KEYBOARD mode (FACES, AXES, ORIENT's view transform) and the one motion
player. Motions are paced by elapsed time (``valterm.core.render.clock``); the pacing clock is
injectable and no timer runs while nothing moves, so Pilot tests stay fast.
"""

from __future__ import annotations

import sys
import time
from functools import lru_cache
from itertools import chain
from pathlib import Path
from typing import Any, Callable, Iterable, Iterator

from textual.app import App
from textual.binding import Binding

from valterm.core.crashlog import EXIT_BUG, crash_line, write_crash_log
from valterm.core.events import Error, Event, Message, PoseEvent
from valterm.ui.messages import MotionDone, PoseShown, SceneChanged, SimulatorEvent
from valterm.ui.view.animation import MotionDriver
from valterm.core.render.clock import DEFAULT_RATE
from valterm.core.render.raster import Scene, ViewTransform

@lru_cache(maxsize=1)
def core_errors() -> tuple[type[BaseException], ...]:
    from valterm.core.cad.errors import CadImportError
    from valterm.core.files.errors import FileFormatError
    from valterm.core.motion import MotionRefused
    from valterm.core.workspace import WorkspaceError

    # errors of the core shown as messages, never as tracebacks
    return (FileFormatError, WorkspaceError, MotionRefused, CadImportError, OSError, ValueError, IndexError, KeyError)


def error_text(error: BaseException) -> str:
    """The message of a core error, upper case as on the VS11."""
    from valterm.core.motion import MotionRefused

    text = str(error).strip() or type(error).__name__
    if isinstance(error, KeyError) and error.args:
        text = str(error.args[0])
    text = text.upper()
    return f"MOTION REFUSED: {text}" if isinstance(error, MotionRefused) else text


class ValtermApp(App[int]):
    """The whole simulator; ``setup`` skips the start screen (tests and ``--setup``)."""

    CSS_PATH = "app.tcss"
    TITLE = "VAL-II SIMULATOR"
    ENABLE_COMMAND_PALETTE = False
    AUTO_FOCUS = None  # menus take single keys: nothing is focused unless a question asks
    BINDINGS = [
        Binding("ctrl+c", "abort", "Abort", priority=True, show=False, id="app.abort"),
    ]

    def __init__(
        self,
        workspace: str | Path | None = None,
        setup: str | None = None,
        *,
        ascii: bool = False,
        clock: Callable[[], float] = time.monotonic,
        motion_rate: float = DEFAULT_RATE,
        session=None,  # type: ignore[no-untyped-def]  # a ready Session (tests)
    ) -> None:
        super().__init__()
        self.workspace_root = workspace
        self.initial_setup = setup
        self.session = session
        self.ascii = ascii
        self.motion_rate = motion_rate
        self.clock = clock
        # KEYBOARD mode's view options, shared by every model view
        self.view_transform = ViewTransform()
        self.back_faces = False  # hidden surfaces removed until FACES (Table C-1)
        self.axes = False
        self.motion: MotionDriver[PoseEvent] = MotionDriver(self, self._on_pose, self._on_motion_done, clock=clock)
        self._source: Iterator[Event] | None = None
        self._target = None  # the screen that started the motion
        self._workspace = None  # the workspace before any session (start screen)
        self.crash: BaseException | None = None  # the bug that ended the app, if one did
        self.crash_log: Path | None = None

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

    # -- starting ------------------------------------------------------------------
    def on_mount(self) -> None:
        from valterm.ui.screens.main_menu import MainMenuScreen
        from valterm.ui.screens.start import StartScreen

        if self.session is not None:
            self.fit_view()
            self.push_screen(MainMenuScreen())
            return
        if self.initial_setup:
            try:
                self.open_session(self.initial_setup)
            except core_errors() as error:
                self.push_screen(StartScreen(message=error_text(error)))
                return
            self.push_screen(MainMenuScreen())
            return
        self.push_screen(StartScreen())

    def open_session(self, setup: str | None):  # type: ignore[no-untyped-def]
        """A fresh session on ``setup`` (raises the core's errors for the caller to show)."""
        from valterm.core.session import Session

        root = self.workspace_root if self.session is None else self.session.workspace.root
        session = Session(workspace_root=root, setup=setup)
        self.session = session
        self.view_transform = ViewTransform()
        self.fit_view()
        return session

    def fit_view(self) -> None:
        """The first view (and ORIENT's home): the whole cell and the robot's reach."""
        import numpy as np

        lo, hi = self.scene().bounds()
        reach = np.array([1000.0, 1000.0, 1050.0])
        self.view_transform.fit((np.minimum(lo, -reach * [1, 1, 0.6]), np.maximum(hi, reach)))

    def session_workspace(self):  # type: ignore[no-untyped-def]
        """The workspace, also before a setup is read (the start screen's CAD files)."""
        if self.session is not None:
            return self.session.workspace
        if self._workspace is None:
            from valterm.core.workspace import Workspace

            self._workspace = Workspace.open(self.workspace_root)
        return self._workspace

    @property
    def simulator(self):  # type: ignore[no-untyped-def]
        return self.session.simulator

    # -- the picture -----------------------------------------------------------------
    def scene(self, part_axes: int | None = None) -> Scene:
        from valterm.ui.widgets.scene import simulator_scene

        if self.session is None:
            return Scene.build([])
        return simulator_scene(self.session.simulator, part_axes)

    def changed(self) -> None:
        """The cell or the robot changed outside a motion: tell the screen to redraw."""
        self.screen.post_message(SceneChanged())

    # -- motions ---------------------------------------------------------------------
    @property
    def moving(self) -> bool:
        return self.motion.playing

    def run_events(self, events: Iterable[Event]) -> bool:
        """Play what a simulator action yields: poses paced by the clock, the rest as messages.

        A refused motion (raised before the first pose) is shown, and False returned.
        """
        if self.motion.playing:
            self.motion.skip_to_end()  # one motion at a time, as on the controller
        source = iter(events)
        target = self.screen
        try:
            first = next(source)
        except StopIteration:
            target.post_message(MotionDone())
            return True
        except core_errors() as error:
            target.post_message(SimulatorEvent(Message(error_text(error), "warning")))
            target.post_message(MotionDone())
            return False
        self._source, self._target = source, target
        self.motion.play(self._poses(chain([first], source), target), self.motion_rate)
        return True

    def _poses(self, events: Iterator[Event], target) -> Iterator[PoseEvent]:  # type: ignore[no-untyped-def]
        """Only poses go to the player; the rest is shown as it is reached."""
        errors = core_errors()  # looked up now: the generator may be closed at shutdown
        try:
            for event in events:
                if isinstance(event, PoseEvent):
                    yield event
                else:
                    target.post_message(SimulatorEvent(event))
        except errors as error:
            target.post_message(SimulatorEvent(Error("", 0, error_text(error))))

    def _on_pose(self, pose: PoseEvent) -> None:
        if self._target is not None:
            self._target.post_message(PoseShown())

    def _on_motion_done(self, player) -> None:  # type: ignore[no-untyped-def]
        target, self._target = self._target, None
        self._source = None
        if target is not None:
            target.post_message(MotionDone(aborted=player.aborted))

    def action_abort(self) -> None:
        """CTRL-C: abort the running program or motion within a frame (§6.4.10)."""
        if self.session is not None and self.session._interpreter is not None:
            self.session.interpreter.abort()
        source = self._source
        if self.motion.playing:
            self.motion.abort()
        if source is not None and hasattr(source, "close"):
            source.close()  # the interpreter's generator ends where it stood

    def skip_motion(self) -> None:
        """Show the end of the running motion now (tests; an impatient user)."""
        self.motion.skip_to_end()


def run(workspace: str | Path | None = None, setup: str | None = None, ascii: bool = False) -> int:
    app = ValtermApp(workspace, setup, ascii=ascii)
    result = app.run()
    return exit_status(app, result)


def exit_status(app: ValtermApp, result: object) -> int:
    """The app's exit status: non-zero, with one line naming the log, when it crashed."""
    if app.crash is not None:  # its one line is already on stderr
        return EXIT_BUG
    if app.return_code:
        return app.return_code
    return int(result or 0)  # type: ignore[call-overload]


