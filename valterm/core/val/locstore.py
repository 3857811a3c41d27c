"""Monitor commands about the robot's state that outlive a session: STOREL, LOAD and RULES.

``STOREL NAME`` writes every location variable (with the configuration and joint angles a
taught one keeps) and every precision point to NAME.LOC in the workspace (SPEC §3a, §5), in
the thesis's number format, and never a file the reader would refuse. It never silently
replaces a file: a NAME.LOC this session did not write is refused with a message, and
``STOREL NAME`` typed again replaces it; a file another session stored since this one last
saw it is refused the same way (the editor's changed-on-disk check, ``files/atomic.py``).
Storing no locations over a file is always refused.
``LOAD NAME`` (VAL-II's monitor command) reads NAME.LOC's locations and checks NAME.DAT's
program (``LOAD NAME.LOC`` or ``LOAD NAME.DAT`` reads only that one).
``RULES`` shows or sets the joint-state rules (``RULES 1985``, ``RULES CONTROLLER``).
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Protocol

from valterm.core.errors import ValtermError
from valterm.core.events import Error, Event, Message, Status
from valterm.core.files.atomic import file_stamp, text_stamp, write_text_atomic
from valterm.core.files.commandfile import CommandTable
from valterm.core.files.errors import FileChanged
from valterm.core.files.locations import FileState, checked_location_text, file_state, read_location_file
from valterm.core.files.programs import Program
from valterm.core.kinematics import Location
from valterm.core.val.machine import Machine
from valterm.core.val.parser import Statement
from valterm.core.val.protocol import Simulator

SHOWN_NAMES = 12  # LOAD names this many locations it read, then "..."


class Workspace(Protocol):
    """What STOREL and LOAD need of the workspace (valterm.core.workspace.Workspace)."""

    def path(self, name: str, ext: str) -> Path: ...


class StoreRefused(ValtermError):
    """STOREL wrote nothing; the message says why and how to store anyway."""


class LocationFiles:
    """The workspace's .LOC files as this session's STOREL knows them.

    ``at_start``: the .LOC files as the session began; ``written``: the stamp of each file
    this session stored (a later STOREL replaces it when it is still so); ``refused``: the
    stamp of each file a STOREL was refused over (STOREL of the same name again replaces it,
    when nobody changed it since the refusal)."""

    def __init__(self, workspace: Workspace, at_start: dict[str, FileState] | None = None) -> None:
        self.workspace = workspace
        # the .LOC files when the session began (location_files_now): one changed since that
        # this session did not store was stored by another session, and STOREL says so
        self.at_start = at_start
        self.written: dict[str, str] = {}
        self.refused: dict[str, str] = {}

    def store(self, name: str, locations: dict[str, Location], precision: dict[str, tuple[float, ...]]) -> Path:
        """Write NAME.LOC, or StoreRefused / FileWriteError (nothing written) saying why not."""
        path = self.workspace.path(name, "LOC")  # a name that is no file name: WorkspaceError
        key, again = path.name.upper(), f"STOREL {path.stem.upper()} AGAIN REPLACES IT"
        now = file_stamp(path)
        if not locations and not precision:
            if now:
                raise StoreRefused(f"NO LOCATIONS ARE DEFINED: {path.name} ({_held(path)}) IS KEPT AS IT IS")
            raise StoreRefused("NO LOCATIONS ARE DEFINED: NOTHING TO STORE")
        text = checked_location_text(path, locations, precision)  # more than the reader takes: refused
        expected = self.written.get(key, self.refused.pop(key, None))
        if expected is None and now:
            self.refused[key] = now
            if self.at_start is not None and file_state(path) != self.at_start.get(key):
                # made or changed since this session began, and not by it: another session stored it
                raise StoreRefused(_changed(path.name, "BEGAN", again))
            raise StoreRefused(f"{path.name} ({_held(path)}) WAS NOT STORED BY THIS SESSION: NOTHING WRITTEN. "
                               f"{again}; STOREL <ANOTHER NAME> KEEPS IT")
        try:
            write_text_atomic(path, text, expected=expected or "")
        except FileChanged:
            self.written.pop(key, None)
            self.refused[key] = file_stamp(path)
            raise StoreRefused(_changed(path.name, "LAST SAW IT", again)) from None
        self.written[key] = text_stamp(text)
        return path


def _changed(file: str, since: str, again: str) -> str:
    return (f"{file} CHANGED ON DISK SINCE THIS SESSION {since} (ANOTHER SESSION STORED IT): NOTHING WRITTEN. "
            f"{again}; STOREL <ANOTHER NAME> KEEPS BOTH")



def _held(path: Path) -> str:
    """What a location file holds, as a refusal names it."""
    try:
        locations, points = read_location_file(path)
    except ValtermError:
        return "A FILE THE SIMULATOR CANNOT READ"
    return _count(len(locations) + len(points))


def _count(count: int) -> str:
    return f"{count} LOCATION{'S' if count != 1 else ''}"


class Interpreter(Protocol):
    """What these commands read of the interpreter (no import of it: no circle)."""

    sim: Simulator
    machine: Machine
    location_files: LocationFiles | None
    commands: CommandTable

    def status(self) -> Status: ...
    def load_program(self, name: str) -> Program: ...


def storel(interpreter: Interpreter, st: Statement) -> Iterator[Event]:
    """STOREL NAME: the locations to NAME.LOC (through the workspace's one safe write path)."""
    name = (st.args[0] or "").strip() if st.args else ""
    if not name:
        yield Error("", 0, "STOREL NEEDS A FILE NAME: STOREL NAME WRITES NAME.LOC")
        return
    files = interpreter.location_files
    if files is None:
        yield Error("", 0, "STOREL: THERE IS NO WORKSPACE TO WRITE TO")
        return
    sim = interpreter.sim
    locations = dict(sim.locations)
    precision = dict(interpreter.machine.precision)
    try:
        path = files.store(name.upper().removesuffix(".LOC"), locations, precision)
    except (OSError, ValtermError) as error:
        yield Error("", 0, f"STOREL: {error}")
        return
    sim.mark_locations_stored(locations)
    yield Message(f"{_count(len(locations) + len(precision))} STORED IN {path.name}")


def load(interpreter: Interpreter, st: Statement) -> Iterator[Event]:
    """LOAD NAME: NAME.LOC's locations into the session, NAME.DAT's program read and checked."""
    name = (st.args[0] or "").strip().upper() if st.args else ""
    files = interpreter.location_files
    stem, _, ext = name.partition(".")
    if not stem or ext not in ("", "LOC", "DAT"):
        yield Error("", 0, "LOAD NAME READS NAME.LOC (LOCATIONS) AND NAME.DAT (A PROGRAM); "
                           "LOAD NAME.LOC OR LOAD NAME.DAT READS ONE OF THEM")
        return
    if files is None:
        yield Error("", 0, "LOAD: THERE IS NO WORKSPACE TO READ FROM")
        return
    try:
        found = [kind for kind in ("LOC", "DAT") if ext in ("", kind) and files.workspace.path(stem, kind).is_file()]
    except ValtermError as error:  # not a file name
        yield Error("", 0, f"LOAD: {error}")
        return
    if not found:
        wanted = " OR ".join(f"{stem}.{kind}" for kind in ("LOC", "DAT") if ext in ("", kind))
        yield Error("", 0, f"LOAD: THERE IS NO {wanted} IN THE WORKSPACE (LISTL AND LISTF LIST THEM)")
        return
    if "LOC" in found:
        yield from _load_locations(interpreter, files.workspace.path(stem, "LOC"))
    if "DAT" in found:
        yield from _load_program(interpreter, stem)


def _load_locations(interpreter: Interpreter, path: Path) -> Iterator[Event]:
    """The locations (and precision points) of a .LOC file, as --loc reads them."""
    try:
        locations, points = read_location_file(path)
    except (OSError, ValtermError) as error:
        yield Error("", 0, f"LOAD: {error}")
        return
    sim = interpreter.sim
    sim.locations.update(locations)
    interpreter.machine.precision.update(points)
    sim.mark_locations_stored(locations)
    names = [*locations, *points]
    shown = ", ".join(names[:SHOWN_NAMES]) + (", ..." if len(names) > SHOWN_NAMES else "")
    yield Message(f"{_count(len(names))} READ FROM {path.name}" + (f": {shown}" if names else ""))


def _load_program(interpreter: Interpreter, name: str) -> Iterator[Event]:
    """The program NAME.DAT read and checked as EXECUTE will read it (each EXECUTE reads it again)."""
    from valterm.core.val.checker import check_program

    try:
        program = interpreter.load_program(name)
    except (OSError, ValtermError) as error:
        yield Error("", 0, f"LOAD: {error}")
        return
    report = check_program(program, interpreter.commands)
    for problem in report.errors:
        yield Error(problem.program, problem.step, problem.message)
    ready = "LISTP OR EDIT SHOWS THE STEPS TO MEND" if report.errors else f"EXECUTE {name} RUNS IT"
    yield Message(f"PROGRAM {name}.DAT READ: {len(program.steps)} STEPS, "
                  f"{len(report.errors)} ERROR{'S' if len(report.errors) != 1 else ''}; {ready}")


def rules(interpreter: Interpreter, st: Statement) -> Iterator[Event]:
    """RULES: which joint-state rules are in force; RULES 1985 / RULES CONTROLLER sets them."""
    word = (st.args[0] or "").strip() if st.args else ""
    sim = interpreter.sim
    if word:
        try:
            sim.set_rules(word)
        except ValtermError as error:
            yield Error("", 0, str(error).upper())
            return
    yield interpreter.status()
