"""MANIPULATION MENU (Fig. 4-1, Fig. C-5, §4.1, §4.2, §7.2): reposition the cell's parts.

The part number first, then I_NCREMENTS (typed translations and rotations about the screen
axes), K_EYBOARD (5 mm a key along the screen axes) or R_ETURN. The Fig. 4-2 readout shows
the part's reference corner in world and screen coordinates after every change. S_TOP ends:
another part, or save the setup under the same or a new name. Saved under its own name
when another session saved it meanwhile, the one question asks (valterm.ui.screens.changed):
overwrite, reload or save as.

Screen axes (SPEC §1): X_s = Y_w, Y_s = Z_w + 26, Z_s = X_w; so U/D move along Z_w, R/L
along Y_w and F/B along X_w.
"""

from __future__ import annotations

from pathlib import Path

from textual.app import ComposeResult
from textual.binding import Binding

from valterm.core.errors import ValtermError
from valterm.core.files.errors import FileChanged
from valterm.ui import legends
from valterm.ui.errors import Refusal, problem_text
from valterm.ui.screens.base import MenuScreen
from valterm.ui.widgets.menus import MANIPULATION_CHOICE, MANIPULATION_MENU
from valterm.ui.widgets.readouts import PartReadout

STEP_MM = 5.0  # §4.1: "The default increments are set to <5 mm> for each key depression"
STEP_DEG = 5.0
# key -> world translation of one step
KEY_MOVES = {
    "U": (0.0, 0.0, STEP_MM), "D": (0.0, 0.0, -STEP_MM),
    "R": (0.0, STEP_MM, 0.0), "L": (0.0, -STEP_MM, 0.0),
    "F": (STEP_MM, 0.0, 0.0), "B": (-STEP_MM, 0.0, 0.0),
}
SCREEN_AXIS_TO_WORLD = {"X": 1, "Y": 2, "Z": 0}  # the world axis along each screen axis


def screen_to_world_offset(dx: float, dy: float, dz: float) -> tuple[float, float, float]:
    """A screen-axes displacement in world axes."""
    return dz, dx, dy


def parse_triple(text: str) -> tuple[float, float, float]:
    parts = [p for p in text.replace(",", " ").split()]
    if len(parts) != 3:
        raise Refusal(f"{text or 'nothing'}: type three numbers X, Y, Z")
    try:
        x, y, z = (float(p) for p in parts)
    except ValueError:  # float()'s own refusal of a word
        raise Refusal(f"{text}: type three numbers X, Y, Z") from None
    return x, y, z


class ManipulationScreen(MenuScreen):
    MENU = MANIPULATION_CHOICE
    MENU_KEYS_BOUND = False  # I, K, R answer a question (not rebound); K_EYBOARD's menu is bound
    BINDINGS = [
        Binding("u,U", "step('U')", "Upward", id="manipulation.up"),
        Binding("d,D", "step('D')", "Downward", id="manipulation.down"),
        Binding("r,R", "step('R')", "Right", id="manipulation.right"),
        Binding("l,L", "step('L')", "Left", id="manipulation.left"),
        Binding("f,F", "step('F')", "Forward", id="manipulation.forward"),
        Binding("b,B", "step('B')", "Backward", id="manipulation.backward"),
        Binding("x,X", "turn('X')", "X rot", id="manipulation.xrot"),
        Binding("y,Y", "turn('Y')", "Y rot", id="manipulation.yrot"),
        Binding("z,Z", "turn('Z')", "Z rot", id="manipulation.zrot"),
        Binding("a,A", "axes", "Axes", id="manipulation.axes"),
        Binding("s,S", "stop", "Stop", id="manipulation.stop"),
        Binding("m,M", "model", "Model", id="manipulation.model"),
    ]

    def __init__(self) -> None:
        super().__init__()
        self.part = 0
        self.keyboard = False  # the K_EYBOARD menu is active
        self.mode = ""  # I or K once chosen: another part goes on the same way (§7.2)
        self.modified = False

    def compose_readout(self) -> ComposeResult:
        yield PartReadout(id="readout")

    def on_mount(self) -> None:
        super().on_mount()
        self.ask_part()

    def update_readout(self) -> None:
        if self.part:
            reference = self.stage.simulator.cell.object(self.part).reference
            self.query_one("#readout", PartReadout).show_part(self.part, [float(v) for v in reference])

    # -- which part, which way ------------------------------------------------------
    def ask_part(self) -> None:
        self.keyboard = False
        self.menu.set_text(MANIPULATION_CHOICE)
        count = len(self.stage.simulator.cell.objects)
        if count == 0:
            self.say("THERE ARE NO PARTS IN THIS CELL", "warning")
            self.ask_key("PRESS R TO RETURN:", lambda _k: self.leave(), "R")
            return
        self.ask_line(f"ENTER PART NUMBER TO BE MOVED (1-{count}):", self._part, cancel=self._end)

    def _ask_choice(self) -> None:
        """The menu of a chosen part (§7.2): I, K or R."""
        self.keyboard = False
        self.menu.set_text(MANIPULATION_CHOICE)
        self.ask_key("ENTER COMMAND# (I, K OR R):", self._choice, "IKR", cancel=self._end)

    def prompt_cancelled(self) -> None:
        """ESC at any question of I_NCREMENTS: back to this part's I, K, R menu."""
        if self.part:
            self._ask_choice()
        else:
            self.ask_part()

    def escape_menu(self) -> None:
        """ESC in the K_EYBOARD menu is S_TOP; anywhere else the part's menu is asked again."""
        if self.keyboard:
            self.action_stop()
        else:
            self.prompt_cancelled()

    def _part(self, answer: str) -> None:
        count = len(self.stage.simulator.cell.objects)
        if not answer.isdigit() or not 1 <= int(answer) <= count:
            self.say(f"{answer or 'NOTHING'} IS NOT A PART NUMBER (1-{count})", "error")
            self.ask_part()
            return
        self.part = int(answer)
        self.part_axes = self.part if self.stage.axes else None
        self.redraw()
        if self.mode == "I":
            self._ask_translate()
        elif self.mode == "K":
            self._choice("K")
        else:
            self._ask_choice()

    def _choice(self, key: str) -> None:
        self.mode = key if key in "IK" else ""
        if key == "K":
            self.keyboard = True
            self.menu.set_text(self.live_menu(MANIPULATION_MENU))
        elif key == "I":
            self.ask_key("COORDINATE AXES DISPLAY ON (Y/N) ?:", self._increments_axes)
        else:
            self._end()

    # -- K_EYBOARD ------------------------------------------------------------------------
    def _move(self, translation: tuple[float, float, float] = (0.0, 0.0, 0.0), axis: int | None = None,
              degrees: float = 0.0) -> None:
        try:
            self.stage.simulator.move_part(self.part, translation, axis, degrees)
        except Exception as error:
            self.say(problem_text(error), "error")
            return
        self.modified = True
        self.app.mark_setup_modified()
        self.show_model_if_narrow()
        self.redraw()

    def action_step(self, key: str) -> None:
        if self.keyboard:
            self._move(KEY_MOVES[key])

    def action_turn(self, axis: str) -> None:
        if self.keyboard:
            self._move(axis=SCREEN_AXIS_TO_WORLD[axis], degrees=STEP_DEG)

    def action_axes(self) -> None:
        if not self.keyboard:
            return
        self._set_axes(not self.stage.axes)

    def _set_axes(self, on: bool) -> None:
        self.app.show_axes(on)
        self.model_view.axes = on
        self.part_axes = self.part if on else None
        self.say(f"COORDINATE AXES {'ON' if on else 'OFF'}")
        self.redraw()

    def action_model(self) -> None:
        self.toggle_model()

    def action_stop(self) -> None:
        if self.keyboard:
            self.keyboard = False
            self._another()

    # -- I_NCREMENTS (§4.2, §7.2) ----------------------------------------------------------
    def _increments_axes(self, key: str) -> None:
        self._set_axes(key == "Y")
        self._ask_translate()

    def _ask_translate(self) -> None:
        self.ask_key("DO YOU WANT TO TRANSLATE THE PART (Y/N) ?:",
                     lambda k: self._ask_triple_translate() if k == "Y" else self._ask_rotate())

    def _ask_triple_translate(self) -> None:
        self.ask_line("ENTER TRANSLATIONAL INCREMENTS X, Y, Z (MM):", self._translate)

    def _translate(self, text: str) -> None:
        try:
            dx, dy, dz = parse_triple(text)
        except Refusal as error:
            self.say(problem_text(error), "error")
            self._ask_triple_translate()
            return
        self._move(screen_to_world_offset(dx, dy, dz))
        self._ask_rotate()

    def _ask_rotate(self) -> None:
        # Table C-1: answering N here is done with this part ("N  no rotation", then
        # "N  end moving parts"); after a rotation the "continue moving" question comes
        self.ask_key("DO YOU WANT TO ROTATE THE PART (Y/N) ?:",
                     lambda k: self._ask_triple_rotate() if k == "Y" else self._another())

    def _ask_triple_rotate(self) -> None:
        self.ask_line("ENTER ROTATIONAL INCREMENTS ABOUT X, Y, Z (DEG):", self._rotate)

    def _rotate(self, text: str) -> None:
        try:
            angles = parse_triple(text)
        except Refusal as error:
            self.say(problem_text(error), "error")
            self._ask_triple_rotate()
            return
        for axis, degrees in zip("XYZ", angles):
            if degrees:
                self._move(axis=SCREEN_AXIS_TO_WORLD[axis], degrees=degrees)
        self._ask_continue()

    def _ask_continue(self) -> None:
        self.ask_key(f"DO YOU WANT TO CONTINUE MOVING PART {self.part} (Y/N) ?:",
                     lambda k: self._ask_translate() if k == "Y" else self._another())

    # -- the end of a session ---------------------------------------------------------------
    def _another(self) -> None:
        self.ask_key("DO YOU WANT TO MOVE ANOTHER PART (Y/N) ?:",
                     lambda k: self.ask_part() if k == "Y" else self._end())

    def _end(self) -> None:
        if not self.modified:
            self._back()
            return
        # ESC cancels the question, not the work: back to this screen's menu, where R or ESC
        # asks again (MAIN has no save key; N leaves with the layout NOT SAVED in the session)
        self.ask_key("DO YOU WANT TO SAVE THE NEW SET-UP FILE (Y/N) ?:",
                     lambda k: self._ask_name() if k == "Y" else self._back(), cancel=self._not_saved)

    def _not_saved(self) -> None:
        again = "THE NEW SET-UP IS NOT SAVED: {menu.cancel} ASKS AGAIN (Y SAVES IT, N LEAVES IT UNSAVED)"
        self.say(legends.fill(self, again), "warning")
        self.prompt_cancelled()

    def _ask_name(self) -> None:
        name = self.stage.active_session.setup_name
        self.ask_line(f"ENTER SET-UP FILE NAME (RETURN: SAME NAME {name}):", self._save, cancel=self._end)

    def _save(self, name: str, overwrite: bool = False) -> None:
        typed, name = name, self._name_1985(name)
        try:
            path = self.stage.active_session.save_setup(name or None, overwrite=overwrite)
        except FileChanged:
            self._ask_changed()
            return
        except Exception as error:
            self.say(problem_text(error), "error")
            self._ask_name()
            return
        if name != typed:  # said by the screen the save returns to, after its own first words
            self.app.say_next(f"SET-UP SAVED AS {path.name} ({typed.strip().upper()} TAKEN AS "
                              f"{path.stem}: A SET-UP FILE ENDS IN .SET)")
        self._saved(path)

    def _name_1985(self, typed: str) -> str:
        """--keys 1985: a name with another file's ending is taken as the 1985 program took it,
        by its stem (Table C-1's `Y, "TEST.DAT" RETURN` saves the set-up TEST, TEST.SET)."""
        stem, dot, ending = typed.strip().rpartition(".")
        if getattr(self.app, "keys_1985", False) and dot and stem and ending.upper() != "SET":
            return stem
        return typed

    def _ask_changed(self) -> None:
        """NAME.SET changed on disk since it was read: overwrite, reload or save as."""
        from valterm.ui.screens.changed import FileChangedScreen

        session = self.stage.active_session
        self.say(f"{session.setup_name}.SET CHANGED ON DISK: NOT SAVED", "warning")

        def answered(answer: tuple[str, str] | None) -> None:
            if answer is None:
                self.say(f"{session.setup_name}.SET NOT SAVED: THE MOVED PARTS STAY (NOT SAVED)", "warning")
                self._back()
            elif answer[0] == "overwrite":
                self._save("", overwrite=True)
            elif answer[0] == "reload":
                self._reload()
            elif self._taken(answer[1]):
                self._ask_changed()
            else:
                self._save(answer[1])

        self.app.push_screen(FileChangedScreen(f"{session.setup_name}.SET", "set-up file"), answered)

    def _taken(self, name: str) -> bool:
        """Save as: a bad name or one a setup file has is refused (said) and asked again."""
        try:
            taken = bool(self.stage.active_session.workspace.exists(name, "SET"))
        except ValtermError as error:
            self.say(problem_text(error), "error")
            return True
        if taken:
            self.say(f"{name.upper().removesuffix('.SET')}.SET EXISTS: GIVE A NEW NAME", "error")
        return taken

    def _reload(self) -> None:
        try:
            self.stage.active_session.load_setup(self.stage.active_session.setup_name)
        except (ValtermError, OSError) as error:
            self.say(problem_text(error), "error")
            self._back()
            return
        self.modified = False
        self.app.mark_setup_modified(False)
        self.app.changed()
        self.say(f"{self.stage.active_session.setup_name}.SET RELOADED AS THE OTHER SESSION SAVED IT")
        self._back()

    def _saved(self, path: Path) -> None:
        self.modified = False
        self.app.mark_setup_modified(False)
        self.app.notify(f"{path.name} SAVED", timeout=3)
        self._back()

    def _back(self) -> None:
        self.part_axes = None
        self.leave()
