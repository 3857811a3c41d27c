"""The VAL-II SIMULATOR app: the start screen, the menus and the model view (Chapters 2-4).

The app holds what the screens share: the session (workspace, cell, robot, interpreter),
the view options of KEYBOARD mode (FACES, AXES, ORIENT's view transform) and the one event
player (``valterm.ui.playback``). Motions are paced by elapsed time on an injectable clock;
no timer runs while nothing plays, so Pilot tests stay fast. Screens never import this
module: they reach the app's state through ``self.app``.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable
from pathlib import Path

import numpy as np
from textual.app import App
from textual.binding import Binding

from valterm.core.errors import ValtermError
from valterm.core.events import Event
from valterm.core.render.clock import DEFAULT_RATE
from valterm.core.render.raster import Scene, ViewTransform
from valterm.core.session import Session
from valterm.core.workspace import Workspace
from valterm.ui.errors import error_text
from valterm.ui.messages import SceneChanged
from valterm.ui.playback import Audience, Player
from valterm.ui.screens.main_menu import MainMenuScreen
from valterm.ui.screens.start import StartScreen
from valterm.ui.widgets.scene import simulator_scene


class ValtermApp(App[int]):
    """The whole simulator; ``setup`` skips the start screen (tests and ``--setup``)."""

    CSS_PATH = Path(__file__).with_name("app.tcss")  # absolute: subclasses (demo, tests) live elsewhere
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
        session: Session | None = None,  # a ready Session (tests)
    ) -> None:
        super().__init__()
        self.workspace_root = workspace
        self.initial_setup = setup
        self.session: Session | None = session
        self.ascii = ascii
        # KEYBOARD mode's view options, shared by every model view
        self.view_transform = ViewTransform()
        self.back_faces = False  # hidden surfaces removed until FACES (Table C-1)
        self.axes = False
        self.player = Player(self, clock=clock, rate=motion_rate)
        self._workspace: Workspace | None = None  # the workspace before any session (start screen)

    # -- starting ------------------------------------------------------------------
    def on_mount(self) -> None:
        if self.session is not None:
            self.fit_view()
            self.push_screen(MainMenuScreen())
            return
        if self.initial_setup:
            try:
                self.open_session(self.initial_setup)
            except ValtermError as error:
                self.push_screen(StartScreen(message=error_text(error)))
                return
            self.push_screen(MainMenuScreen())
            return
        self.push_screen(StartScreen())

    def on_unmount(self) -> None:
        self.player.close()  # a running program ends (and keeps its variables) before the exit

    def show_main_menu(self) -> None:
        """The start screen's way on: MAIN MENU in its place."""
        self.switch_screen(MainMenuScreen())

    def show_start(self) -> None:
        """B (BEGIN) at MAIN MENU: the start screen in its place."""
        self.switch_screen(StartScreen())

    def open_session(self, setup: str | None) -> Session:
        """A fresh session on ``setup`` (raises the core's errors for the caller to show)."""
        root = self.workspace_root if self.session is None else self.session.workspace.root
        session = Session(workspace_root=root, setup=setup)
        self.session = session
        self.view_transform = ViewTransform()
        self.fit_view()
        return session

    def fit_view(self) -> None:
        """The first view (and ORIENT's home): the whole cell and the robot's reach."""
        lo, hi = self.scene().bounds()
        reach = np.array([1000.0, 1000.0, 1050.0])
        self.view_transform.fit((np.minimum(lo, -reach * [1, 1, 0.6]), np.maximum(hi, reach)))

    def session_workspace(self) -> Workspace:
        """The workspace, also before a setup is read (the start screen's CAD files)."""
        if self.session is not None:
            return self.session.workspace
        if self._workspace is None:
            self._workspace = Workspace.open(self.workspace_root)
        return self._workspace

    @property
    def simulator(self):  # type: ignore[no-untyped-def]
        assert self.session is not None
        return self.session.simulator

    # -- the picture -----------------------------------------------------------------
    def scene(self, part_axes: int | None = None) -> Scene:
        if self.session is None:
            return Scene.build([])
        return simulator_scene(self.session.simulator, part_axes)

    def changed(self) -> None:
        """The cell or the robot changed outside a motion: tell the screen to redraw."""
        self.screen.post_message(SceneChanged())

    # -- playing events ----------------------------------------------------------------
    @property
    def moving(self) -> bool:
        return self.player.playing

    def run_events(self, events: Iterable[Event], audience: Audience | None = None) -> None:
        """Play what a simulator action or a command yields on the one player, to
        ``audience`` (default: the screen on top). CTRL-C reaches a running program."""
        target = audience if audience is not None else self.screen
        stop = self.session.abort_program if self.session is not None else None
        if self.session is not None:
            self.session.take_inputs_from_keyboard()  # the I/O panel (F6 in VAL-II mode) sets inputs
        self.player.play(events, target, stop)  # type: ignore[arg-type]

    def action_abort(self) -> None:
        """CTRL-C: abort the running program or motion (§6.4.10)."""
        self.player.abort()

    def skip_motion(self) -> None:
        """Show the end of what is playing now (tests; an impatient user)."""
        self.player.skip_to_end()


def run(workspace: str | Path | None = None, setup: str | None = None, ascii: bool = False) -> int:
    app = ValtermApp(workspace, setup, ascii=ascii)
    result = app.run()
    return int(result or 0)


