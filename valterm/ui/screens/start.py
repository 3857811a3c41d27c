"""The start screen (§7.1, App. C §2): the copyright, then I_GES / U_GII / E_XISTING FILE.

E reads an existing setup file (RETURN accepts PROCESS); I and U read a CAD file from the
workspace, ask the §7.1 questions and write the new setup file, then go to the MAIN MENU.
A setup file that exists is never replaced unasked: Y replaces it, A adds the parts to it
(its objects kept), N or ESC ends the transfer with the file untouched. The units question
offers the file's own units (the IGES header; metres for glTF/GLB).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from textual.binding import Binding

from valterm.core.cad.convert import add_parts, import_cad, native_units
from valterm.core.errors import ValtermError
from valterm.core.files.errors import shown_name
from valterm.core.workspace import check_name
from valterm.ui import legends
from valterm.ui.errors import Refusal, problem_text
from valterm.ui.screens.base import MenuScreen
from valterm.ui.widgets.menus import COPYRIGHT, START_MENU, TITLE

DEFAULT_SETUP = "PROCESS"


@dataclass
class Transfer:
    """The answers of a part transfer, as they come."""

    kind: str  # I or U
    cad_file: str = ""
    setup: str = ""
    parts: int = 0
    units: str = "MM"
    file_units: str = "MM"  # what the file says its numbers are: the units question's default
    system: str = "W"
    add: bool = False  # add the parts to the existing setup file instead of writing a new one
    done: list[str] = field(default_factory=list)


class StartScreen(MenuScreen):
    SCREEN_NAME = "START"
    MENU = f"{TITLE}\n\n{COPYRIGHT}\n* VAL-II is a trademark of Unimation, Inc.\n\n{START_MENU}"
    BINDINGS = [
        Binding("i,I", "iges", "IGES file", id="start.iges"),
        Binding("u,U", "ugii", "UGII file", id="start.ugii"),
        Binding("e,E", "existing", "Existing file", id="start.existing"),
    ]

    def __init__(self, message: str = "", note: str = "") -> None:
        super().__init__()
        self._first_message = message
        self._note = note  # B_BEGIN: what the next set-up read starts without

    def on_mount(self) -> None:
        super().on_mount()
        self.add_class("-start")
        if self._first_message:
            self.say(self._first_message, "error")
        if self._note:
            self.say(self._note)

    def escape_menu(self) -> None:
        keys = ", ".join(f'"{legends.key_for(self, action, action[0].upper())}"' for action in ("iges", "ugii"))
        existing = legends.key_for(self, "existing", "E")
        helps = legends.shown(self, legends.HELP, " OR ")
        self.say(f'PRESS {keys} OR "{existing}" (RETURN THEN READS PROCESS); {helps} FOR HELP')

    # -- E_XISTING FILE ---------------------------------------------------------------
    def action_existing(self) -> None:
        self.ask_line(f"ENTER SET-UP FILE NAME (RETURN: {DEFAULT_SETUP}):", self._existing)

    def _existing(self, name: str) -> None:
        name = name or DEFAULT_SETUP
        try:
            self.app.open_session(name)
        except Exception as error:
            self.say(problem_text(error), "error")
            return
        self._to_main_menu()

    def _to_main_menu(self) -> None:
        self.app.show_main_menu()

    # -- I_GES FILE / U_GII FILE --------------------------------------------------------
    def action_iges(self) -> None:
        self._transfer(Transfer("I"))

    def action_ugii(self) -> None:
        self._transfer(Transfer("U"))

    def _transfer(self, t: Transfer) -> None:
        """Ask the next unanswered question of §7.1."""
        if not t.cad_file:
            what = "IGES" if t.kind == "I" else "UGII (POLYGON OR MESH)"
            self.ask_line(f"ENTER {what} FILE NAME TO BE READ:", lambda a: self._answer(t, "cad_file", a))
        elif not t.setup:
            self.ask_line("ENTER SET-UP FILE NAME:", lambda a: self._answer(t, "setup", a))
        elif "replace" not in t.done and self.app.session_workspace().exists(t.setup, "SET"):
            self.ask_key(f"{t.setup}.SET EXISTS: REPLACE IT (Y), ADD THE PARTS TO IT (A) OR KEEP IT (N) ?:",
                         lambda key: self._replace(t, key), "YAN", cancel=lambda: self._replace(t, "N"))
        elif not t.parts:
            self.ask_line("ENTER THE NUMBER OF WORKPIECES IN CELL:", lambda a: self._answer(t, "parts", a))
        elif "units" not in t.done:
            self.ask_line(f"ENTER UNITS OF WORKPIECES (MM/IN/M; THE FILE SAYS {t.file_units}):",
                          lambda a: self._answer(t, "units", a or t.file_units), t.file_units)
        elif "system" not in t.done:
            self.ask_line("ENTER COORDINATE AXES SYSTEM (W/S):", lambda a: self._answer(t, "system", a), "W")
        else:
            self._convert_large_after_saying(t)

    def _convert_large_after_saying(self, t: Transfer) -> None:
        """A large mesh takes seconds to read: say so on screen first, then convert."""
        from valterm.core.cad import mesh

        try:
            size = Path(t.cad_file).stat().st_size
        except OSError:
            size = 0
        if size < mesh.LARGE_BYTES:
            self._convert(t)
            return
        self.say(f"READING {Path(t.cad_file).name.upper()} ({size / 1e6:.0f} MB): THIS TAKES A FEW SECONDS ...")
        self.call_after_refresh(self._convert, t)

    def _answer(self, t: Transfer, what: str, answer: str) -> None:
        answer = answer.strip().upper()
        try:
            if what == "cad_file":
                stem, dot, ext = answer.rpartition(".")
                if not dot:
                    stem, ext = answer, ("IGS" if t.kind == "I" else "OBJ")
                file_name = check_name(stem, ext)
                path = self.app.session_workspace().path(*file_name.rsplit(".", 1))
                if not path.is_file():
                    raise Refusal(f"input file {file_name} does not exist in the workspace")
                t.cad_file = str(path)
                t.file_units = self._file_units(path)
            elif what == "setup":
                t.setup = check_name(answer, "SET").removesuffix(".SET")
            elif what == "parts":
                if not answer.isdigit() or int(answer) < 1:
                    raise Refusal(f"{answer or 'nothing'} is not a number of workpieces")
                t.parts = int(answer)
            elif what == "units":
                if answer not in ("MM", "IN", "M"):
                    raise Refusal("units must be MM, IN or M")
                t.units = answer
            elif what == "system":
                if answer not in ("W", "S"):
                    raise Refusal("the coordinate axes system must be W or S")
                t.system = answer
            t.done.append(what)
        except Exception as error:
            self.say(problem_text(error), "error")
            if what == "cad_file":                  # where the file must be, and the way round it
                self.say(self._where_cad_files())     # info: the command and the path as typed
            self.ask_key("DO YOU WANT TO CONTINUE THE PART TRANSFER (Y/N) ?:",
                         lambda key: self._transfer(t) if key == "Y" else self.say("PART TRANSFER ENDED"))
            return
        self._transfer(t)

    def _where_cad_files(self) -> str:
        """CAD files are read from the workspace under a short name (one read path, issue 16):
        say where it is, and that ``valterm import`` reads a file from anywhere."""
        root = shown_name(str(self.app.session_workspace().root), 80)
        return (f"CAD FILES ARE READ FROM THE WORKSPACE {root} UNDER A NAME OF AT MOST 9 LETTERS "
                "OR DIGITS (E.G. CHASSIS.IGS); valterm import FILE --out NAME.SET READS ANY PATH")

    @staticmethod
    def _file_units(path: object) -> str:
        """The file's own units for the units question; MM when the file cannot tell (the
        conversion reports what is wrong with it)."""
        try:
            return native_units(str(path))
        except ValtermError:
            return "MM"

    def _replace(self, t: Transfer, key: str) -> None:
        """The answer to "NAME.SET EXISTS": Y replace, A add the parts, N keep it (ends)."""
        if key == "N":
            self.say(f"{t.setup}.SET KEPT; PART TRANSFER ENDED")
            return
        t.add = key == "A"
        t.done.append("replace")
        self._transfer(t)

    def _convert(self, t: Transfer) -> None:
        try:
            workspace = self.app.session_workspace()
            setup = workspace.read_setup(t.setup) if t.add else None
            cell = import_cad(t.cad_file, units=t.units, system=t.system, name=t.setup, parts=t.parts,
                              around=setup.objects if setup is not None else ())
            if setup is not None:
                cell = add_parts(setup, cell)
            path = workspace.write_setup(t.setup, cell)
        except ImportError as error:
            self.say(f"CAD IMPORT NOT AVAILABLE: {error}".upper(), "error")
            return
        except Exception as error:
            self.say(problem_text(error), "error")
            self.say("PART TRANSFER ENDED")
            return
        for warning in cell.warnings:
            self.say(warning.upper(), "warning")
        added = f"{len(cell.objects) - len(setup.objects)} PART(S) ADDED; " if setup is not None else ""
        self.say(f"{added}FILE {path.name} HAS SUCCESSFULLY BEEN WRITTEN")
        if not cell.warnings:
            self._existing(t.setup)
            return
        # the MAIN MENU would hide the warnings (a part too large for any table): let them be read
        self.ask_key("PRESS RETURN TO CONTINUE", lambda _: self._existing(t.setup), "\n",
                     cancel=lambda: self._existing(t.setup))
