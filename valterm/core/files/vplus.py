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
blocks may only be blank or comments; other dot-directives in the file
(``.LOCATIONS``, ``.REALS``, ``.STRINGS`` data sections) are skipped up to their ``.END``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from valterm.core.files._text import numbered_lines, read_text
from valterm.core.files.errors import FileFormatError
from valterm.core.files.programs import MAX_LINE, Program, ProgramLine, read_program, split_label

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


def _header(text: str, where: Path, number: int) -> VplusProgram:
    match = _HEADER.match(text.strip())
    if match is None:
        raise FileFormatError(where, number, "expected .PROGRAM name(arguments)")
    name = match.group(1).upper()
    if not _NAME.fullmatch(name):
        raise FileFormatError(
            where, number, f"{name[:40]!r} is not a program name (a letter, then up to "
            f"{MAX_NAME - 1} letters, digits, '.' or '_')")
    parameters = [p.strip().upper() for p in (match.group(2) or "").split(",") if p.strip()]
    for parameter in parameters:
        if not re.fullmatch(r"[A-Z$][A-Z0-9._]*(\[\])?", parameter):
            raise FileFormatError(where, number, f"{parameter[:40]!r} is not a parameter name")
    comment = (match.group(3) or "").lstrip(";").strip()
    # A program exported from the workspace says it is in the thesis's language.
    dialect = "1985" if DIALECT_1985.fullmatch(comment) else "v+"
    program = Program(name, parameters=parameters, dialect=dialect)
    return VplusProgram(program, parameters, comment)


def parse_vplus(text: str, path: str | Path) -> list[VplusProgram]:
    """Every ``.PROGRAM`` block of a V+ file, in file order (FileFormatError, located)."""
    where = Path(path)
    found: list[VplusProgram] = []
    current: VplusProgram | None = None
    skipping = False
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
            current, skipping = None, False
        elif upper.startswith(".PROGRAM"):
            if current is not None:
                raise FileFormatError(where, number, f".PROGRAM inside {current.program.name}: .END missing")
            current = _header(stripped, where, number)
        elif current is not None:
            _add_step(current, line, where, number)
        elif upper.startswith(_DATA_SECTIONS):
            skipping = True
        elif stripped and not stripped.startswith(";") and not skipping:
            raise FileFormatError(where, number, "a statement outside .PROGRAM ... .END")
    if current is not None:
        raise FileFormatError(where, 0, f"program {current.program.name} has no .END")
    if not found:
        raise FileFormatError(where, 0, "no .PROGRAM block in the file")
    _refuse_duplicates(found, where)
    return found


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
    return parse_vplus(read_text(path, "V+ program"), path)


def read_program_file(path: str | Path) -> tuple[Program, dict[str, Program]]:
    """The main program of a program file and every program it holds, by name: a V+ file
    (``.v2``/``.pg``) holds several, the first is the main one; a ``.DAT`` file holds one."""
    if Path(path).suffix.upper() in EXTENSIONS:
        programs = [block.program for block in read_vplus(path)]
        return programs[0], {p.name: p for p in programs}
    main = read_program(path)
    return main, {main.name: main}


def format_vplus(blocks: list[VplusProgram]) -> str:
    """The file text: each program as ``.PROGRAM name(args)``, its steps indented, ``.END``."""
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
    return "\n".join(out)
