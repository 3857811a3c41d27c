"""The workspace: the one folder that holds every user file (SPEC §5, §5.1, §6.7).

Names are 1 to 9 characters of A-Z and 0-9 before the extension, as on the VAX; typed
names are upper-cased. Nothing is read or written outside the workspace: a name that
could reach elsewhere (a path separator, ``..``, anything but A-Z0-9) is refused before
any file is touched, and so is a file that is a link to somewhere outside the folder.
Every file is written through ``valterm.core.files.atomic`` (never through a link).

On first use the bundled cells and programs of the thesis are copied in, each atomically,
then an empty CHECK.DAT and, last, DATFILER.DAT listing the programs: DATFILER.DAT marks a
finished first use. Until it exists every open seeds again, restoring a bundled file that
is missing, empty or cut short (a strict prefix of the bundled one); afterwards only an
empty bundled file is restored. A file the user changed is never touched. Each open also
removes the temporaries of writes that were killed.

Several sessions may share a workspace. A save given the stamp its session read the file
with (:meth:`Workspace.stamp`) raises FileChanged instead of overwriting another session's
save; CHECK.DAT is merged per variable under the folder's lock (:meth:`Workspace.merge_variables`).
"""

from __future__ import annotations

import os
import re
import stat
from collections.abc import Callable
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING

from valterm.core import resources
from valterm.core.errors import ValtermError
from valterm.core.files import datfiler, programs, variables
from valterm.core.files._text import read_bytes
from valterm.core.files.atomic import (
    file_stamp,
    folder_lock,
    open_regular,
    remove_stale_temporaries,
    write_bytes_atomic,
)
from valterm.core.files.datfiler import DATFILER
from valterm.core.files.errors import shown_name
from valterm.core.files.programs import Program
from valterm.core.files.variables import CHECK

if TYPE_CHECKING:
    from valterm.core.cell.workcell import WorkCell
    from valterm.core.files.vplus import VplusData
    from valterm.core.kinematics import Location

# The set-up and location readers (numpy, the kinematics) load when a set-up or a location
# file is first read: the command line and the app's first frame need neither (issue 25).

ENV_VAR = "VALTERM_WORKSPACE"
DEFAULT_ROOT = Path("~/valterm")

MAX_NAME = 9
_NAME = re.compile(r"[A-Z0-9]{1,9}")

# Files the simulator keeps for itself: not programs, though they end in .DAT.
SYSTEM_FILES = frozenset({"DATFILER", "CHECK", "HELPER", "COMMAND"})

# Names Windows will not create as files; refused everywhere so a workspace travels.
_RESERVED = frozenset({"CON", "PRN", "AUX", "NUL",
                       *(f"COM{i}" for i in range(1, 10)), *(f"LPT{i}" for i in range(1, 10))})

_KINDS = {"SET": "setup", "LOC": "location", "DAT": "program"}
# V+ program files (docs/VPLUS.md): NAME.V2 / NAME.PG, several .PROGRAM blocks each; their
# reader loads when a V+ name or file is first met (not at the app's start, issue 25)
VPLUS_KINDS = ("V2", "PG")  # valterm.core.files.vplus.EXTENSIONS without the dot


def _vplus() -> ModuleType:
    from valterm.core.files import vplus

    return vplus


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
        return WorkspaceError(f"{shown_name(name)!r} is not a valid name: {why}")

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


def checked_path(folder: Path, file_name: str) -> Path:
    """folder/FILE_NAME (an existing file in another case is found too), or WorkspaceError when
    that file is a link to somewhere outside ``folder``. ``file_name`` is already checked."""
    path = folder / file_name
    if not os.path.lexists(path):
        path = _other_case(folder, file_name) or path
    if path.is_symlink():
        try:
            outside = path.resolve().parent != folder.resolve()
        except (OSError, RuntimeError):  # a link loop
            outside = True
        if outside:
            raise WorkspaceError(f"{path.name} links outside the workspace; refusing to use it")
    return path


def _other_case(folder: Path, file_name: str) -> Path | None:
    """A file copied in as ``process.set`` still answers to PROCESS.SET."""
    try:
        return next((p for p in folder.iterdir() if p.name.upper() == file_name), None)
    except OSError:
        return None


def bundled_workspace_files() -> list[tuple[str, Path]]:
    """(NAME.EXT, bundled path) of every setup, location and program file a workspace is seeded with."""
    found: list[tuple[str, Path]] = []
    for folder in (resources.CELLS, resources.PROGRAMS):
        for source in resources.bundled_files(folder):
            try:
                file_name = check_name(source.name, source.suffix.lstrip(".") or "?")
            except WorkspaceError:
                continue  # README.md and the like
            if file_name.rsplit(".", 1)[1] in _KINDS:
                found.append((file_name, source))
    return found


def first_setup_bytes(root: str | Path | None, name: str) -> bytes | None:
    """NAME.SET's bytes as a session opening the workspace at ``root`` would read them, without
    opening it: the bundled file's in a workspace not filled yet (its first use copies it in);
    None when the name is refused or there is no such file. For the start's kept picture
    (core/render/kept.py), before anything is written."""
    folder = default_root() if root is None else Path(root).expanduser()
    try:
        file_name = check_name(name, "SET")
        path = checked_path(folder, file_name)
        if not os.path.lexists(folder / DATFILER) and not os.path.lexists(path):
            path = resources.data_path(resources.CELLS, file_name)
        return read_bytes(path, "setup")  # as the set-up reader opens it: no FIFO waited on
    except ValtermError:
        return None


def _damaged_copy(target: Path, source: Path, prefix: bool) -> bytes | None:
    """The bundled bytes when ``target`` is a damaged copy of ``source`` (a plain file that is
    empty or, when ``prefix``, a strict prefix of it), else None: a user's file stays as it is."""
    try:
        info = os.lstat(target)
    except OSError:
        return None
    if not stat.S_ISREG(info.st_mode):
        return None
    if info.st_size == 0:
        return source.read_bytes()
    if not prefix:
        return None
    data = source.read_bytes()
    if info.st_size >= len(data):
        return None
    try:
        handle, _info = open_regular(target, follow_links=False)  # swapped for a FIFO since: no wait
    except OSError:
        return None
    with handle:
        return data if data.startswith(handle.read(len(data))) else None


class Workspace:
    """The workspace folder and the files in it, read and written through valterm.core.files."""

    def __init__(self, root: str | Path) -> None:
        self.root = Path(root).expanduser()
        # CHECK.DAT's values as this session last read or wrote them: a merge writes only the
        # variables the session changed since, and keeps the others' as they are on disk
        self._variables_seen: dict[str, float] = {}

    @classmethod
    def open(cls, root: str | Path | None = None) -> Workspace:
        """The workspace at ``root`` (default: $VALTERM_WORKSPACE or ~/valterm), created and
        seeded with the bundled data on first use; killed writes' temporaries removed."""
        workspace = cls(default_root() if root is None else root)
        shown = shown_name(str(workspace.root), 80)
        try:
            if workspace.root.exists() and not workspace.root.is_dir():
                raise WorkspaceError(f"the workspace {shown} is a file, not a folder")
            workspace.root.mkdir(parents=True, exist_ok=True)
        except OSError as error:  # a name too long, a path through a file, no permission
            raise WorkspaceError(f"cannot create the workspace {shown}: {error.strerror or error}") from None
        remove_stale_temporaries(workspace.root)
        try:
            workspace.seed()
        except OSError as error:  # a read-only or full disk: say so, once, with the file
            raise WorkspaceError(f"cannot fill the workspace {shown}: {error}") from None
        return workspace

    # -- names ---------------------------------------------------------------
    check_name = staticmethod(check_name)

    def path(self, name: str, ext: str) -> Path:
        """root/NAME.EXT after the name check; an existing file in another case is found too.

        WorkspaceError when the file is a link to somewhere outside the workspace."""
        return checked_path(self.root, check_name(name, ext))

    def exists(self, name: str, ext: str) -> bool:
        return self.path(name, ext).is_file()

    def stamp(self, name: str, ext: str) -> str:
        """The stamp of NAME.EXT as it is now ("" when there is none), for a later checked save."""
        return file_stamp(self.path(name, ext))

    # -- first use -----------------------------------------------------------
    def seed(self) -> list[str]:
        """Copy the bundled cells and programs in (see the module docstring); make CHECK.DAT
        exist, then DATFILER.DAT list the bundled programs. Returns the file names written."""
        first_use = not os.path.lexists(self.root / DATFILER)
        copied: list[str] = []
        program_names: list[str] = []
        for file_name, source in bundled_workspace_files():
            stem, ext = file_name.rsplit(".", 1)
            if ext == "DAT" and stem not in SYSTEM_FILES:
                program_names.append(stem)
            target = self.root / file_name
            if first_use and not os.path.lexists(target) and _other_case(self.root, file_name) is None:
                data: bytes | None = source.read_bytes()
            else:
                data = _damaged_copy(target, source, prefix=first_use)
            if data is None:
                continue
            try:
                write_bytes_atomic(target, data)
            except OSError:
                if first_use:
                    raise
                continue  # a read-only workspace: the damaged file says so when it is read
            copied.append(file_name)
        if first_use:
            if not os.path.lexists(self.root / CHECK):
                variables.write_variables(self.root / CHECK, {})
            datfiler.write_datfiler(self.root / DATFILER, program_names)
        return copied

    def program_loader(self, beside: str | Path | None = None) -> Callable[[str], Program]:
        """``load(NAME) -> Program`` for CALLed programs: NAME.DAT from the folder ``beside``
        (the main program's, when it was given as a path) if it holds one, else from the
        workspace. Both folders get the workspace's checks: a valid name, and no link to
        anywhere outside the folder."""
        folder = Path(beside) if beside is not None else None

        def load(name: str) -> Program:
            if _vplus().is_dotted_name(name):
                return self.read_program(name)  # only the workspace's V+ files define it
            stem = self._program_name(name)
            if folder is not None:
                near = checked_path(folder, f"{stem}.DAT")
                if os.path.lexists(near):
                    return programs.read_program(near)
            return self.read_program(stem)

        return load

    def program_test(self, beside: str | Path | None = None) -> Callable[[str], bool]:
        """``exists(NAME) -> bool`` matching :meth:`program_loader` (the syntax checker's CALL
        test); WorkspaceError for a file that links outside its folder."""
        folder = Path(beside) if beside is not None else None

        def exists(name: str) -> bool:
            if _vplus().is_dotted_name(name):
                return name.strip().upper() in self.vplus_programs()
            file_name = check_name(name, "DAT")
            if folder is not None and checked_path(folder, file_name).is_file():
                return True
            return self.path(file_name, "DAT").is_file() or name.strip().upper() in self.vplus_programs()

        return exists

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
        seen = set(listed + on_disk)
        return listed + on_disk + [n for n in self.vplus_programs() if n not in seen]

    # -- setup files ------------------------------------------------------------
    def read_setup(self, name: str) -> WorkCell:
        from valterm.core.files import setup

        return setup.read_setup(self.path(name, "SET"))

    def write_setup(self, name: str, cell: WorkCell, expected: str | None = None) -> Path:
        """Write NAME.SET; with ``expected`` (its stamp when read) FileChanged if it changed since."""
        from valterm.core.files import setup

        path = self.path(name, "SET")
        setup.write_setup(path, cell, expected)
        return path

    # -- location files ----------------------------------------------------------
    def read_locations(self, name: str) -> dict[str, Location]:
        from valterm.core.files import locations

        return locations.read_locations(self.path(name, "LOC"))

    def write_locations(self, name: str, points: dict[str, Location],
                        precision: dict[str, tuple[float, ...]] | None = None) -> Path:
        from valterm.core.files import locations

        path = self.path(name, "LOC")
        locations.write_locations(path, points, precision)
        return path

    # -- programs ----------------------------------------------------------------
    def read_program(self, name: str) -> Program:
        """NAME.DAT; else the program NAME of a V+ file of the workspace (a dotted name: only there)."""
        if _vplus().is_dotted_name(name):
            return self._vplus_program(name.strip().upper())
        path = self.path(self._program_name(name), "DAT")
        if not path.is_file():
            found = self.vplus_programs().get(path.stem.upper())
            if found is not None:
                return found[0]
        return programs.read_program(path)

    # -- V+ program files (.V2, .PG) -------------------------------------------------
    def vplus_source(self, name: str) -> tuple[Program, Path] | None:
        """(program, its .V2/.PG file) when ``name`` is a V+ program of the workspace that no
        NAME.DAT holds (the editor shows it read-only); None otherwise."""
        upper = name.strip().upper().removesuffix(".DAT")
        if not _vplus().is_dotted_name(upper):
            try:
                if self.path(self._program_name(upper), "DAT").is_file():
                    return None
            except WorkspaceError:
                return None  # a bad name: the caller's own check says why
        return self.vplus_programs().get(upper)

    def vplus_data(self, name: str) -> tuple[str, VplusData] | None:
        """(the file, its data sections) of the V+ file holding program ``name``; None when
        no V+ file of the workspace holds it."""
        found = self.vplus_source(name)
        if found is None:
            return None
        return str(found[1].resolve()), _vplus().read_vplus_file(found[1]).data

    def vplus_files(self) -> list[Path]:
        """NAME.V2 / NAME.PG files whose NAME is a workspace name, in name order; a file that
        links outside the workspace is left out (WorkspaceError when it is read by name)."""
        found = []
        for ext in VPLUS_KINDS:
            for stem in self._names(ext):
                try:
                    found.append(self.path(stem, ext))
                except WorkspaceError:
                    continue
        return sorted(found, key=lambda path: path.name.upper())

    def vplus_programs(self) -> dict[str, tuple[Program, Path]]:
        """Every program of the workspace's V+ files (the first file to define a name wins);
        a damaged file is left out (reading one of its programs by name says why)."""
        found: dict[str, tuple[Program, Path]] = {}
        for path in self.vplus_files():
            try:
                blocks = _vplus().read_vplus(path)
            except (ValtermError, OSError):
                continue
            for block in blocks:
                found.setdefault(block.program.name, (block.program, path))
        return found

    def _vplus_program(self, name: str) -> Program:
        found = self.vplus_programs().get(name)
        if found is not None:
            return found[0]
        for path in self.vplus_files():  # a damaged file may be the one meant: say why it is not read
            try:
                _vplus().read_vplus(path)
            except (ValtermError, OSError) as error:
                raise WorkspaceError(f"PROGRAM {name} IS NOT DEFINED; {path.name} CANNOT BE READ: {error}") from None
        raise WorkspaceError(f"PROGRAM {name} IS NOT DEFINED (NO .V2 OR .PG FILE OF THE WORKSPACE HAS IT)")

    def write_program(self, program: Program, name: str | None = None, expected: str | None = None) -> Path:
        """Save a program and list it in DATFILER.DAT (§5.1: a new program's name is added).

        With ``expected`` (its stamp when read) FileChanged, nothing written, if it changed since."""
        stem = self._program_name(name or program.name)
        path = self.path(stem, "DAT")
        programs.write_program(path, program, expected)
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
            raise WorkspaceError(f"{shown_name(name)!r} is not a valid name: {stem}.DAT is kept by the simulator")
        return stem

    # -- variables (CHECK.DAT) ---------------------------------------------------
    def read_variables(self) -> dict[str, float]:
        path = self.path("CHECK", "DAT")
        values = variables.read_variables(path) if path.exists() else {}
        self._variables_seen = dict(values)
        return values

    def write_variables(self, values: dict[str, float]) -> Path:
        """Keep ``values`` in CHECK.DAT, merged with what other sessions wrote (see merge_variables)."""
        self.merge_variables(values)
        return self.path("CHECK", "DAT")

    def merge_variables(self, values: dict[str, float]) -> dict[str, float]:
        """Write the variables of ``values`` this session set or changed since it last read or
        wrote CHECK.DAT, over the file as it is now, under the folder's lock: two sessions (two
        ``run`` at once) each keep their own variables and every other one. Returns the merged
        variables (what CHECK.DAT now holds)."""
        path = self.path("CHECK", "DAT")
        with folder_lock(self.root):
            merged = variables.read_variables(path) if path.exists() else {}
            seen = self._variables_seen
            changed = {name: value for name, value in values.items()
                       if name not in merged or seen.get(name) != value}
            merged.update(changed)
            variables.write_variables(path, merged)
        self._variables_seen = dict(merged)
        return merged
