"""KEYBOARD MENU (Fig. 2-3, Fig. C-3): listings, the clamp position, collision checks, back
faces, ORIENT, axes, the model, one VAL-II command."""

from __future__ import annotations

from typing import TYPE_CHECKING

from textual import events
from textual.app import ComposeResult
from textual.binding import Binding

from valterm.core.text.transcript import wrap_line
from valterm.ui import legends
from valterm.ui.errors import Refusal, problem_text
from valterm.ui.screens.base import MENU, MenuScreen
from valterm.ui.widgets.menus import KEYBOARD_MENU, ORIENT_MENU
from valterm.ui.widgets.readouts import PositionReadout

if TYPE_CHECKING:  # annotations only
    from valterm.core.session import Session
    from valterm.core.workspace import Workspace

ORIENT_TURN = 15.0  # degrees a key
ORIENT_ZOOM = 1.25
ORIENT_PAN = 50.0  # screen mm a key, at scale 1
POINT_NAMES = {1: "TCS ORIGIN", 2: "LED SENSOR", 3: "CLAMP TIP"}


def program_listing(workspace: Workspace, name: str) -> list[str]:
    """LISTP: a program's steps, numbered as the editor numbers them."""
    program = workspace.read_program(name)
    lines = [f"PROGRAM {program.name}.DAT", ""]
    for number, step in enumerate(program.steps, start=1):
        label = "" if step.label is None else str(step.label)
        lines.append(f"{number:>3}. {label:<4} {step.text}")
    return lines


def command_view(session: Session, command: str) -> list[str]:
    """LISTP name / LISTF / LISTL typed after L (the LIST prefix may be left out)."""
    words = command.strip().upper().replace(",", " ").split()
    if not words:
        raise Refusal("type LISTP NAME, LISTF OR LISTL")
    verb = words[0] if words[0].startswith("LIST") else "LIST" + words[0]
    workspace = session.workspace
    if verb == "LISTF":
        names = workspace.list_programs()
        return ["VAL-II PROGRAMS:", *(f"  {n}.DAT" for n in names)] if names else ["NO VAL-II PROGRAMS"]
    if verb == "LISTL":
        names = workspace.list_locations()
        return ["VAL-II LOCATION DATA FILES:", *(f"  {n}.LOC" for n in names)] if names else ["NO LOCATION DATA FILES"]
    if verb == "LISTP":
        if len(words) < 2:
            raise Refusal("LISTP needs a program name")
        return program_listing(workspace, words[1])
    raise NotAListing(f"{words[0]} is not LISTP, LISTF or LISTL")


class NotAListing(Refusal):
    """What was typed after L is no listing (``LOAD`` typed at the menu: its L opened LIST)."""


class KeyboardScreen(MenuScreen):
    MENU = KEYBOARD_MENU
    # the thesis takes V before a command; a person types HERE P1 as at the real terminal:
    # a letter that is no menu key starts the command line, other keys get the hint
    LETTERS_START_A_COMMAND = True
    UNKNOWN_KEY_HINT = "{val} FIRST TO TYPE A VAL-II COMMAND"  # V as bound now
    BINDINGS = [
        Binding("l,L", "list", "List", id="keyboard.list"),
        Binding("p,P", "position", "Position", id="keyboard.position"),
        Binding("s,S", "smooth", "Collision checks", id="keyboard.smooth"),
        Binding("f,F", "faces", "Back faces", id="keyboard.faces"),
        Binding("o,O", "orient", "Orient", id="keyboard.orient"),
        Binding("a,A", "axes", "Axes", id="keyboard.axes"),
        Binding("r,R", "return", "Return", id="keyboard.return"),
        Binding("m,M", "model", "Model", id="keyboard.model"),
        Binding("v,V", "val", "VAL-II command", id="keyboard.val"),
        # ORIENT1's keys (Fig. 2-3): the view only
        Binding("plus,equals_sign", "orient_key('zoom_in')", "Scale up", show=False, id="keyboard.orient.zoom_in"),
        Binding("minus,underscore", "orient_key('zoom_out')", "Scale down", show=False, id="keyboard.orient.zoom_out"),
        *(Binding(arrow, f"orient_key('{arrow}')", f"Translate {arrow}", show=False, id=f"keyboard.orient.{arrow}")
          for arrow in ("left", "right", "up", "down")),
        *(Binding(axis, f"orient_key('{axis}')", f"Rotate about screen {axis.upper()}", show=False,
                  id=f"keyboard.orient.{axis}") for axis in "xyz"),
        *(Binding(axis.upper(), f"orient_key('-{axis}')", f"Rotate back about screen {axis.upper()}",
                  show=False, id=f"keyboard.orient.back_{axis}") for axis in "xyz"),
        Binding("h,H", "orient_key('home')", "The first view", show=False, id="keyboard.orient.home"),
        Binding("r,R", "orient_key('menu')", "Back to the KEYBOARD MENU", show=False, id="keyboard.orient.return"),
    ]
    STATES = {"orient_key": frozenset({"orient"})}  # the menu's own keys work at the menu (MenuScreen)

    def __init__(self) -> None:
        super().__init__()
        self.point = 0  # the position readout's point (1, 2, 3), 0 = not shown
        self.orienting = False
        self.listing = False

    def compose_readout(self) -> ComposeResult:
        yield PositionReadout(id="readout", classes="-hidden")

    def update_readout(self) -> None:
        if not self.point:
            return
        readout = self.query_one("#readout", PositionReadout)
        readout.show_where(self.stage.simulator.where(self.point), f"POSITION {self.point}: {POINT_NAMES[self.point]}")
        readout.remove_class("-hidden")

    # -- listings ---------------------------------------------------------------------
    def action_list(self) -> None:
        self.ask_line("LIST - TYPE LISTP PROG. NAME, LISTF OR LISTL:", self._list)

    def _list(self, command: str) -> None:
        try:
            lines = command_view(self.stage.active_session, command)
        except Exception as error:
            text = problem_text(error)
            if isinstance(error, NotAListing):  # say why a command typed here became a listing
                text += f" ({legends.key_for(self, 'list', 'L')} IS LIST HERE: {self.unknown_key_hint()})"
            self.say(text, "error")
            return
        width = max(min(self.app.size.width - 4, 74), 20)  # long lines wrap, never cut (issue 17)
        wrapped = [part for line in lines for part in wrap_line(line, width, "      ")]
        self.menu.set_text("\n".join([*wrapped, "", "PRESS ANY KEY FOR THE MENU"]))
        self.listing = True
        self.show_model(False)

    def _restore_menu(self) -> None:
        self.listing = self.orienting = False
        self.menu.set_text(self.live_menu(KEYBOARD_MENU))

    @property
    def key_state(self) -> str:
        """Asking, at the menu, a listing shown, or ORIENT1's keys."""
        if self.asking:
            return super().key_state
        return "orient" if self.orienting else "listing" if self.listing else MENU

    def on_key(self, event: events.Key) -> None:
        """A listing: any key brings the menu back (a menu key also does its work); then the
        one key path (KeyedScreen.on_key)."""
        if self.key_state == "listing":
            self._restore_menu()
            if not self.bound_here(event.key):
                event.stop()
                event.prevent_default()

    def other_key(self, event: events.Key) -> bool:
        if self.key_state == "orient":
            keys = ("ORIENT1: {keyboard.orient.zoom_in|+} {keyboard.orient.zoom_out|-} ARROWS X Y Z "
                    "{keyboard.orient.home} OR {keyboard.orient.return}")
            self.say(legends.fill(self, keys), "warning")
            return True
        return super().other_key(event)

    def escape_menu(self) -> None:
        """ESC: ORIENT1 back to the KEYBOARD MENU; at the menu, MAIN."""
        if self.orienting:
            self._restore_menu()
        else:
            super().escape_menu()

    # -- P, S, F, A ------------------------------------------------------------------
    def action_position(self) -> None:
        self.ask_key("POSITION: 1 (TCS ORIGIN), 2 (LED SENSOR) OR 3 (CLAMP TIP) ?:", self._position, "123")

    def _position(self, key: str) -> None:
        self.point = int(key)
        self.update_readout()

    def action_smooth(self) -> None:
        on = self.stage.active_session.toggle_collision_checks()
        self.say(f"COLLISION CHECKS {'ON' if on else 'OFF'}")

    def action_faces(self) -> None:
        shown = not self.stage.back_faces
        self.app.show_back_faces(shown)
        self.model_view.back_faces = shown
        self.say("BACK FACES ON: HIDDEN SURFACES NOT REMOVED" if shown
                 else "BACK FACES OFF: HIDDEN SURFACES REMOVED")

    def action_axes(self) -> None:
        shown = not self.stage.axes
        self.app.show_axes(shown)
        self.model_view.axes = shown
        self.say(f"COORDINATE FRAMES {'ON' if shown else 'OFF'}")

    # -- ORIENT1 --------------------------------------------------------------------------
    def action_orient(self) -> None:
        self.orienting = True
        self.menu.set_text(self.live_menu(ORIENT_MENU, "orient"))
        self.say("ORIENT1: THE VIEW ONLY; WORLD DATA ARE NOT CHANGED")

    def action_orient_key(self, what: str) -> None:
        """One of ORIENT1's keys: scale, translate, rotate, home, or back to the menu."""
        view = self.model_view
        pan = ORIENT_PAN / max(self.stage.view_transform.scale, 1e-6)
        moves = {"left": (-pan, 0), "right": (pan, 0), "up": (0, pan), "down": (0, -pan)}
        if what in ("zoom_in", "zoom_out"):
            view.scale_by(ORIENT_ZOOM if what == "zoom_in" else 1 / ORIENT_ZOOM)
        elif what in moves:
            view.pan_by(*moves[what])
        elif what.lstrip("-") in ("x", "y", "z"):
            view.rotate_by(what.lstrip("-"), -ORIENT_TURN if what.startswith("-") else ORIENT_TURN)
        elif what == "home":
            view.reset_view()
        else:
            self._restore_menu()
            return
        if self.has_class("-narrow"):
            self.show_model(True)

    # -- R, M, V ------------------------------------------------------------------------
    def action_return(self) -> None:
        self.leave()

    def action_model(self) -> None:
        self.toggle_model()

    def after_motion(self, aborted: bool) -> None:
        self.update_readout()
