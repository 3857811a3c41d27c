"""The workspace: the one folder that holds every user file (SPEC §5, §5.1, §6.7).

Names are 1 to 9 characters of A-Z and 0-9 before the extension, as on the VAX; typed
names are upper-cased. Nothing is read or written outside the workspace: a name that
could reach elsewhere (a path separator, ``..``, anything but A-Z0-9) is refused before
any file is touched. On first use the bundled cells and programs of the thesis are copied
in, with DATFILER.DAT listing the programs and an empty CHECK.DAT.
"""

from __future__ import annotations

import os
import re
import shutil
from pathlib import Path

from valterm.core.errors import ValtermError
from valterm.core import resources
from valterm.core.cell.workcell import WorkCell
from valterm.core.files import datfiler, locations, programs, setup, variables
from valterm.core.files.datfiler import DATFILER
from valterm.core.files.programs import Program
from valterm.core.files.variables import CHECK
from valterm.core.kinematics import Location

ENV_VAR = "VALTERM_WORKSPACE"
DEFAULT_ROOT = Path("~/valterm")

MAX_NAME = 9
_NAME = re.compile(r"[A-Z0-9]{1,9}")

# Files the simulator keeps for itself: not programs, though they end in .DAT.
SYSTEM_FILES = frozenset({"DATFILER", "CHECK", "HELPER", "COMMAND"})

# Names Windows will not create as files; refused everywhere so a workspace travels.
_RESERVED = frozenset({"CON", "PRN", "AUX", "NUL", *(f"COM{i}" for i in range(1, 10)), *(f"LPT{i}" for i in range(1, 10))})

_KINDS = {"SET": "setup", "LOC": "location", "DAT": "program"}


class WorkspaceError(ValtermError):
    """A name or folder the workspace refuses; the message says why."""




def default_root() -> Path:
    """$VALTERM_WORKSPACE, else ~/valterm."""
    chosen = os.environ.get(ENV_VAR)
    return Path(chosen).expanduser() if chosen else DEFAULT_ROOT.expanduser()


def check_name(name: str, ext: str) -> str:
    """``NAME.EXT`` for a typed name (case-insensitive, extension optional), or WorkspaceError."""
    ext = ext.upper().lstrip(".")
    typed = name.strip()
    upper = typed.upper()
    stem, dot, given = upper.rpartition(".") if "." in upper else (upper, "", "")

    def refuse(why: str) -> WorkspaceError:
        return WorkspaceError(f"{name!r} is not a valid name: {why}")

    if "/" in typed or "\\" in typed or ".." in typed or typed.startswith("~"):
        raise refuse("names may not contain a path; files live in the workspace folder")
    if not typed:
        raise refuse("a name needs 1 to 9 letters or digits")
    if dot and given != ext:
        kind = _KINDS.get(ext, ext)
        raise refuse(f"a {kind} file name ends in .{ext}")
    if len(stem) > MAX_NAME:
        raise refuse(f"at most {MAX_NAME} letters or digits before .{ext} ({len(stem)} given)")
    if not _NAME.fullmatch(stem):
        raise refuse("only the letters A-Z and digits 0-9 are allowed")
    if stem in _RESERVED:
        raise refuse("that name is reserved by some operating systems")
    return f"{stem}.{ext}"


class Workspace:
    """The workspace folder and the files in it, read and written through valterm.core.files."""

    def __init__(self, root: str | Path) -> None:
        self.root = Path(root).expanduser()

    @classmethod
    def open(cls, root: str | Path | None = None) -> "Workspace":
        """The workspace at ``root`` (default: $VALTERM_WORKSPACE or ~/valterm), created and
        seeded with the bundled data on first use."""
        workspace = cls(default_root() if root is None else root)
        if workspace.root.exists() and not workspace.root.is_dir():
            raise WorkspaceError(f"the workspace {workspace.root} is a file, not a folder")
        try:
            workspace.root.mkdir(parents=True, exist_ok=True)
        except OSError as error:
            raise WorkspaceError(f"cannot create the workspace {workspace.root}: {error.strerror or error}") from None
        if not (workspace.root / DATFILER).exists():
            workspace.seed()
        return workspace

    # -- names ---------------------------------------------------------------
    check_name = staticmethod(check_name)

    def path(self, name: str, ext: str) -> Path:
        """root/NAME.EXT after the name check; an existing file in another case is found too."""
        file_name = check_name(name, ext)
        path = self.root / file_name
        if not path.exists():
            path = self._other_case(file_name) or path
        if path.is_symlink() and path.resolve().parent != self.root.resolve():
            raise WorkspaceError(f"{file_name} links outside the workspace; refusing to use it")
        return path

    def _other_case(self, file_name: str) -> Path | None:
        """A file copied in as ``process.set`` still answers to PROCESS.SET."""
        try:
            return next((p for p in self.root.iterdir() if p.name.upper() == file_name), None)
        except OSError:
            return None

    def exists(self, name: str, ext: str) -> bool:
        return self.path(name, ext).is_file()

    # -- first use -----------------------------------------------------------
    def seed(self) -> list[str]:
        """Copy the bundled cells and programs in (never over a user's file); make DATFILER.DAT
        list the bundled programs and CHECK.DAT exist. Returns the file names copied."""
        copied: list[str] = []
        program_names: list[str] = []
        for folder in (resources.CELLS, resources.PROGRAMS):
            for source in resources.bundled_files(folder):
                try:
                    file_name = check_name(source.name, source.suffix.lstrip(".") or "?")
                except WorkspaceError:
                    continue  # README.md and the like
                stem, ext = file_name.rsplit(".", 1)
                if ext not in _KINDS or not source.is_file():
                    continue
                if ext == "DAT" and stem not in SYSTEM_FILES:
                    program_names.append(stem)
                target = self.root / file_name
                if not target.exists():
                    shutil.copyfile(source, target)
                    copied.append(file_name)
        datfiler_path = self.root / DATFILER
        if not datfiler_path.exists():
            datfiler.write_datfiler(datfiler_path, program_names)
        check_path = self.root / CHECK
        if not check_path.exists():
            variables.write_variables(check_path, {})
        return copied

    # -- listings (names without extension, as LISTF / LISTL show them) -------
    def _names(self, ext: str) -> list[str]:
        found = set()
        try:
            entries = list(self.root.iterdir())
        except OSError:
            return []
        for entry in entries:
            upper = entry.name.upper()
            stem, _, given = upper.rpartition(".")
            if given == ext and _NAME.fullmatch(stem) and entry.is_file():
                found.add(stem)
        return sorted(found)

    def list_setups(self) -> list[str]:
        return self._names("SET")

    def list_locations(self) -> list[str]:
        return self._names("LOC")

    def list_programs(self) -> list[str]:
        """The programs of DATFILER.DAT in its order, then any other program file found."""
        listed = self.programs_directory()
        on_disk = [n for n in self._names("DAT") if n not in SYSTEM_FILES and n not in listed]
        return listed + on_disk

    # -- setup files ------------------------------------------------------------
    def read_setup(self, name: str) -> WorkCell:
        return setup.read_setup(self.path(name, "SET"))

    def write_setup(self, name: str, cell: WorkCell) -> Path:
        path = self.path(name, "SET")
        setup.write_setup(path, cell)
        return path

    # -- location files ----------------------------------------------------------
    def read_locations(self, name: str) -> dict[str, Location]:
        return locations.read_locations(self.path(name, "LOC"))

    def write_locations(self, name: str, points: dict[str, Location]) -> Path:
        path = self.path(name, "LOC")
        locations.write_locations(path, points)
        return path

    # -- programs ----------------------------------------------------------------
    def read_program(self, name: str) -> Program:
        return programs.read_program(self.path(self._program_name(name), "DAT"))

    def write_program(self, program: Program, name: str | None = None) -> Path:
        """Save a program and list it in DATFILER.DAT (§5.1: a new program's name is added)."""
        stem = self._program_name(name or program.name)
        path = self.path(stem, "DAT")
        programs.write_program(path, program)
        self.add_program(stem)
        return path

    def programs_directory(self) -> list[str]:
        """The program names DATFILER.DAT lists (empty if it is missing)."""
        path = self.path("DATFILER", "DAT")
        return datfiler.read_datfiler(path) if path.exists() else []

    def add_program(self, name: str) -> bool:
        """List a program in DATFILER.DAT; False when it was listed already."""
        stem = self._program_name(name)
        return datfiler.add_program_name(self.path("DATFILER", "DAT"), stem)

    def _program_name(self, name: str) -> str:
        stem = check_name(name, "DAT").removesuffix(".DAT")
        if stem in SYSTEM_FILES:
            raise WorkspaceError(f"{name!r} is not a valid name: {stem}.DAT is kept by the simulator")
        return stem

    # -- variables (CHECK.DAT) ---------------------------------------------------
    def read_variables(self) -> dict[str, float]:
        path = self.path("CHECK", "DAT")
        return variables.read_variables(path) if path.exists() else {}

    def write_variables(self, values: dict[str, float]) -> Path:
        path = self.path("CHECK", "DAT")
        variables.write_variables(path, values)
        return path
