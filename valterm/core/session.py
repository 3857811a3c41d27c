"""One user's session: the workspace, the loaded setup, the simulator and the interpreter.

The app, ``valterm run`` and the tests build one of these; nothing here imports the UI.
"""

from __future__ import annotations

from pathlib import Path

from valterm.core.cell.workcell import WorkCell
from valterm.core.simulator import Simulator

DEFAULT_SETUP = "PROCESS"


class Session:
    """What a VAL-II SIMULATOR session holds: the workspace, the cell, the robot, the programs."""

    def __init__(self, workspace_root: str | Path | None = None, setup: str | None = DEFAULT_SETUP) -> None:
        from valterm.core.workspace import Workspace

        self.workspace = Workspace.open(workspace_root)
        self.setup_name = ""
        self.simulator = Simulator()
        self._interpreter = None
        if setup:
            self.load_setup(setup)

    # -- setup files -----------------------------------------------------------
    def load_setup(self, name: str) -> WorkCell:
        """Read NAME.SET from the workspace into the simulator (FileFormatError if malformed)."""
        from valterm.core.files.setup import read_setup

        path = self.workspace.path(name, "SET")
        cell = read_setup(path)
        self.simulator.cell = cell
        self.simulator.carried = None
        self.setup_name = path.stem
        return cell

    def save_setup(self, name: str | None = None) -> Path:
        from valterm.core.files.setup import write_setup

        path = self.workspace.path(name or self.setup_name, "SET")
        write_setup(path, self.simulator.cell)
        self.setup_name = path.stem
        return path

    def load_locations(self, name: str) -> int:
        """Read NAME.LOC into the simulator's locations; returns how many."""
        from valterm.core.files.locations import read_locations

        locations = read_locations(self.workspace.path(name, "LOC"))
        self.simulator.locations.update(locations)
        return len(locations)

    # -- the interpreter -------------------------------------------------------
    @property
    def interpreter(self):  # type: ignore[no-untyped-def]
        """The VAL-II interpreter bound to this session's simulator and workspace (made once)."""
        if self._interpreter is None:
            from valterm.core.val.interpreter import Interpreter

            self._interpreter = Interpreter.for_workspace(self.simulator, self.workspace)
        return self._interpreter
