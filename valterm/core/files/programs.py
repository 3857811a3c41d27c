"""VAL-II program files, NAME.DAT (§5, App. C §2, Figs. 7-4, C-19, C-20).

One step a line. Columns 1-4 hold an optional numeric step label and the statement starts
in column 5 ("the first four spaces in any line are reserved for step labels"; a TAB goes
to column 5). Free form is accepted too: ``300 ENDIF`` (a label, spaces, the statement) and
``READY`` starting in column 1 (no label).

Decisions (the thesis's listings, Figs. 7-4, C-19, C-20, and §6.8.1):

* a comment line (``; PROGRAM : PROCESS``) is a step, as on the controller: the listings
  start with one and §6.8.1 calls it a "comment line" of the program; the step's text keeps
  the ``;`` so the interpreter can skip it;
* a ``;`` after a statement stays in the step's text (the VAL-II parser strips it);
* blank lines are not steps (the editor cannot make one; files edited elsewhere may have them);
* an empty file is damaged; an empty program is written as its ``; PROGRAM NAME`` line.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from valterm.core.files import limits
from valterm.core.files._text import numbered_lines, read_text
from valterm.core.files.atomic import write_text_atomic
from valterm.core.files.errors import FileFormatError, FileWriteError
from valterm.core.files.foreign import refuse_foreign
from valterm.core.files.limits import MAX_STEPS
from valterm.core.numbers import NumberError, parse_count

LABEL_COLUMNS = 4         # columns 1-4: the step label
MAX_LABEL = 65535         # VAL-II step labels are 0..65535
MAX_LINE = limits.MAX_LINE  # longer lines are not VAL-II program steps (the editor's limit too)

_FREE_LABEL = re.compile(r"\s*([0-9]+)(?:\s+(.*))?", re.ASCII)
_CONTROL = re.compile(r"[\x00-\x1f\x7f]")


@dataclass
class ProgramLine:
    """One step: its optional label, its statement text, and its line in the file (0: not from a file)."""

    label: int | None
    text: str
    line: int = 0


@dataclass
class Program:
    """A VAL-II program: its name (no extension) and its steps, numbered 1.. in order."""

    name: str
    steps: list[ProgramLine] = field(default_factory=list)
    # V+ (issue 14): the .PROGRAM header's parameter names, and the dialect the steps are in
    parameters: list[str] = field(default_factory=list)
    dialect: str = "1985"

    def step(self, number: int) -> ProgramLine:
        """Step by its 1-based step number."""
        if not 1 <= number <= len(self.steps):
            raise IndexError(f"{self.name} has no step {number} (it has {len(self.steps)})")
        return self.steps[number - 1]

    def find_label(self, label: int) -> int | None:
        """The step number (1-based) carrying ``label``, or None."""
        for number, step in enumerate(self.steps, start=1):
            if step.label == label:
                return number
        return None


def split_label(line: str) -> tuple[int | None, str]:
    """(label, statement) of one program line, tabs already expanded.

    Raises ValueError for a label above 65535.
    """
    label_text: str | None = None
    statement = line.strip()
    free = _FREE_LABEL.fullmatch(line.rstrip())
    head = line[:LABEL_COLUMNS]
    if free is not None:
        label_text, statement = free.group(1), (free.group(2) or "").strip()
    elif len(line) > LABEL_COLUMNS and head.strip().isascii() and head.strip().isdigit() and head == head.rstrip():
        # label filling column 4 with the statement glued on at column 5: "1234READY"
        label_text, statement = head.strip(), line[LABEL_COLUMNS:].strip()
    if label_text is None:
        return None, statement
    try:
        return parse_count(label_text, MAX_LABEL, "step label"), statement
    except NumberError:  # only digits reach here: the label is too large
        shown = label_text if len(label_text) <= 12 else label_text[:12] + "..."
        raise ValueError(f"step label {shown} is too large (labels are 0 to {MAX_LABEL})") from None


def read_program(path: str | Path) -> Program:
    """Read a program file (FileFormatError if malformed); the program's name is the file's stem."""
    path = Path(path)
    return parse_program(read_text(path, "program"), path.stem.upper(), path)


def parse_program(text: str, name: str, path: str | Path | None = None) -> Program:
    """Parse program text. ``path`` (default ``NAME.DAT``) locates errors."""
    where = Path(path) if path is not None else Path(f"{name.upper()}.DAT")
    if not text.strip():
        raise FileFormatError(where, 0, "the program file is empty")
    refuse_foreign(text, where)  # a Kawasaki AS or VAL3 file: one message, not one a line
    program = Program(name.upper())
    for number, line in numbered_lines(text):
        if not line.strip():
            continue
        if len(line) > MAX_LINE:
            raise FileFormatError(where, number, f"line is {len(line)} characters long (at most {MAX_LINE})")
        try:
            label, statement = split_label(line)
        except ValueError as error:
            raise FileFormatError(where, number, str(error)) from None
        if len(program.steps) >= MAX_STEPS:
            raise FileFormatError(where, number, f"more than {MAX_STEPS} steps in one program")
        program.steps.append(ProgramLine(label, statement, number))
    return program


def format_step(step: ProgramLine) -> str:
    """One step as a program-file line: label in columns 1-4, statement from column 5."""
    text = _CONTROL.sub(" ", step.text).strip()  # a step is one line, whatever was typed
    if step.label is None:
        return " " * LABEL_COLUMNS + text
    label = str(step.label)
    if not text:
        return label
    if len(label) < LABEL_COLUMNS:
        return label.ljust(LABEL_COLUMNS) + text
    return f"{label} {text}"  # a 4- or 5-digit label: free form, read back the same


def format_program(program: Program) -> str:
    """The program-file text (an empty program is written as its heading comment)."""
    steps = program.steps or [ProgramLine(None, f"; PROGRAM {program.name}")]
    return "\n".join(format_step(step) for step in steps) + "\n"


def write_program(path: str | Path, program: Program, expected: str | None = None) -> None:
    """Write the program atomically (FileWriteError for one of more than MAX_STEPS steps;
    FileChanged when ``expected``, the stamp it was read with, no longer matches the file)."""
    if len(program.steps) > MAX_STEPS:
        raise FileWriteError(path, f"{len(program.steps)} steps are too many for one program (at most {MAX_STEPS})")
    write_text_atomic(path, format_program(program), expected=expected)
