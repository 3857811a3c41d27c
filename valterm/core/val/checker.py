"""The syntax checker: every bad step of a program with its program, step and reason
(`CONV1 step 7: ...`), the structure errors pass 1 finds (IF without END, UNTIL without
DO, ...), and warnings for GOTOs to missing labels and CALLs to missing programs.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field

from valterm.core.files.commandfile import CommandTable, default_commands
from valterm.core.files.programs import Program, split_label
from valterm.core.val import dialects
from valterm.core.val.compiler import Diagnosed, Diagnostic, analyse
from valterm.core.val.parser import ValSyntaxError, parse_statement


@dataclass
class CheckReport(Diagnosed):
    program: str
    steps: int
    diagnostics: list[Diagnostic] = field(default_factory=list)
    dialect: str = "1985"  # the language the program was checked against


    @property
    def ok(self) -> bool:
        return not self.diagnostics

    def summary(self) -> str:
        if self.ok:
            return f"{self.program}: {self.steps} steps, no errors"
        return (f"{self.program}: {self.steps} steps, {len(self.errors)} error(s), "
                f"{len(self.warnings)} warning(s)")

    @property
    def against(self) -> str:
        """Which language the program was checked against: `DIALECT 1985 (COMMAND.DAT)`."""
        return f"DIALECT {dialects.dialect(self.dialect).title}"


def check_program(program: Program, table: CommandTable | None = None,
                  program_exists: Callable[[str], bool] | None = None,
                  dialect: str | None = None) -> CheckReport:
    """Check a whole program.  `program_exists(name)` lets CALLs to missing programs be warned about.

    ``dialect`` ("1985" or "v+") overrides the program's own (a V+ file's programs are v+).
    """
    dialect = dialect or program.dialect
    language = dialects.dialect(dialect)  # loads that dialect's package (the start loads none)
    analysis = analyse(program, table or default_commands(), language.grammar)
    diagnostics = list(analysis.diagnostics)
    if program_exists is not None:
        for index, called in analysis.calls:
            if called != program.name and not program_exists(called):
                step = program.steps[index]
                where = language.missing_program.format(name=called)
                diagnostics.append(Diagnostic(program.name, index + 1,
                                              f"CALL {called}: there is no program {where}",
                                              "warning", step.line))
        diagnostics.sort(key=lambda d: (d.step, not d.is_error))
    return CheckReport(program.name, len(program.steps), diagnostics, dialect)


def check_statement(text: str, table: CommandTable | None = None) -> str | None:
    """One program step as typed in the editor (label columns allowed): None if good, else why."""
    try:
        _label, statement = split_label(text.expandtabs())
        parsed = parse_statement(statement, table or default_commands())
    except (ValSyntaxError, ValueError) as error:
        return str(error)
    if parsed.spec is not None and not parsed.spec.in_program:
        return f"{parsed.command} is a monitor command: type it at the VAL-II prompt, not in a program"
    return None


# a command word, then one letter standing alone: "CLOSE I 50"
_SPLIT_WORD = re.compile(r"([A-Za-z]+) +([A-Za-z])(?= |$)")


def read_as_1985(typed: str, table: CommandTable | None = None) -> str | None:
    """The reading the 1985 program gave a step this checker rejects as typed: a command word
    split by a blank (``CLOSE I 50``, Table C-1) closed up into the COMMAND.DAT command it
    spells (``CLOSEI 50``). The thesis's session shows the program took the step (``D,3``
    deletes it); its source is lost, so this is the one reading the tables need, no wider
    (a blank-blind command matcher, as a FORTRAN keyword reader is). None: no such reading."""
    table = table or default_commands()
    expanded = typed.expandtabs()
    try:
        _label, statement = split_label(expanded)
    except ValueError:
        return None
    found = _SPLIT_WORD.match(statement)
    if found is None or check_statement(expanded, table) is None:
        return None
    joined = (found.group(1) + found.group(2)).upper()
    if joined not in table:
        return None
    start = expanded.rfind(statement)
    reading = expanded[:start] + joined + statement[found.end():] + expanded[start + len(statement):]
    return reading if check_statement(reading, table) is None else None
