"""Grading students' programs against a task an instructor writes (``valterm grade``,
docs/GRADING.md).

A task file (TOML) names the cell, the location files, the final position of parts with a
tolerance, the cycle time allowed and whether collisions are allowed. ``grade`` runs one
program headless with the collision check on, as ``valterm run --collisions`` does, and
returns a ``Verdict``: passed or not, each failure with its kind and a located message, the
findings (collisions, near misses, grasps, a clamp closed on air) as transcript lines.

Each program runs on its own simulator, cell and variables, read fresh: nothing is read
from or written to a workspace (no CHECK.DAT), so submissions cannot disturb each other and
``valterm grade`` may run them in parallel processes.
"""

from __future__ import annotations

import contextlib
import copy
import math
import os
import time
import tomllib
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, TypeVar

from valterm.core import resources
from valterm.core.cell.workcell import WorkCell
from valterm.core.errors import ValtermError
from valterm.core.events import Collision, Contact, Error, Event, Grasp, Json, LimitReached, Message, Near, TypeOut
from valterm.core.files.errors import FileFormatError
from valterm.core.files.locations import read_location_file, read_locations
from valterm.core.files.programs import Program
from valterm.core.files.setup import read_setup
from valterm.core.files.vplus import EXTENSIONS as VPLUS_EXTENSIONS
from valterm.core.robot_choice import check_robot
from valterm.core.rules import check_rules, rules_of_dialect
from valterm.core.simulator import Simulator
from valterm.core.text.transcript import event_lines
from valterm.core.val.checker import check_program
from valterm.core.val.dialects import check_dialect
from valterm.core.val.dialects.val1985.builders import CLOSED_ON_AIR
from valterm.core.val.interpreter import Interpreter
from valterm.core.val.limits import RunLimits

PROGRAM_EXTENSIONS = (".DAT", *VPLUS_EXTENSIONS)

# The kinds of failure, in the order a verdict names its first one.
KINDS = ("file", "syntax", "error", "limit", "collision", "part", "cycle-time")

_TASK_KEYS = {"name", "cell", "locations", "program", "cycle_time", "collisions", "loops", "dialect", "rules",
              "robot", "part", "max_steps", "max_seconds", "max_lines", "allowed_contacts"}
# with a cycle time and no max_seconds, a run is cut at this many times the cycle time
CYCLES_ALLOWED = 10
_PART_KEYS = {"number", "position", "tolerance", "held"}
MAX_TASK_BYTES = 64 * 1024
MAX_OUTPUT = 200  # lines of a program's TYPEd output kept in its verdict
_N = TypeVar("_N", int, float)


class TaskError(FileFormatError):
    """A task file that cannot be used: ``PICK.TOML: part 1: position needs 3 numbers``."""


@dataclass(frozen=True)
class ExpectedPart:
    number: int
    position: tuple[float, float, float]
    tolerance: float = 5.0
    held: bool | None = None  # None: not checked


@dataclass(frozen=True)
class Task:
    name: str
    cell: Path
    locations: tuple[Path, ...] = ()
    program: str = ""  # the program to run in a submission folder ("" : its only program)
    cycle_time: float | None = None  # seconds of robot time at most
    collisions: bool = False  # allowed?
    loops: int = 1
    dialect: str = "1985"
    rules: str = ""  # the joint-state rules (docs/MOTION.md); "": the dialect's
    robot: str = ""  # the robot graded on (--robot's names, core/arms.py); "": the thesis's
    parts: tuple[ExpectedPart, ...] = ()
    max_steps: int | None = None  # the run limits (core/val/limits.py; 0: none); None: the default
    max_seconds: float | None = None
    max_lines: int | None = None
    # contacts the task intends, as written: parts by number or name, robot links by name
    allowed_contacts: tuple[tuple[str, str], ...] = ()
    file: Path = Path("TASK.toml")  # the task file (its errors name it)


@dataclass(frozen=True)
class Failure:
    kind: str  # one of KINDS
    message: str
    part: int = 0  # a "part" failure's part number


@dataclass
class Verdict:
    """One submission's result. ``findings``: the transcript lines of the collisions, near
    misses, grasps, messages and errors, each located by program and step."""

    student: str
    program: str
    failures: list[Failure] = field(default_factory=list)
    findings: list[str] = field(default_factory=list)
    collisions: int = 0
    near_misses: int = 0
    cycle_time: float = 0.0
    seconds: float = 0.0  # the wall-clock time grading took
    parts: tuple[dict[str, Json], ...] = ()
    output: list[str] = field(default_factory=list)  # what the program TYPEd (the first MAX_OUTPUT lines)

    @property
    def passed(self) -> bool:
        return not self.failures

    @property
    def first(self) -> Failure | None:
        """The failure the table shows: the earliest kind in KINDS."""
        return min(self.failures, key=lambda f: KINDS.index(f.kind), default=None)

    def to_json(self) -> dict[str, Json]:
        return {"student": self.student, "program": self.program, "passed": self.passed,
                "failures": [{"kind": f.kind, "message": f.message} for f in self.failures],
                "collisions": self.collisions, "near_misses": self.near_misses,
                "cycle_time_s": round(self.cycle_time, 3), "seconds": round(self.seconds, 3),
                "parts": list(self.parts), "findings": list(self.findings), "output": list(self.output)}


# -- the task file ---------------------------------------------------------------------------

def read_task(path: str | Path) -> Task:
    """The task file at ``path`` (TaskError naming the file and the key when it is wrong)."""
    from valterm.core.files._text import read_text

    path = Path(path)
    text = read_text(path, "task", MAX_TASK_BYTES)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise TaskError(path, 0, f"not a TOML file: {error}") from None
    except ValueError:  # Python's limit on reading a whole number (TOMLDecodeError is one too: caught above)
        raise TaskError(path, 0, "a number of more than 4300 digits: not a number a task needs") from None
    unknown = sorted(set(data) - _TASK_KEYS)
    if unknown:
        raise TaskError(path, 0, f"unknown key {unknown[0]!r} (the keys are {', '.join(sorted(_TASK_KEYS))})")
    if "cell" not in data:
        raise TaskError(path, 0, "no cell: name the setup file (cell = \"PROCESS\")")
    locations = data.get("locations", [])
    if isinstance(locations, str):
        locations = [locations]
    return Task(
        name=_text(data.get("name", path.stem.upper()), path, "name"),
        cell=_data_file(path, _text(data["cell"], path, "cell"), "SET"),
        locations=tuple(_data_file(path, _text(name, path, "locations"), "LOC")
                        for name in _list(locations, path, "locations")),
        program=_text(data.get("program", ""), path, "program").upper(),
        cycle_time=None if "cycle_time" not in data else _positive(data["cycle_time"], path, "cycle_time"),
        collisions=_flag(data.get("collisions", False), path, "collisions"),
        loops=_count(data.get("loops", 1), path, "loops"),
        dialect=_setting(data, "dialect", "1985", check_dialect, path),
        rules=_setting(data, "rules", "", check_rules, path),
        robot=_setting(data, "robot", "", check_robot, path),
        parts=_parts(_list(data.get("part", []), path, "part"), path),
        max_steps=_limit(data, "max_steps", path),
        max_seconds=None if "max_seconds" not in data else _at_least_0(data["max_seconds"], path, "max_seconds"),
        max_lines=_limit(data, "max_lines", path),
        allowed_contacts=_contacts(data.get("allowed_contacts", []), path),
        file=path,
    )


def run_limits(task: Task, steps: int | None = None, seconds: float | None = None,
               lines: int | None = None) -> RunLimits:
    """Each student's run limits: the command line's (the arguments), else the task's, else the
    defaults, where the robot time's is CYCLES_ALLOWED times the task's cycle time when it has one."""
    default = RunLimits()
    by_cycle = default.seconds if task.cycle_time is None else CYCLES_ALLOWED * task.cycle_time
    return RunLimits(_first(steps, task.max_steps, default.steps), _first(seconds, task.max_seconds, by_cycle),
                     _first(lines, task.max_lines, default.lines))


def _first(given: _N | None, tasks: _N | None, default: _N) -> _N:
    return given if given is not None else tasks if tasks is not None else default


def _limit(data: dict[str, object], key: str, path: Path) -> int | None:
    if key not in data:
        return None
    number = _number(data[key], path, key)
    if number < 0 or not number.is_integer():
        raise TaskError(path, 0, f"{key}: {number:g} must be a whole number, 0 (no limit) or more")
    return int(number)


def _at_least_0(value: object, path: Path, key: str) -> float:
    number = _number(value, path, key)
    if number < 0:
        raise TaskError(path, 0, f"{key}: {number:g} must be 0 (no limit) or more")
    return number


def _parts(entries: list[Any], path: Path) -> tuple[ExpectedPart, ...]:
    parts = tuple(_part(entry, path) for entry in entries)
    numbers = [part.number for part in parts]
    twice = next((n for n in numbers if numbers.count(n) > 1), None)
    if twice is not None:
        raise TaskError(path, 0, f"part {twice}: two [[part]] tables for one part (one says where it must end)")
    return parts


def _part(entry: object, path: Path) -> ExpectedPart:
    if not isinstance(entry, dict):
        raise TaskError(path, 0, "each [[part]] is a table (number, position, tolerance, held)")
    number = entry.get("number")
    where = f"part {number}" if isinstance(number, int) else "a [[part]]"
    unknown = sorted(set(entry) - _PART_KEYS)
    if unknown:
        raise TaskError(path, 0, f"{where}: unknown key {unknown[0]!r} (the keys are {', '.join(sorted(_PART_KEYS))})")
    if not isinstance(number, int) or isinstance(number, bool) or number < 1:
        raise TaskError(path, 0, f"{where}: number must be a part number, 1 or more")
    position = entry.get("position")
    if not isinstance(position, list) or len(position) != 3:
        raise TaskError(path, 0, f"{where}: position needs 3 numbers [x, y, z] in mm")
    x, y, z = (_number(v, path, f"{where} position") for v in position)
    tolerance = _number(entry.get("tolerance", 5.0), path, f"{where} tolerance")
    if tolerance < 0:
        raise TaskError(path, 0, f"{where} tolerance: {tolerance:g} must be 0 or more (mm)")
    held = entry.get("held")
    return ExpectedPart(number, (x, y, z), tolerance, None if held is None else _flag(held, path, f"{where} held"))


def _contacts(value: object, path: Path) -> tuple[tuple[str, str], ...]:
    """``allowed_contacts`` as written, each name upper case; checked against the cell and
    the robot by :func:`contact_pairs`."""
    pairs = []
    for pair in _list(value, path, "allowed_contacts"):
        if not isinstance(pair, list) or len(pair) != 2:
            raise TaskError(path, 0, "allowed_contacts: each pair is two names, a part (number or name) "
                                     "or a robot link: [\"1\", \"13\"], [\"CLAMP\", \"13\"]")
        first, second = (_party(word, path) for word in pair)
        if first == second:
            raise TaskError(path, 0, f"allowed_contacts: \"{first}\" with itself is no contact")
        pairs.append((first, second))
    return tuple(pairs)


def _party(word: object, path: Path) -> str:
    if isinstance(word, str) and word.strip():
        return " ".join(word.upper().split())
    if isinstance(word, int) and not isinstance(word, bool):
        return str(word)
    shown = str(word).lower() if isinstance(word, bool) else repr(word)
    raise TaskError(path, 0, f"allowed_contacts: {shown} is not a part number, a part's name nor a robot link")


def contact_pairs(task: Task, parts: list[str], links: Iterable[str]) -> frozenset[frozenset[str]]:
    """The task's allowed contacts as the collision events name their parties (a part by its
    number, "1"; a link by name), ``parts`` the cell's part names in order. A name stands for
    every part so named (the processor's two objects). TaskError for a name that is neither."""
    links = {link.upper() for link in links}
    allowed: set[frozenset[str]] = set()
    for pair in task.allowed_contacts:
        first, second = (_parties(word, parts, links, task.file) for word in pair)
        allowed.update(frozenset((a, b)) for a in first for b in second if a != b)
    return frozenset(allowed)


def _parties(word: str, parts: list[str], links: set[str], path: Path) -> set[str]:
    if word.isdigit() and 1 <= int(word) <= len(parts):
        return {str(int(word))}
    named = {str(number) for number, name in enumerate(parts, start=1) if name.upper() == word}
    if named:
        return named
    if word in links:
        return {word}
    names = sorted({name.upper() for n, name in enumerate(parts, start=1) if name.upper() != f"PART {n}"})
    known = f"1-{len(parts)}" + (f" or {', '.join(names)}" if names else "")
    raise TaskError(path, 0, f"allowed_contacts: \"{word}\" is not a part ({known}) nor a robot link "
                             f"({', '.join(sorted(links))})")


def part_names(cell: WorkCell) -> list[str]:
    """The cell's part names in order (the setup file's ``; NAME`` lines; "PART n" unnamed)."""
    return [part.name or f"PART {number}" for number, part in enumerate(cell.objects, start=1)]


def _setting(data: dict[str, object], key: str, default: str, check: Callable[[str], str], path: Path) -> str:
    """A task file's named setting (dialect, rules, robot) as its core check takes it; ""
    when an optional one (no default) is left out."""
    name = _text(data.get(key, default), path, key)
    if not name and not default:
        return ""
    try:
        return check(name)
    except ValtermError as error:
        raise TaskError(path, 0, f"{key}: {error}") from None


def _text(value: object, path: Path, key: str) -> str:
    if not isinstance(value, str):
        raise TaskError(path, 0, f"{key} must be a string")
    return value


def _list(value: object, path: Path, key: str) -> list[Any]:
    if not isinstance(value, list):
        raise TaskError(path, 0, f"{key} must be a list")
    return value


def _positive(value: object, path: Path, key: str) -> float:
    number = _number(value, path, key)
    if number <= 0:
        raise TaskError(path, 0, f"{key}: {number:g} must be more than 0")
    return number


def _count(value: object, path: Path, key: str) -> int:
    number = _number(value, path, key)
    if number < 1 or not number.is_integer():
        raise TaskError(path, 0, f"{key}: {number:g} must be a whole number, 1 or more")
    return int(number)


def _number(value: object, path: Path, key: str) -> float:
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) > 10**15:  # no float holds some
        digits = len(str(abs(value)))
        raise TaskError(path, 0, f"{key}: a {digits}-digit number is out of range (at most 1e+15 in size)")
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value < -1e15:
        raise TaskError(path, 0, f"{key} must be a finite number")
    if abs(value) > 1e15:
        raise TaskError(path, 0, f"{key}: {value} is out of range (at most 1e+15 in size)")
    return float(value)


def _flag(value: object, path: Path, key: str) -> bool:
    if not isinstance(value, bool):
        raise TaskError(path, 0, f"{key} must be true or false")
    return value


def _data_file(task: Path, name: str, ext: str) -> Path:
    """A setup or location file the task names: a path beside the task file (the extension
    may be left off), else one of the bundled cells and programs (``PROCESS``)."""
    given = Path(name)
    for candidate in (given, given.with_name(f"{given.name}.{ext}")):
        beside = candidate if candidate.is_absolute() else task.parent / candidate
        if beside.is_file():
            return beside
    folder = resources.CELLS if ext == "SET" else resources.PROGRAMS
    bundled = resources.data_path(folder, f"{name.upper()}.{ext}")
    if "/" not in name and "\\" not in name and bundled.is_file():
        return bundled
    raise TaskError(task, 0, f"{name}: no such {ext} file beside the task file, nor a bundled one")


_CELLS: dict[str, tuple[tuple[int, int], WorkCell]] = {}  # a process's setup files, by path
_WORKER = {"warm": False}


def task_cell(path: Path) -> WorkCell:
    """The setup file's cell, read once a process while the file is unchanged (its time and
    size); each caller gets a copy of its own, so students cannot disturb each other."""
    status = os.stat(path)
    stamp = (status.st_mtime_ns, status.st_size)
    key = os.path.abspath(path)
    found = _CELLS.get(key)
    if found is None or found[0] != stamp:
        found = (stamp, read_setup(path))
        _CELLS[key] = found
    return copy.deepcopy(found[1])


def forget_cells() -> None:
    """Read every setup file afresh next time (tests)."""
    _CELLS.clear()


_WARM_UP = ("DRIVE 1, -5, 50", "READY", "DRAW 0, 0, -10", "CLOSEI", "OPENI")


def warm_worker(task: Task) -> None:
    """A grading worker's start (``valterm grade --jobs``): the collision check loaded and
    the task's cell read before its first student, once a process."""
    from valterm.core.files.programs import parse_program

    # a joint and a straight move and a grasp, collision check on: the first-time costs (imports) of each
    warm = parse_program("".join(f"    {line}\n" for line in _WARM_UP), "WARM", task.file)
    with contextlib.suppress(ValtermError, OSError):  # check_task has said what is wrong with the task
        _run(Verdict("", ""), task, warm, {warm.name: warm}.__getitem__, run_limits(task))
    _WORKER["warm"] = True


def worker_ready(_: object = None) -> bool:
    """Whether this process has been warmed for grading."""
    return _WORKER["warm"]


def check_task(task: Task) -> None:
    """The task's own files read and its parts in the cell (TaskError otherwise): before any
    student is graded, so a mistake in the task is not a failure of every student."""
    try:
        cell = task_cell(task.cell)
        for location_file in task.locations:
            read_locations(location_file)
    except (FileFormatError, OSError) as error:
        raise TaskError(task.cell, 0, f"the task's files cannot be read: {error}") from None
    for expected in task.parts:
        if expected.number > len(cell.objects):
            raise TaskError(task.cell, 0, f"the task names part {expected.number}; the cell has {len(cell.objects)}")
    if task.allowed_contacts:
        contact_pairs(task, part_names(cell), Simulator(cell, robot=task.robot or None).model.names)


# -- a class of submissions -----------------------------------------------------------------

LINK = "is a link; a submission is read only inside itself, never through a link"
_MAX_DEPTH = 4  # classes within classes (a course, its sections, their students)


@dataclass(frozen=True)
class Submission:
    """One student: a program file, or a folder holding the student's programs."""

    student: str  # unique among the students graded together
    path: Path


def find_students(arguments: Iterable[str | Path]) -> list[Submission]:
    """The students in the paths named (docs/GRADING.md): a folder holding program files is
    one student; a folder holding folders is a class (each folder in it, and each program file
    beside them, a student); a folder holding neither is a student with nothing to run; a
    link is a student whose submission is refused. ``subs`` and ``subs/*`` find the same
    students: each is named by its path less the folder all of them share.
    FileFormatError for a path that is not there."""
    found: dict[str, Path] = {}
    for argument in arguments:
        path = Path(os.path.normpath(os.path.expanduser(str(argument))))
        if not os.path.lexists(path):
            raise FileFormatError(path, 0, "no such program file or folder")
        for student in _students_in(path, 0):
            found.setdefault(os.path.abspath(student), student)  # a student named twice is graded once
    names = _names(list(found))
    return [Submission(name, path) for name, path in zip(names, found.values(), strict=True)]


def _students_in(path: Path, depth: int) -> list[Path]:
    if path.is_symlink() or not path.is_dir():
        return [path] if path.is_symlink() or _is_program(path.name) else []  # a README is no student
    entries = _entries(path)
    if any(_is_program(e.name) and not e.is_dir(follow_symlinks=False) for e in entries) or depth >= _MAX_DEPTH:
        return [path]
    folders = [e for e in entries if e.is_dir(follow_symlinks=False) or e.is_symlink()]
    if not folders:
        return [path]  # nothing to run: a FAIL row, never dropped
    return [student for e in entries for student in _students_in(path / e.name, depth + 1)]


def _entries(folder: Path, strict: bool = False) -> list[os.DirEntry[str]]:
    """The folder's entries, hidden ones left out, in name order; an unreadable folder has
    none (a student then: its grading, ``strict``, says why)."""
    try:
        with os.scandir(folder) as listing:
            return sorted((e for e in listing if not e.name.startswith(".")), key=lambda e: e.name)
    except OSError as error:
        if strict:
            raise FileFormatError(folder, 0, f"cannot read the folder: {error.strerror or error}") from None
        return []


def _is_program(name: str) -> bool:
    return Path(name).suffix.upper() in PROGRAM_EXTENSIONS


def _names(paths: list[str]) -> list[str]:
    """Each student's path less the folder all of them share (the parent of a lone one), a
    program file's extension left off when that stays unique."""
    try:
        base = os.path.commonpath(paths) if paths else ""
    except ValueError:  # Windows: paths on two drives share nothing
        base = ""
    if base in paths:
        base = os.path.dirname(base)
    full = [Path(os.path.relpath(p, base) if base else p).as_posix() for p in paths]
    short = [name[: -len(Path(name).suffix)] if _is_program(name) else name for name in full]
    return [s if short.count(s) == 1 else f for s, f in zip(short, full, strict=True)]


# -- one submission --------------------------------------------------------------------------

class _Programs:
    """A submission's programs, read only as regular files inside it (never through a link,
    never a FIFO or a device): the file given, or every program file of the folder given."""

    def __init__(self, submission: Path) -> None:
        if submission.is_symlink():
            raise FileFormatError(submission, 0, LINK)
        self.folder = submission if submission.is_dir() else submission.parent
        self.files: dict[Path, Program] = {}  # each file's main program
        self.by_name: dict[str, Program] = {}  # every program, by name (a V+ file holds several)
        if submission.is_dir():
            for entry in _entries(submission, strict=True):
                if _is_program(entry.name) and not entry.is_dir(follow_symlinks=False):
                    self.read(submission / entry.name)
        else:
            self.read(submission)

    def read(self, path: Path) -> Program:
        from valterm.core.files._text import decode_text, read_bytes
        from valterm.core.files.programs import parse_program
        from valterm.core.files.vplus import parse_vplus_file

        try:
            data = read_bytes(path, "program", follow_links=False)
        except FileFormatError as error:
            if "symbolic link" in error.reason:
                raise FileFormatError(path, 0, LINK) from None
            raise
        if path.suffix.upper() in VPLUS_EXTENSIONS:
            text = decode_text(data, path, "V+ program", eight_bit=True)
            programs = [block.program for block in parse_vplus_file(text, path).blocks]
        else:
            programs = [parse_program(decode_text(data, path, "program"), path.stem.upper(), path)]
        self.files[path] = programs[0]
        for program in programs:
            self.by_name.setdefault(program.name, program)
        return programs[0]

    def load(self, name: str) -> Program:
        """A CALLed program: of the submission, else (a program file given alone) NAME.DAT beside it."""
        name = name.strip().upper()
        if name not in self.by_name:
            beside = [self.folder / e.name for e in _entries(self.folder) if e.name.upper() == f"{name}.DAT"]
            if not beside:
                raise FileFormatError(self.folder / f"{name}.DAT", 0, "no such program in the submission")
            self.read(beside[0])
        return self.by_name[name]

    def main(self, task: Task) -> Path:
        """The program file to run: the task's program, else the one no other program CALLs."""
        files = sorted(self.files, key=lambda p: p.name)
        if task.program:
            found = [p for p in files if p.stem.upper() == task.program]
            if not found:
                raise FileFormatError(self.folder, 0, f"no program {task.program}.DAT in the submission")
            return found[0]
        called = {name for program in self.by_name.values() for name in calls(program, task) if name != program.name}
        roots = [p for p in files if self.files[p].name not in called]
        if len(roots) == 1:
            return roots[0]
        if not files:
            raise FileFormatError(self.folder, 0, f"0 program files ({', '.join(PROGRAM_EXTENSIONS)}): nothing to run")
        if not roots:
            why = "every program is CALLed by another"
        else:
            why = f"{len(roots)} programs that no other CALLs ({', '.join(self.files[p].name for p in roots)})"
        raise FileFormatError(self.folder, 0, f"{why}: name the one to run (program = \"NAME\" in the task)")


def calls(program: Program, task: Task) -> set[str]:
    """The names of the programs ``program`` CALLs (the syntax checker's CALL test records them)."""
    called: set[str] = set()

    def record(name: str) -> bool:
        called.add(name.upper())
        return True  # no warning: only the names are wanted

    check_program(program, program_exists=record, dialect="v+" if task.dialect == "v+" else None)
    return called


def grade_student(task: Task, limits: RunLimits | None, submission: Submission) -> Verdict:
    """``grade`` for one of :func:`find_students`' students (what the parallel workers run)."""
    return grade(task, submission.path, limits, submission.student)


def grade(task: Task, submission: str | Path, limits: RunLimits | None = None, student: str = "") -> Verdict:
    """Run ``submission`` (a program file, or a folder with the program and what it CALLs)
    against ``task``; never raises for the student's mistakes: they are failures. Its files
    are read only as regular files inside it: a link or a FIFO is the student's failure."""
    started = time.perf_counter()
    submission = Path(submission)
    verdict = Verdict(student=student or (submission.name if submission.is_dir() else submission.stem), program="")
    try:
        programs = _Programs(submission)
        path = programs.main(task)
        verdict.program = path.name
        main = programs.files[path]
    except (FileFormatError, OSError, ValtermError) as error:
        verdict.failures.append(Failure("file", str(error)))
        verdict.seconds = time.perf_counter() - started
        return verdict
    _syntax(verdict, main, task)
    if not verdict.failures:  # a program pass 1 refuses is not run
        _run(verdict, task, main, programs.load, limits or run_limits(task))
    verdict.seconds = time.perf_counter() - started
    return verdict


def _syntax(verdict: Verdict, main: Program, task: Task) -> None:
    """Pass 1 and the syntax check: every error a failure, located by program and step."""
    report = check_program(main, dialect="v+" if task.dialect == "v+" else None)
    for diagnostic in report.errors:
        verdict.failures.append(Failure("syntax", f"{main.name} STEP {diagnostic.step}: {diagnostic.message}"))


def _run(verdict: Verdict, task: Task, main: Program, load: Callable[[str], Program], limits: RunLimits) -> None:
    sim = Simulator(task_cell(task.cell), robot=task.robot or None)  # read once a process: check_task's
    precision: dict[str, tuple[float, ...]] = {}
    for location_file in task.locations:
        locations, points = read_location_file(location_file)
        sim.locations.update(locations)
        precision.update(points)  # V+ precision points (#NAME), as run reads them
    sim.collision_checks = True
    vplus = "v+" in (task.dialect, main.dialect)
    sim.set_rules(task.rules or rules_of_dialect("v+" if vplus else "1985"))  # as run does
    # CALLed programs come from the submission, read as its main program was; nothing is written
    interpreter = Interpreter(sim, load, {}, dialect=task.dialect, limits=limits)
    interpreter.machine.precision.update(precision)
    names = part_names(sim.cell)
    contacts = _Contacts(names, contact_pairs(task, names, sim.model.names))
    _observe(verdict, task, interpreter.execute(main.name, task.loops), limits, contacts)
    verdict.cycle_time = interpreter.cycle_seconds
    verdict.parts = part_positions(sim)
    _check_end(verdict, task, sim)


@dataclass(frozen=True)
class _Contacts:
    """The cell's part names (for messages) and the contacts the task allows."""

    names: list[str]
    allowed: frozenset[frozenset[str]]

    def named(self, event: Contact) -> Contact:
        """The finding with each part's name after its number: ``1 COLLIDES WITH 8 (RIGHT-HAND TABLE)``."""
        a, b = self._name(event.a), self._name(event.b)
        if isinstance(event, Near):
            a, b = (f"PART {x}" if x[:1].isdigit() else x for x in (a, b))
            return replace(event, text=f"{a} IS NEAR {b}")
        return replace(event, text=f"{a} COLLIDES WITH {b}")

    def _name(self, party: str) -> str:
        if not party.isdigit() or not 1 <= int(party) <= len(self.names):
            return party
        name = self.names[int(party) - 1]
        return party if name.upper() == f"PART {party}" else f"{party} ({name.upper()})"

    def intended(self, event: Contact) -> bool:
        return frozenset((event.a, event.b)) in self.allowed


def _observe(verdict: Verdict, task: Task, events: Iterable[Event], limits: RunLimits,
             contacts: _Contacts) -> None:
    """The failures and findings of the run's events."""
    for event in events:
        if isinstance(event, Collision):
            verdict.collisions += 1
            event = contacts.named(event)
            first = not any(f.kind == "collision" for f in verdict.failures)
            if first and not (task.collisions or contacts.intended(event)):
                verdict.failures.append(Failure("collision", event_lines(event)[0]))
        elif isinstance(event, Near):
            verdict.near_misses += 1
            event = contacts.named(event)
        elif isinstance(event, LimitReached):
            verdict.failures.append(Failure("limit", _unfinished(event, limits)))
        elif isinstance(event, Error):
            verdict.failures.append(Failure("error", event_lines(event)[0].removeprefix("*** ")))
        elif isinstance(event, TypeOut):
            if len(verdict.output) < MAX_OUTPUT:
                verdict.output.append(event.text)
            continue
        elif isinstance(event, Grasp):
            verdict.findings.append(f"GRASPED PART {event.part}{event.located}")
            continue
        elif not (isinstance(event, Message) and event.level == "warning"):  # CLOSE on air, AUTOCONFIG
            continue
        verdict.findings.extend(event_lines(event))


def _unfinished(stop: LimitReached, limits: RunLimits) -> str:
    """A limit's stop as the student reads it (not the instructor's flag that raises it)."""
    value = float(getattr(limits, stop.limit))
    shown = f"{value:g}" if value < 1e15 else str(int(value))
    within = {"steps": f"WITHIN {shown} STEPS", "seconds": f"WITHIN {shown} S OF ROBOT TIME",
              "lines": f"WITHIN {shown} LINES OF TRANSCRIPT"}.get(stop.limit, stop.message)
    return f"{stop.program} STEP {stop.step}: DID NOT FINISH {within}: AN ENDLESS LOOP?"


def _check_end(verdict: Verdict, task: Task, sim: Simulator) -> None:
    """The parts where the task wants them, and the cycle time."""
    air = [line for line in verdict.findings if CLOSED_ON_AIR in line]
    for expected in task.parts:
        at = sim.cell.objects[expected.number - 1].reference
        off = math.dist(at, expected.position)
        held = sim.carried == expected.number
        if off > expected.tolerance:
            shown = ", ".join(f"{v:.1f}" for v in at)
            why = f" ({air[0]})" if air else ""
            target = ", ".join(f"{v:.1f}" for v in expected.position)
            verdict.failures.append(Failure("part", f"PART {expected.number} IS AT {shown}, NOT AT {target}: "
                                                    f"{off:.1f} MM AWAY (TOLERANCE {expected.tolerance:g} MM){why}",
                                            expected.number))
        elif expected.held is not None and held != expected.held:
            state = "HELD" if held else "NOT HELD"
            verdict.failures.append(Failure("part", f"PART {expected.number} IS {state} AT THE END", expected.number))
    if task.cycle_time is not None and verdict.cycle_time > task.cycle_time:
        verdict.failures.append(Failure("cycle-time", f"CYCLE TIME {verdict.cycle_time:.2f} S IS OVER "
                                                      f"THE {task.cycle_time:g} S ALLOWED"))


def part_positions(sim: Simulator) -> tuple[dict[str, Json], ...]:
    """Every part of the cell: its number, reference point (world mm, its first vertex as the
    setup file gives it) and whether the clamp holds it (``run --json``'s end event too)."""
    return tuple({"part": number, "position": [round(float(v), 3) for v in part.reference],
                  "held": sim.carried == number}
                 for number, part in enumerate(sim.cell.objects, start=1))


# -- reports ---------------------------------------------------------------------------------

MAX_RESULTS_BYTES = 256 * 1024 * 1024  # a class's JSON results (valterm grade --merge)


@dataclass(frozen=True)
class Results:
    """A ``valterm grade --json`` file read back (``--merge``)."""

    path: Path
    task: str
    robot: str
    verdicts: list[Verdict]
    seconds: float = 0.0  # how long the share took to grade


def read_results(path: str | Path) -> Results:
    """The results ``valterm grade --json`` wrote (FileFormatError naming the file and the
    result that is wrong)."""
    import json

    from valterm.core.files._text import read_text

    path = Path(path)
    text = read_text(path, "results", MAX_RESULTS_BYTES)
    try:
        data = json.loads(text)
    except ValueError as error:
        raise FileFormatError(path, 0, f"not a JSON file: {error}") from None
    except RecursionError:  # nested deeper than the parser goes: no results file is
        raise FileFormatError(path, 0, "not a JSON file: nested too deep") from None
    if not isinstance(data, dict) or not isinstance(data.get("task"), str) or not isinstance(data.get("results"), list):
        raise FileFormatError(path, 0, "not the JSON of valterm grade --json (task and results)")
    verdicts = [_verdict(entry, path, n) for n, entry in enumerate(data["results"], start=1)]
    robot, seconds = data.get("robot", "PUMA"), data.get("seconds", 0.0)
    return Results(path, data["task"], robot if isinstance(robot, str) else "PUMA", verdicts,
                   float(seconds) if isinstance(seconds, (int, float)) else 0.0)


def _verdict(entry: object, path: Path, n: int) -> Verdict:
    """One result of a JSON file as the Verdict it was written from."""
    if not isinstance(entry, dict):
        raise FileFormatError(path, 0, f"result {n}: not a result (student, program, failures ...)")

    def need(key: str, kind: type | tuple[type, ...], default: object = None) -> Any:
        value = entry.get(key, default)
        if not isinstance(value, kind) or isinstance(value, bool):
            what = {str: "a string", list: "a list"}.get(kind, "a number")  # type: ignore[call-overload]
            raise FileFormatError(path, 0, f"result {n}: {key} must be {what}")
        return value

    student, program = need("student", str), need("program", str)
    failures = []
    for failure in need("failures", list):
        if not (isinstance(failure, dict) and isinstance(failure.get("kind"), str)
                and isinstance(failure.get("message"), str)):
            raise FileFormatError(path, 0, f"result {n}: each failure has a kind and a message")
        failures.append(Failure(failure["kind"], failure["message"]))
    findings, output = need("findings", list), need("output", list, [])  # output: since --gradescope
    if not all(isinstance(line, str) for line in findings + output):
        raise FileFormatError(path, 0, f"result {n}: findings and output are lines of text")
    number = (int, float)
    return Verdict(student, program, failures, findings, int(need("collisions", number)),
                   int(need("near_misses", number)), float(need("cycle_time_s", number)),
                   float(need("seconds", number)), tuple(need("parts", list)), output)


def merge_results(files: list[Results]) -> list[Verdict]:
    """The verdicts of several shares of one class, in file order (FileFormatError when they
    are of two tasks, or a student is in two of them)."""
    seen: dict[str, Path] = {}
    verdicts: list[Verdict] = []
    for results in files:
        first = files[0]
        if results.task != first.task:
            raise FileFormatError(results.path, 0, f"task {results.task}, not {first.task} as in {first.path.name}: "
                                                   "the results of one task are merged")
        for verdict in results.verdicts:
            if verdict.student in seen:
                raise FileFormatError(results.path, 0, f"student {verdict.student} is in {seen[verdict.student].name} "
                                                       "too: each student is graded once (grade each share's students "
                                                       "by their paths from one class folder, so names stay unique)")
            seen[verdict.student] = results.path
            verdicts.append(verdict)
    return verdicts

def junit_xml(name: str, verdicts: list[Verdict]) -> str:
    """The verdicts as a JUnit XML report (what CI systems and LMS autograders read): one
    <testcase> a submission, a <failure> for each failure (its type the kind), the findings
    in <system-out>."""
    import xml.etree.ElementTree as ET

    failed = sum(1 for v in verdicts if not v.passed)
    total = f"{sum(v.seconds for v in verdicts):.3f}"
    counts = {"tests": str(len(verdicts)), "failures": str(failed), "errors": "0", "skipped": "0", "time": total}
    root = ET.Element("testsuites", {"name": "valterm grade", **counts})
    suite = ET.SubElement(root, "testsuite", {"name": name, **counts,
                                              "timestamp": time.strftime("%Y-%m-%dT%H:%M:%S")})
    for verdict in verdicts:
        case = ET.SubElement(suite, "testcase", {"classname": name, "name": verdict.student,
                                                 "file": verdict.program, "time": f"{verdict.seconds:.3f}"})
        for failure in verdict.failures:
            node = ET.SubElement(case, "failure", {"type": failure.kind, "message": failure.message})
            node.text = failure.message
        lines = [f"CYCLE TIME {verdict.cycle_time:.2f} S, {verdict.collisions} COLLISIONS, "
                 f"{verdict.near_misses} NEAR MISSES", *verdict.findings]
        ET.SubElement(case, "system-out").text = "\n".join(lines)
    ET.indent(root)
    return ET.tostring(root, encoding="unicode", xml_declaration=True) + "\n"


def gradescope_results(task: Task, verdict: Verdict) -> dict[str, Json]:
    """One submission's results.json for Gradescope's autograder (its documented fields:
    https://gradescope-autograders.readthedocs.io/en/latest/specs/#output-format): a test a
    check of the task, 1 point each, with the failures' messages; the student's findings and
    TYPEd output in ``output``."""
    tests: list[Json] = []
    for name, failed, blocked in _checks(task, verdict):
        passed = not failed and not blocked
        output = blocked or "\n".join(f.message for f in failed) or "PASSED"
        tests.append({"name": name, "score": 1.0 if passed else 0.0, "max_score": 1.0,
                      "status": "passed" if passed else "failed", "output": output})
    score = sum(1.0 for test in tests if isinstance(test, dict) and test["status"] == "passed")
    lines = [f"{verdict.student}: {'PASS' if verdict.passed else 'FAIL'}, {score:g} OF {len(tests)} CHECKS PASSED",
             f"CYCLE TIME {verdict.cycle_time:.2f} S, {verdict.collisions} COLLISIONS, "
             f"{verdict.near_misses} NEAR MISSES",
             *verdict.findings]
    if verdict.output:
        lines += ["", "THE PROGRAM TYPED:", *verdict.output]
    return {"score": score, "execution_time": round(verdict.seconds, 3), "output": "\n".join(lines),
            "output_format": "text", "tests": tests}


def _checks(task: Task, verdict: Verdict) -> list[tuple[str, list[Failure], str]]:
    """Each check of ``task``: its name, the verdict's failures of it, and why it was not
    made ("" when it was)."""
    kinds = {f.kind for f in verdict.failures}
    unread = "NOT RUN: THE SUBMISSION CANNOT BE READ" if "file" in kinds else ""
    unrun = unread or ("NOT RUN: THE PROGRAM HAS SYNTAX ERRORS" if "syntax" in kinds else "")

    def of(kind: str, part: int = 0) -> list[Failure]:
        return [f for f in verdict.failures if f.kind == kind and f.part == part]

    checks = [("PROGRAM READ", of("file"), ""), ("SYNTAX", of("syntax"), unread),
              ("RUNS WITHOUT AN ERROR", of("error"), unrun), ("FINISHES WITHIN THE LIMITS", of("limit"), unrun)]
    if not task.collisions:
        checks.append(("NO COLLISION", of("collision"), unrun))
    for part in task.parts:
        held = "" if part.held is None else ", HELD" if part.held else ", NOT HELD"
        at = ", ".join(f"{v:.1f}" for v in part.position)
        checks.append((f"PART {part.number} AT {at} (TOLERANCE {part.tolerance:g} MM){held}",
                       of("part", part.number), unrun))
    if task.cycle_time is not None:
        checks.append((f"CYCLE TIME AT MOST {task.cycle_time:g} S", of("cycle-time"), unrun))
    return checks


def table_lines(verdicts: list[Verdict]) -> list[str]:
    """The terminal's table: one row a submission, its first failure named."""
    rows = [("STUDENT", "RESULT", "FAILURE", "CYCLE S", "TIME S", "WHAT")]
    for v in verdicts:
        first = v.first
        rows.append((v.student, "PASS" if v.passed else "FAIL", first.kind if first else "",
                     f"{v.cycle_time:.2f}", f"{v.seconds:.2f}", first.message if first else ""))
    widths = [max(len(row[i]) for row in rows) for i in range(5)]
    return [("  ".join(cell.ljust(width) for cell, width in zip(row[:5], widths, strict=True)) + "  " + row[5]).rstrip()
            for row in rows]
