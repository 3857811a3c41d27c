"""One user's session: the workspace, the loaded setup, the simulator and the interpreter.

The app, ``valterm run`` and the tests build one of these; nothing here imports the UI.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING

from valterm.core.cell.workcell import WorkCell
from valterm.core.events import Event, Signal
from valterm.core.files.atomic import bytes_stamp, text_stamp
from valterm.core.files.locations import location_files_now, read_locations
from valterm.core.files.setup import format_setup, read_setup_bytes, write_setup
from valterm.core.kinematics import Location
from valterm.core.simulator import Simulator
from valterm.core.val.limits import RunLimits
from valterm.core.workspace import Workspace

if TYPE_CHECKING:        # the interpreter loads when first asked for (issue 25: start time)
    from valterm.core.val.interpreter import Interpreter

DEFAULT_SETUP = "PROCESS"


class Session:
    """What a VAL-II SIMULATOR session holds: the workspace, the cell, the robot, the programs."""

    def __init__(self, workspace_root: str | Path | None = None, setup: str | None = DEFAULT_SETUP,
                 limits: RunLimits | None = None, robot: str | None = None) -> None:
        self.workspace = Workspace.open(workspace_root)
        # the .LOC files as this session begins: STOREL says when another session stored one since
        self._loc_at_start = location_files_now(self.workspace.root)
        self.limits = limits or RunLimits()  # every EXECUTE's (valterm.core.val.limits)
        self.setup_name = ""
        self._setup_stamp = ""  # see setup_stamp
        self._setup_read: bytes | None = None  # NAME.SET's bytes as read, not stamped yet
        self.simulator = Simulator(robot=robot)  # robot: --robot's name (None: the thesis's)
        self._interpreter: Interpreter | None = None
        self._keyboard = False  # the app's keyboard sets inputs (take_inputs_from_keyboard)
        if setup:
            self.load_setup(setup)

    # -- setup files -----------------------------------------------------------
    def load_setup(self, name: str) -> WorkCell:
        """Read NAME.SET from the workspace into the simulator (FileFormatError if malformed)."""
        path = self.workspace.path(name, "SET")
        cell, self._setup_read = read_setup_bytes(path)  # one read: stamped as parsed
        self.simulator.cell = cell
        self.simulator.carried = None
        self.setup_name = path.stem
        return cell

    @property
    def setup_stamp(self) -> str:
        """NAME.SET as read ("" none): saving it again checks no other session saved it since.
        Taken from the bytes parsed when first asked (a save), not at the start (issue 25:
        hashlib loads OpenSSL, and the file was read a second time for it)."""
        if self._setup_read is not None:
            self._setup_stamp, self._setup_read = bytes_stamp(self._setup_read), None
        return self._setup_stamp

    def save_setup(self, name: str | None = None, overwrite: bool = False) -> Path:
        """Write the cell as NAME.SET (default: the setup loaded). Saved again under its own
        name, FileChanged (nothing written) when another session saved it since it was read,
        unless ``overwrite``; the UI asks (overwrite / reload / save as)."""
        path = self.workspace.path(name or self.setup_name, "SET")
        same = path.stem.upper() == self.setup_name.upper() and bool(self.setup_name)
        write_setup(path, self.simulator.cell, self.setup_stamp if same and not overwrite else None)
        self.setup_name = path.stem
        self._setup_stamp, self._setup_read = text_stamp(format_setup(self.simulator.cell)), None
        return path

    def load_locations(self, name: str) -> int:
        """Read NAME.LOC into the simulator's locations; returns how many."""
        locations = read_locations(self.workspace.path(name, "LOC"))
        self.simulator.locations.update(locations)
        self.simulator.mark_locations_stored(locations)
        return len(locations)

    def define_location(self, name: str, location: Location, stored: bool = False) -> None:
        """D_DEFINE or POINT in VAL-II mode: the location is known from now on (``stored``:
        as a .LOC file holds it, so leaving loses nothing)."""
        self.simulator.locations[name] = location
        if stored:
            self.simulator.mark_locations_stored([name])

    def toggle_collision_checks(self) -> bool:
        """S at KEYBOARD: collision checks on or off; returns the new state."""
        self.simulator.collision_checks = not self.simulator.collision_checks
        return bool(self.simulator.collision_checks)

    # -- the interpreter -------------------------------------------------------
    @property
    def interpreter(self) -> Interpreter:
        """The VAL-II interpreter bound to this session's simulator and workspace (made once)."""
        if self._interpreter is None:
            from valterm.core.val.interpreter import Interpreter

            self._interpreter = Interpreter.for_workspace(self.simulator, self.workspace)
            if self._interpreter.location_files is not None:  # STOREL: what changed since we began
                self._interpreter.location_files.at_start = self._loc_at_start
            self._interpreter.limits = self.limits
            self._interpreter.machine.keyboard = self._keyboard
        return self._interpreter

    def take_inputs_from_keyboard(self) -> None:
        """The app: a V+ WAIT that no scripted input can end waits for the user's keyboard
        (``key_input``) instead of stopping the program; CTRL-C still ends it."""
        self._keyboard = True
        if self._interpreter is not None:  # else the interpreter is made with it (not read early)
            self._interpreter.machine.keyboard = True

    def key_input(self, number: int, on: bool) -> Signal:
        """The user sets input ``number`` (1001-1512) of the I/O panel; SignalError otherwise."""
        return self.interpreter.machine.key_input(number, on)

    def command(self, text: str) -> Iterator[Event]:
        """One line typed at the VAL-II prompt (or after V at a menu), as events."""
        return self.interpreter.command(text)

    @property
    def program_running(self) -> bool:
        """An EXECUTE is under way (also while it is paused)."""
        return self._interpreter is not None and self._interpreter.running

    @property
    def program_paused(self) -> bool:
        """The running program waits at a PAUSE for PROCEED."""
        return self._interpreter is not None and self._interpreter.paused

    def abort_program(self) -> bool:
        """CTRL-C: the running program stops after its step (§6.4.10); False if none runs."""
        if not self.program_running:
            return False
        assert self._interpreter is not None
        self._interpreter.abort()
        return True
