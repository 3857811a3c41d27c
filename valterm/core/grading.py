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

import math
import time
import tomllib
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from valterm.core import resources
from valterm.core.errors import ValtermError
from valterm.core.events import Collision, Error, Event, Grasp, Json, LimitReached, Message, Near
from valterm.core.files.errors import FileFormatError
from valterm.core.files.locations import read_location_file, read_locations
from valterm.core.files.programs import Program
from valterm.core.files.setup import read_setup
from valterm.core.files.vplus import EXTENSIONS as VPLUS_EXTENSIONS
from valterm.core.files.vplus import read_program_file
from valterm.core.robot_choice import check_robot
from valterm.core.rules import check_rules, rules_of_dialect
from valterm.core.simulator import Simulator
from valterm.core.text.transcript import event_lines
from valterm.core.val.checker import check_program
from valterm.core.val.dialects import check_dialect
from valterm.core.val.dialects.val1985.builders import CLOSED_ON_AIR
from valterm.core.val.interpreter import Interpreter
from valterm.core.val.limits import RunLimits
from valterm.core.workspace import Workspace

PROGRAM_EXTENSIONS = (".DAT", *VPLUS_EXTENSIONS)

# The kinds of failure, in the order a verdict names its first one.
KINDS = ("file", "syntax", "error", "limit", "collision", "part", "cycle-time")

_TASK_KEYS = {"name", "cell", "locations", "program", "cycle_time", "collisions", "loops", "dialect", "rules",
              "robot", "part"}
_PART_KEYS = {"number", "position", "tolerance", "held"}
MAX_TASK_BYTES = 64 * 1024


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


@dataclass(frozen=True)
class Failure:
    kind: str  # one of KINDS
    message: str


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
                "parts": list(self.parts), "findings": list(self.findings)}


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
        cycle_time=None if "cycle_time" not in data else _number(data["cycle_time"], path, "cycle_time"),
        collisions=_flag(data.get("collisions", False), path, "collisions"),
        loops=int(_number(data.get("loops", 1), path, "loops")),
        dialect=_setting(data, "dialect", "1985", check_dialect, path),
        rules=_setting(data, "rules", "", check_rules, path),
        robot=_setting(data, "robot", "", check_robot, path),
        parts=tuple(_part(entry, path) for entry in _list(data.get("part", []), path, "part")),
    )


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
    held = entry.get("held")
    return ExpectedPart(number, (x, y, z), tolerance, None if held is None else _flag(held, path, f"{where} held"))


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


def _number(value: object, path: Path, key: str) -> float:
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


def check_task(task: Task) -> None:
    """The task's own files read and its parts in the cell (TaskError otherwise): before any
    student is graded, so a mistake in the task is not a failure of every student."""
    try:
        cell = read_setup(task.cell)
        for location_file in task.locations:
            read_locations(location_file)
    except (FileFormatError, OSError) as error:
        raise TaskError(task.cell, 0, f"the task's files cannot be read: {error}") from None
    for expected in task.parts:
        if expected.number > len(cell.objects):
            raise TaskError(task.cell, 0, f"the task names part {expected.number}; the cell has {len(cell.objects)}")


# -- one submission --------------------------------------------------------------------------

def main_program(submission: Path, task: Task) -> Path:
    """The program file of a submission: the file itself, or in a folder the task's program
    (else the folder's only program). FileFormatError when there is none to run."""
    if not submission.is_dir():
        return submission
    files = sorted(p for p in submission.iterdir() if p.suffix.upper() in PROGRAM_EXTENSIONS and p.is_file())
    if task.program:
        found = [p for p in files if p.stem.upper() == task.program]
        if found:
            return found[0]
        raise FileFormatError(submission, 0, f"no program {task.program}.DAT in the submission")
    if len(files) != 1:
        raise FileFormatError(submission, 0, f"{len(files)} program files: name the one to run "
                                             "(program = \"NAME\" in the task)")
    return files[0]


def grade(task: Task, submission: str | Path, limits: RunLimits | None = None) -> Verdict:
    """Run ``submission`` (a program file, or a folder with the program and what it CALLs)
    against ``task``; never raises for the student's mistakes: they are failures."""
    started = time.perf_counter()
    submission = Path(submission)
    verdict = Verdict(student=submission.stem if submission.is_file() else submission.name, program="")
    try:
        path = main_program(submission, task)
        verdict.program = path.name
        main, in_file = read_program_file(path)
    except (FileFormatError, OSError, ValtermError) as error:
        verdict.failures.append(Failure("file", str(error)))
        verdict.seconds = time.perf_counter() - started
        return verdict
    _syntax(verdict, main, task)
    if not verdict.failures:  # a program pass 1 refuses is not run
        _run(verdict, task, path, main, in_file, limits or RunLimits())
    verdict.seconds = time.perf_counter() - started
    return verdict


def _syntax(verdict: Verdict, main: Program, task: Task) -> None:
    """Pass 1 and the syntax check: every error a failure, located by program and step."""
    report = check_program(main, dialect="v+" if task.dialect == "v+" else None)
    for diagnostic in report.errors:
        verdict.failures.append(Failure("syntax", f"{main.name} STEP {diagnostic.step}: {diagnostic.message}"))


def _run(verdict: Verdict, task: Task, path: Path, main: Program, in_file: dict[str, Program],
         limits: RunLimits) -> None:
    sim = Simulator(read_setup(task.cell), robot=task.robot or None)  # check_task has read them once already
    precision: dict[str, tuple[float, ...]] = {}
    for location_file in task.locations:
        locations, points = read_location_file(location_file)
        sim.locations.update(locations)
        precision.update(points)  # V+ precision points (#NAME), as run reads them
    sim.collision_checks = True
    vplus = "v+" in (task.dialect, main.dialect)
    sim.set_rules(task.rules or rules_of_dialect("v+" if vplus else "1985"))  # as run does
    # the submission's folder is its workspace: CALLed programs come from there, nothing is written
    load_called = Workspace(path.parent).program_loader(path.parent)

    def load_program(name: str) -> Program:
        return in_file[name] if name in in_file else load_called(name)

    interpreter = Interpreter(sim, load_program, {}, dialect=task.dialect, limits=limits)
    interpreter.machine.precision.update(precision)
    _observe(verdict, task, interpreter.execute(main.name, task.loops))
    verdict.cycle_time = interpreter.cycle_seconds
    verdict.parts = part_positions(sim)
    _check_end(verdict, task, sim)


def _observe(verdict: Verdict, task: Task, events: Iterable[Event]) -> None:
    """The failures and findings of the run's events."""
    for event in events:
        if isinstance(event, Collision):
            verdict.collisions += 1
            if not task.collisions and not any(f.kind == "collision" for f in verdict.failures):
                verdict.failures.append(Failure("collision", event_lines(event)[0]))
        elif isinstance(event, Near):
            verdict.near_misses += 1
        elif isinstance(event, LimitReached):
            verdict.failures.append(Failure("limit", event_lines(event)[0].removeprefix("*** ")))
        elif isinstance(event, Error):
            verdict.failures.append(Failure("error", event_lines(event)[0].removeprefix("*** ")))
        elif isinstance(event, Grasp):
            verdict.findings.append(f"GRASPED PART {event.part}{event.located}")
            continue
        elif not (isinstance(event, Message) and event.level == "warning"):  # CLOSE on air, AUTOCONFIG
            continue
        verdict.findings.extend(event_lines(event))


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
            verdict.failures.append(Failure("part", f"PART {expected.number} IS AT {shown}: {off:.1f} MM FROM WHERE "
                                                    f"IT SHOULD BE (TOLERANCE {expected.tolerance:g} MM){why}"))
        elif expected.held is not None and held != expected.held:
            state = "HELD" if held else "NOT HELD"
            verdict.failures.append(Failure("part", f"PART {expected.number} IS {state} AT THE END"))
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

def junit_xml(task: Task, verdicts: list[Verdict]) -> str:
    """The verdicts as a JUnit XML report (what CI systems and LMS autograders read): one
    <testcase> a submission, a <failure> for each failure (its type the kind), the findings
    in <system-out>."""
    import xml.etree.ElementTree as ET

    failed = sum(1 for v in verdicts if not v.passed)
    total = f"{sum(v.seconds for v in verdicts):.3f}"
    counts = {"tests": str(len(verdicts)), "failures": str(failed), "errors": "0", "skipped": "0", "time": total}
    root = ET.Element("testsuites", {"name": "valterm grade", **counts})
    suite = ET.SubElement(root, "testsuite", {"name": task.name, **counts,
                                              "timestamp": time.strftime("%Y-%m-%dT%H:%M:%S")})
    for verdict in verdicts:
        case = ET.SubElement(suite, "testcase", {"classname": task.name, "name": verdict.student,
                                                 "file": verdict.program, "time": f"{verdict.seconds:.3f}"})
        for failure in verdict.failures:
            node = ET.SubElement(case, "failure", {"type": failure.kind, "message": failure.message})
            node.text = failure.message
        lines = [f"CYCLE TIME {verdict.cycle_time:.2f} S, {verdict.collisions} COLLISIONS, "
                 f"{verdict.near_misses} NEAR MISSES", *verdict.findings]
        ET.SubElement(case, "system-out").text = "\n".join(lines)
    ET.indent(root)
    return ET.tostring(root, encoding="unicode", xml_declaration=True) + "\n"


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
