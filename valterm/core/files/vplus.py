"""V+ program files (``.v2``, ``.pg``): several ``.PROGRAM name(args)`` ... ``.END`` blocks.

This is how Adept V+ (the successor of VAL-II) stores programs on disk:

    .PROGRAM pick.place(part, count)
    ; ABSTRACT: pick a part and place it
        AUTO i
        FOR i = 1 TO count
            CALL pick(part)
        END
    .END

Each block becomes one ``Program`` (its steps are the lines between the header and
``.END``), the name kept as written, dotted names included, upper-cased as VAL-II names
are. Its dialect is v+, unless the header's comment is ``; DIALECT 1985`` (how
``valterm export-program`` marks a workspace program in the thesis's language). Lines outside
blocks may only be blank or comments, or data sections up to their ``.END``, which the
controller's STORE writes and ``read_vplus_file`` reads (anywhere in the file):

    .LOCATIONS
    pick.1      465.00  -45.00  -245.00  0.00  180.00  0.00     ; X Y Z yaw pitch roll
    #safe       0.00  -90.00  90.00  0.00  0.00  0.00            ; a precision point: joints
    .END
    .REALS
    count       5
    .END
    .STRINGS
    $title      "SHIFT REPORT"
    .END

A location's angles are V+'s yaw, pitch, roll (``core/transform.py``); it is kept as the
simulator keeps every location (O A T), the same pose. A bad header's parameter list or a
bad data line is a problem of that program or line (``VplusProgram.problem``,
``VplusData.problems``), not of the whole file: the rest is still read and checked. Bytes
that are not UTF-8 (a comment in some 8-bit code page) are read as latin-1.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from valterm.core import numbers
from valterm.core.errors import ValtermError
from valterm.core.files._text import numbered_lines, read_text, split_fields
from valterm.core.files.errors import FileFormatError
from valterm.core.files.foreign import refuse_foreign
from valterm.core.files.programs import MAX_LINE, Program, ProgramLine, read_program, split_label
from valterm.core.kinematics import Location
from valterm.core.transform import convert_orientation

EXTENSIONS = (".V2", ".PG")
MAX_NAME = 15  # V+ program names: a letter, then letters, digits, '.' and '_'
_NAME = re.compile(r"[A-Z][A-Z0-9._]{0,14}")
_HEADER = re.compile(r"\.PROGRAM\s+([^\s(]+)\s*(?:\((.*)\))?\s*(;.*)?$", re.IGNORECASE)
DIALECT_1985 = re.compile(r"DIALECT\s+1985", re.IGNORECASE)  # the header comment of a 1985 program
_DATA_SECTIONS = (".LOCATIONS", ".REALS", ".STRINGS", ".PRECISIONPOINTS")


def is_dotted_name(name: str) -> bool:
    """A V+ program name with a dot (``pick.place``): no NAME.DAT can hold it, only a V+ file."""
    upper = name.strip().upper()
    return "." in upper.removesuffix(".DAT") and _NAME.fullmatch(upper) is not None


@dataclass
class VplusProgram:
    """One ``.PROGRAM`` block: the program, its parameter names, and the header's comment."""

    program: Program
    parameters: list[str] = field(default_factory=list)
    comment: str = ""
    problem: str = ""  # what is wrong with the header (a bad parameter list), located


def _header(text: str, where: Path, number: int) -> VplusProgram:
    match = _HEADER.match(text.strip())
    if match is None:
        raise FileFormatError(where, number, "expected .PROGRAM name(arguments)")
    name = match.group(1).upper()
    if not _NAME.fullmatch(name):
        raise FileFormatError(
            where, number, f"{name[:40]!r} is not a program name (a letter, then up to "
            f"{MAX_NAME - 1} letters, digits, '.' or '_')")
    parameters, problem = [], ""
    for parameter in (p.strip().upper() for p in (match.group(2) or "").split(",") if p.strip()):
        if re.fullmatch(r"[A-Z$][A-Z0-9._]*(\[\])?", parameter):
            parameters.append(parameter)
        elif not problem:  # the program is still read: its steps are checked, it cannot run
            problem = f"{where.name}:{number}: .PROGRAM {name}: {parameter[:40]!r} is not a parameter name"
    comment = (match.group(3) or "").lstrip(";").strip()
    # A program exported from the workspace says it is in the thesis's language.
    dialect = "1985" if DIALECT_1985.fullmatch(comment) else "v+"
    program = Program(name, parameters=parameters, dialect=dialect)
    return VplusProgram(program, parameters, comment, problem)


@dataclass
class VplusData:
    """A V+ file's data sections: locations (kept as O A T), precision points, reals, strings."""

    locations: dict[str, Location] = field(default_factory=dict)
    precision: dict[str, tuple[float, ...]] = field(default_factory=dict)
    reals: dict[str, float] = field(default_factory=dict)
    strings: dict[str, str] = field(default_factory=dict)
    problems: list[str] = field(default_factory=list)  # "FILE:LINE: reason", one a bad line


@dataclass
class VplusFile:
    blocks: list[VplusProgram]
    data: VplusData


_ITEM = re.compile(r"(?P<name>[$#]?[A-Z][A-Z0-9._]*(?:\[[-\d,\s]*\])?)\s*,?\s*(?P<rest>.*)$", re.IGNORECASE)


def _data_line(section: str, line: str, data: VplusData) -> None:
    """One line of a data section into ``data`` (ValueError saying why it is not one)."""
    text = line.strip()
    match = _ITEM.match(text if section == ".STRINGS" else text.upper())
    if match is None:
        raise ValueError(f"{section}: expected a name, then its value")
    name, rest = match.group("name").upper().replace(" ", ""), match.group("rest").strip()
    if section == ".STRINGS":
        if not (name.startswith("$") and len(rest) >= 2 and rest[0] == rest[-1] == '"'):
            raise ValueError(f'.STRINGS: expected $name "text", not {text[:40]!r}')
        data.strings[name] = rest[1:-1]
        return
    values = [numbers.parse_number(v) for v in split_fields(rest.split(";")[0])]
    if section == ".REALS":
        if len(values) != 1 or name.startswith(("$", "#")):
            raise ValueError(f".REALS: expected a name and one value, not {text[:40]!r}")
        data.reals[name] = values[0]
    elif name.startswith("#") or section == ".PRECISIONPOINTS":
        if not 1 <= len(values) <= 12:
            raise ValueError(f"{section}: precision point {name} needs its joint angles")
        data.precision[name if name.startswith("#") else "#" + name] = tuple((values + [0.0] * 6)[:6])
    else:
        if len(values) != 6:
            raise ValueError(f".LOCATIONS: {name} needs X Y Z yaw pitch roll (6 values, {len(values)} given)")
        x, y, z, yaw, pitch, roll = values
        data.locations[name] = Location((x, y, z), convert_orientation((yaw, pitch, roll), "YPR", "OAT"))


def parse_vplus(text: str, path: str | Path) -> list[VplusProgram]:
    """Every ``.PROGRAM`` block of a V+ file, in file order (FileFormatError, located)."""
    return parse_vplus_file(text, path).blocks


def parse_vplus_file(text: str, path: str | Path) -> VplusFile:
    """The ``.PROGRAM`` blocks of a V+ file in file order, and its data sections."""
    where = Path(path)
    refuse_foreign(text, where)  # a Kawasaki AS or VAL3 file: one message, not one a line
    found: list[VplusProgram] = []
    data = VplusData()
    current: VplusProgram | None = None
    skipping = False
    section = ""
    for number, line in numbered_lines(text):
        stripped = line.strip()
        upper = stripped.upper()
        if len(line) > MAX_LINE:
            raise FileFormatError(where, number, f"line is {len(line)} characters long (at most {MAX_LINE})")
        if upper.startswith(".END"):
            if current is None and not skipping:
                raise FileFormatError(where, number, ".END without .PROGRAM")
            if current is not None:
                found.append(current)
            current, skipping, section = None, False, ""
        elif upper.startswith(".PROGRAM"):
            if current is not None:
                raise FileFormatError(where, number, f".PROGRAM inside {current.program.name}: .END missing")
            current = _header(stripped, where, number)
        elif current is not None:
            _add_step(current, line, where, number)
        elif upper.startswith(_DATA_SECTIONS):
            skipping, section = True, upper.split()[0]
        elif upper.startswith(".") and not skipping:
            skipping = True  # another directive's section (V+ writes others): up to its .END
        elif stripped and not stripped.startswith(";") and section in _DATA_SECTIONS:
            try:
                _data_line(section, stripped, data)
            except (ValueError, ValtermError) as error:
                data.problems.append(f"{where.name}:{number}: {error}")
        elif stripped and not stripped.startswith(";") and not skipping:
            raise FileFormatError(where, number, "a statement outside .PROGRAM ... .END")
    if current is not None:
        raise FileFormatError(where, 0, f"program {current.program.name} has no .END")
    if not found:
        raise FileFormatError(where, 0, "no .PROGRAM block in the file")
    _refuse_duplicates(found, where)
    return VplusFile(found, data)


def _add_step(block: VplusProgram, line: str, where: Path, number: int) -> None:
    if not line.strip():
        return
    try:
        label, statement = split_label(line.expandtabs(4))
    except ValueError as error:
        raise FileFormatError(where, number, str(error)) from None
    block.program.steps.append(ProgramLine(label, statement, number))


def _refuse_duplicates(found: list[VplusProgram], where: Path) -> None:
    seen: set[str] = set()
    for block in found:
        name = block.program.name
        if name in seen:
            raise FileFormatError(where, block.program.steps[0].line if block.program.steps else 0,
                                  f"program {name} is defined twice")
        seen.add(name)


def read_vplus(path: str | Path) -> list[VplusProgram]:
    return read_vplus_file(path).blocks


# CALL name, and the program a reaction CALLs (REACT/REACTI signal, name)
_CALLED = re.compile(r"^\s*(?:CALL\s+|REACTI?\s+[^,]+,\s*)([A-Z][A-Z0-9._]*)", re.IGNORECASE)


def called_names(program: Program) -> set[str]:
    """The names of the programs ``program`` CALLs (or arms a reaction to), upper-cased."""
    found = (_CALLED.match(line.text) for line in program.steps)
    return {match.group(1).upper() for match in found if match}


def main_program(programs: list[Program], path: str | Path, chosen: str | None = None) -> Program:
    """The main program of a V+ file: ``chosen`` (``--program NAME``), else the one no other
    program of the file CALLs (all CALLed, a cycle: the first). FileFormatError when the file
    has no ``chosen``, or several programs no other CALLs (listed: choose one)."""
    names = [p.name for p in programs]
    if chosen is not None:
        for program in programs:
            if program.name == chosen.strip().upper():
                return program
        raise FileFormatError(path, 0, f"no program {chosen.strip().upper()} in the file (it holds "
                                       f"{', '.join(names)})")
    called = {name for p in programs for name in called_names(p) - {p.name}}
    candidates = [p for p in programs if p.name not in called]
    if len(candidates) > 1:
        raise FileFormatError(path, 0, f"{len(candidates)} programs that no other program CALLs: "
                                       f"{', '.join(p.name for p in candidates)}; choose the main one "
                                       "with --program NAME")
    return (candidates or programs)[0]


def read_program_file(path: str | Path, chosen: str | None = None) -> tuple[Program, dict[str, Program]]:
    """The main program of a program file and every program it holds, by name: a V+ file
    (``.v2``/``.pg``) holds several (the main one: ``main_program``); a ``.DAT`` file holds one."""
    if Path(path).suffix.upper() in EXTENSIONS:
        programs = [block.program for block in read_vplus(path)]
        return main_program(programs, path, chosen), {p.name: p for p in programs}
    main = read_program(path)
    return main, {main.name: main}


def read_vplus_file(path: str | Path) -> VplusFile:
    return parse_vplus_file(read_text(path, "V+ program", eight_bit=True), path)


def format_data(data: VplusData) -> list[str]:
    """The data sections as STORE writes them: locations in X Y Z yaw pitch roll."""
    out: list[str] = []
    if data.locations or data.precision:
        out.append(".LOCATIONS")
        for name, location in data.locations.items():
            angles = convert_orientation(location.oat, "OAT", "YPR")
            out.append(f"{name.lower():<15} " + " ".join(f"{v:10.3f}" for v in (*location.xyz, *angles)))
        for name, joints in data.precision.items():
            out.append(f"{name.lower():<15} " + " ".join(f"{v:10.3f}" for v in joints))
        out += [".END", ""]
    if data.reals:
        out.append(".REALS")
        out += [f"{name.lower():<15} {value:.9g}" for name, value in data.reals.items()]
        out += [".END", ""]
    if data.strings:
        out.append(".STRINGS")
        out += [f'{name.lower():<15} "{text}"' for name, text in data.strings.items()]
        out += [".END", ""]
    return out


def format_vplus(blocks: list[VplusProgram], data: VplusData | None = None) -> str:
    """The file text: each program as ``.PROGRAM name(args)``, its steps indented, ``.END``;
    then the data sections, if any."""
    out: list[str] = []
    for block in blocks:
        arguments = ", ".join(p.lower() for p in block.parameters)
        text = block.comment or ("DIALECT 1985" if block.program.dialect == "1985" else "")
        comment = f" ; {text}" if text else ""
        out.append(f".PROGRAM {block.program.name.lower()}({arguments}){comment}")
        for step in block.program.steps:
            label = f"{step.label} " if step.label is not None else ""
            out.append(f"    {label}{step.text}".rstrip() if step.text or label else "")
        out.append(".END")
        out.append("")
    if data is not None:
        out += format_data(data)
    return "\n".join(out)
