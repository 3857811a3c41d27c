"""MAIN MENU (Fig. 2-2, Fig. C-2): single keys to the modes, and B, I, S, H, G, R."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

from textual.binding import Binding

from valterm.core.errors import ValtermError
from valterm.ui import legends
from valterm.ui.errors import problem_text
from valterm.ui.screens.base import MenuScreen
from valterm.ui.widgets.menus import MAIN_MENU

# The modes' screens, HARDCOPY and GENERATE load when their key is pressed: the app shows
# MAIN MENU without them (issue 25, tests/test_start_imports.py).


class MainMenuScreen(MenuScreen):
    MENU = MAIN_MENU
    BINDINGS = [
        Binding("k,K", "keyboard", "Keyboard", id="main.keyboard"),
        Binding("m,M", "manipulation", "Manipulation", id="main.manipulation"),
        Binding("p,P", "pendant", "Pendant", id="main.pendant"),
        Binding("e,E", "editor", "Editor", id="main.editor"),
        Binding("v,V", "valmode", "VAL-II", id="main.valmode"),
        Binding("r,R", "toggle_model", "Model/menu", id="main.return"),
        Binding("b,B", "begin", "Begin", id="main.begin"),
        Binding("i,I", "initialize", "Initialize", id="main.initialize"),
        Binding("s,S", "stop", "Stop", id="main.stop"),
        Binding("h,H", "hardcopy", "Hardcopy", id="main.hardcopy"),
        Binding("g,G", "generate", "Generate", id="main.generate"),
    ]

    def on_screen_resume(self) -> None:
        # Textual runs MenuScreen's on_screen_resume after this one (every class's handler
        # along the MRO): calling it here too drew the picture twice (issue 25, the start)
        self._say_setup()  # first shown, or a save-as in MANIPULATION renamed the set-up

    def setup_read(self) -> None:
        super().setup_read()
        self._say_setup(new_turn=False)  # beside what the start said (a bad keymap file)

    def _say_setup(self, new_turn: bool = True) -> None:
        session = self.app.session_read  # none yet at the first frame: setup_read says it
        if session is not None and session.setup_name:
            if new_turn:
                self.messages.new_turn()
            state = " (NOT SAVED)" if self.app.setup_modified else ""
            self.say(f"SETUP FILE {session.setup_name}.SET WITH {len(session.simulator.cell.objects)} PARTS{state}")

    def escape_menu(self) -> None:
        stop = legends.key_for(self, "stop", "")
        leave = "" if getattr(self.app, "kiosk", False) or not stop else f"{stop} TO EXIT, "  # the museum's S is off
        self.say(f"THIS IS THE MAIN MENU: {leave}{legends.shown(self, legends.HELP, ' OR ')} FOR HELP")

    def _ask_first(self, what: str, then: Callable[[list[str]], None]) -> None:
        """B and I start a fresh session: ask first when taught locations, a moved set-up or
        edits would be lost (the CTRL-Q question), naming what goes back to its start too."""
        from valterm.ui.screens.quit import ask_first, fresh_simulator, resets, unsaved_work

        reset = resets(self.app.active_session.simulator, fresh_simulator(self.app))
        if self.app.keys_1985:
            # the thesis's keyboard: B and I act at once as in 1985, so Tables C-1..C-3 typed as
            # printed replay; what they drop is said (never silent), not asked
            lost = unsaved_work(self.app)
            then([*reset, *(f"{item.split(':')[0]} DISCARDED" for item in lost)])
            return
        # after MAIN MENU's resume (the question closed), which says the set-up afresh
        ask_first(self.app, what, lambda: self.call_later(then, reset), reset,
                  cancelled=lambda: self.call_later(self.say, f"{what} CANCELLED: NOTHING LOST, NOTHING RESET"))

    # -- to the modes ---------------------------------------------------------------
    def action_keyboard(self) -> None:
        from valterm.ui.screens.keyboard import KeyboardScreen

        self.app.push_screen(KeyboardScreen())

    def action_manipulation(self) -> None:
        from valterm.ui.screens.manipulation import ManipulationScreen

        self.app.push_screen(ManipulationScreen())

    def action_pendant(self) -> None:
        from valterm.ui.screens.pendant import PendantScreen

        self.app.push_screen(PendantScreen())

    def action_editor(self) -> None:
        from valterm.ui.screens.editor import EditorScreen

        self.app.push_screen(EditorScreen())

    def action_valmode(self) -> None:
        from valterm.ui.screens.valmode import ValModeScreen

        self.app.push_screen(ValModeScreen())


    def action_toggle_model(self) -> None:
        self.toggle_model()

    # -- the session ------------------------------------------------------------------
    def action_begin(self) -> None:
        self._ask_first("BEGIN", self._begin)

    def _begin(self, reset: list[str]) -> None:
        # said on the start screen: the next set-up read starts without them
        self.app.show_start("THE NEXT SET-UP STARTS AFRESH: " + ", ".join(reset) if reset else "")

    def action_initialize(self) -> None:
        self._ask_first("INITIALIZE", lambda said: self._initialize([s for s in said if s.endswith("DISCARDED")]))

    def _initialize(self, dropped: Sequence[str] = ()) -> None:
        from valterm.ui.screens.quit import resets

        before = self.app.active_session.simulator
        name = self.app.active_session.setup_name
        try:
            self.app.open_session(name or None)
        except Exception as error:
            self.say(problem_text(error), "error")
            return
        reset = [*resets(before, self.app.active_session.simulator), *dropped]  # what went back to its start
        self.messages.clear()
        said = f"INITIALIZED WITH {name}.SET" if name else "INITIALIZED"
        self.say(f"{said}: {', '.join(reset)}" if reset else said)
        self.redraw()

    def action_stop(self) -> None:
        def answer(key: str) -> None:
            if key == "Y":
                self.app.exit(0)
            else:
                self.say("SESSION CONTINUES")

        unsaved = " THE SET-UP IS NOT SAVED." if self.app.setup_modified else ""
        self.ask_key(f"{unsaved} ARE YOU SURE YOU WANT TO EXIT (Y/N) ?:".strip(), answer)

    def action_hardcopy(self) -> None:
        from valterm.ui.hardcopy import write_hardcopy

        try:
            svg, txt = write_hardcopy(self.app)
        except Exception as error:
            self.say(problem_text(error), "error")
            return
        self.say(f"HARDCOPY WRITTEN: {svg.name} AND {txt.name}")

    def action_generate(self) -> None:
        """G_GENERATE: the cell and the robot as NAME.OBJ and NAME.GLB, asking first when either
        is there (a U_GII mesh read into this setup may have that very name)."""
        session = self.app.active_session
        name = session.setup_name or "CELL"
        try:
            paths = [session.workspace.path(name, ext) for ext in ("OBJ", "GLB")]
        except ValtermError as error:
            self.say(problem_text(error), "error")
            return
        there = [path.name for path in paths if path.exists()]
        if not there:
            self._generate(paths)
            return
        self.ask_key(f"{' AND '.join(there)} {'EXISTS' if len(there) == 1 else 'EXIST'}: REPLACE (Y/N) ?",
                     lambda key: self._generate(paths) if key == "Y" else self._kept(), cancel=self._kept)

    def _kept(self) -> None:
        self.say("POLYGON FILES KEPT")

    def _generate(self, paths: list[Path]) -> None:
        from valterm.core.cad.export import export_scene

        session = self.app.active_session
        written = []
        try:
            for path in paths:
                export_scene(session.simulator.cell, session.simulator.robot_polyhedra(), path)
                written.append(path.name)
        except ImportError as error:
            self.say(f"EXPORT NOT AVAILABLE: {error}".upper(), "error")
            return
        except Exception as error:
            self.say(problem_text(error), "error")
            return
        self.say("POLYGON FILES WRITTEN: " + ", ".join(written))
