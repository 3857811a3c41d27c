"""Pass 1 of the two-pass interpreter (App. C section 3): decode every step once, record
the step labels, match IF/ELSE/END, WHILE/DO/END and DO/UNTIL.

"In the first pass, the simulator makes a record of the step label, variable names, and
examines the logical condition. In the second pass, it finds the specified step and
transfers the control to that step."  The syntax checker reports what this finds; the
interpreter builds its executable form from it.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from valterm.core.errors import ValtermError
from valterm.core.files.commandfile import CommandTable, default_commands
from valterm.core.files.programs import Program
from valterm.core.val.expr import compile_expr
from valterm.core.val.parser import (
    ControllerOnly,
    Statement,
    ValSyntaxError,
    parse_statement,
    strip_comment,
)
from valterm.core.val.typeout import parse_items

# Commands that transfer control to a label (GRASP and IF ... GOTO too).
_LABEL_USERS = ("GOTO", "GRASP", "IF")


@dataclass(frozen=True)
class Diagnostic:
    """One thing wrong with a program: where (program, step, file line) and why."""

    program: str
    step: int
    message: str
    severity: str = "error"  # error | warning
    line: int = 0

    @property
    def is_error(self) -> bool:
        return self.severity == "error"

    def __str__(self) -> str:
        prefix = "warning: " if self.severity == "warning" else ""
        return f"{self.program} step {self.step}: {prefix}{self.message}"


class Diagnosed:
    """Something holding ``diagnostics``: its errors and its warnings."""

    diagnostics: list[Diagnostic]

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.is_error]

    @property
    def warnings(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if not d.is_error]


@dataclass
class Analysis(Diagnosed):
    """What pass 1 knows about a program.  Step indexes are 0-based; step numbers 1-based."""

    program: Program
    statements: list[Statement | None]  # None: the step does not decode (see syntax)
    syntax: dict[int, str] = field(default_factory=dict)  # step index -> reason
    labels: dict[int, int] = field(default_factory=dict)  # label -> step index
    partner: dict[int, int] = field(default_factory=dict)  # IF->END, WHILE->END, END->WHILE, UNTIL->DO
    else_of: dict[int, int] = field(default_factory=dict)  # IF -> its ELSE
    calls: list[tuple[int, str]] = field(default_factory=list)  # (step index, program called)
    cases: dict[int, list[int]] = field(default_factory=dict)  # V+ CASE -> its VALUE/ANY steps
    case_of: dict[int, int] = field(default_factory=dict)  # V+ VALUE/ANY -> its CASE
    autos: list[str] = field(default_factory=list)  # V+ AUTO/LOCAL names (saved across a CALL)
    loops: dict[int, list[int]] = field(default_factory=dict)  # V+ EXIT/NEXT -> its loops, innermost first
    dialect: str = "1985"
    diagnostics: list[Diagnostic] = field(default_factory=list)
    fatal: list[Diagnostic] = field(default_factory=list)  # structure errors: the program cannot run

    @property
    def name(self) -> str:
        return self.program.name

    @property
    def structure_ok(self) -> bool:
        """No error that stops the program from running (unmatched structures, duplicate labels)."""
        return not self.fatal



Parse = Callable[[str], Statement]


def analyse(program: Program, table: CommandTable | None = None, parse: Parse | None = None,
            dialect: str = "1985") -> Analysis:
    """Pass 1 over a program: every bad step, every structure error, GOTOs to missing labels.

    ``parse`` decodes one step (the dialect's parser; the 1985 COMMAND.DAT one by default).
    """
    table = table or default_commands()
    name = program.name
    result = Analysis(program, [], dialect=dialect)
    diagnostics = result.diagnostics

    def report(index: int, message: str, severity: str = "error", fatal: bool = True) -> None:
        line = program.steps[index].line if 0 <= index < len(program.steps) else 0
        diagnostic = Diagnostic(name, index + 1, message, severity, line)
        diagnostics.append(diagnostic)
        if fatal and severity == "error":
            result.fatal.append(diagnostic)

    stack: list[tuple[str, int]] = []  # open structures: (IF | ELSE | WHILE | DO, step index)
    for index, step in enumerate(program.steps):
        if step.label is not None:
            if step.label in result.labels:
                report(index, f"step label {step.label} is already used at step {result.labels[step.label] + 1}")
            else:
                result.labels[step.label] = index
        try:
            statement = parse(step.text) if parse is not None else parse_statement(step.text, table)
        except ValSyntaxError as error:
            result.statements.append(None)
            result.syntax[index] = str(error)
            opening = _opener_word(step.text, table, parse is not None)
            # A structure's opener that does not decode still opens it (so its END is not
            # reported as a stray one) and the program cannot run. A line real V+ takes that
            # needs the controller's devices or tasks is a warning: the program stops there.
            if isinstance(error, ControllerOnly):
                report(index, f"{error} (a real controller accepts it; a run stops here)", "warning",
                       fatal=opening is not None)
            else:
                report(index, str(error), fatal=opening is not None)
            if opening is not None:
                stack.append((opening, index))
                if opening == "CASE":  # its VALUEs still belong to it
                    result.cases[index] = []
            continue
        result.statements.append(statement)
        command = statement.command
        if statement.spec is not None and not statement.spec.in_program:
            reason = f"{command} is a monitor command: type it at the VAL-II prompt, not in a program"
            result.statements[index] = None
            result.syntax[index] = reason
            report(index, reason, fatal=False)
            continue
        problem = static_problem(statement) if parse is None else None
        if problem is not None:
            result.statements[index] = None
            result.syntax[index] = problem
            report(index, problem, fatal=False)
            continue
        _structure(statement, index, stack, result, report)
    for kind, opener in stack:
        closing = "UNTIL" if kind == "DO" else "END"
        what = "IF" if kind == "ELSE" else kind.split(".")[0]
        report(opener, f"{what} without {closing}")

    for index, decoded in enumerate(result.statements):
        if decoded is None or decoded.command not in _LABEL_USERS:
            continue
        label = _jump_label(decoded)
        if label is not None and label not in result.labels:
            report(index, f"{decoded.command} {label}: no step has label {label} "
                          "(at run time: an error message, then the next step)", "warning")
    diagnostics.sort(key=lambda d: (d.step, not d.is_error))
    return result


def _opener_word(text: str, table: CommandTable, vplus: bool = False) -> str | None:
    """IF (with THEN), WHILE or DO (V+: FOR, CASE) when a step that failed to decode starts with one."""
    words = strip_comment(text).upper().replace(",", " ").split()
    if not words:
        return None
    if vplus:
        if words[0] in ("FOR", "CASE", "WHILE", "DO"):
            return words[0]
        return "IF" if words[0] == "IF" and "GOTO" not in words else None
    try:
        command = table.lookup(words[0]).name if words[0].isalpha() else ""
    except ValueError:
        return None
    if command == "WHILE" or command == "DO":
        return command
    if command == "IF" and "THEN" in words and "GOTO" not in words:
        return "IF"
    return None


def static_problem(statement: Statement) -> str | None:
    """What is certainly wrong with a decoded step whatever the variables (DRIVE 7,...)."""
    if statement.command == "DRIVE" and statement.args and statement.args[0] is not None:
        joint = statement.args[0].const
        if joint is not None and (joint != int(joint) or not 1 <= joint <= 6):
            return f"DRIVE: JOINT NUMBER {joint:g} IS NOT 1 TO 6"
    if statement.command == "TYPE" and statement.shape != 0 and (statement.args[0] or "").lstrip().startswith('"'):
        try:
            parse_items(statement.args[0], compile_expr)
        except (ValueError, ValtermError) as error:
            return str(error)
    return None


def _structure(statement: Statement, index: int, stack: list[tuple[str, int]], result: Analysis,
               report: Callable[[int, str], None]) -> None:
    """Record a CALL, or match one step of IF/ELSE/END, WHILE/END, DO/UNTIL on `stack`."""
    command = statement.command
    if command in ("FOR", "CASE", "VALUE", "ANY", "AUTO"):
        _vplus_structure(statement, index, stack, result, report)
    elif command in ("EXIT", "NEXT"):
        loops = [opener for kind, opener in reversed(stack) if kind in ("FOR", "WHILE", "DO")]
        count = statement.args[0]
        if count > len(loops):
            what = "A LOOP" if count == 1 else f"{count} NESTED LOOPS"
            report(index, f"{command} {count}: NOT INSIDE {what} (FOR, WHILE or DO)")
        result.loops[index] = loops
    elif command == "CALL":
        result.calls.append((index, statement.args[0]))
    elif command == "IF" and "THEN" in statement.keywords:
        stack.append(("IF", index))
    elif command == "WHILE":
        stack.append(("WHILE", index))
    elif command == "DO":
        stack.append(("DO", index))
    elif command == "ELSE":
        if stack and stack[-1][0] == "IF":
            opener = stack.pop()[1]
            result.else_of[opener] = index
            stack.append(("ELSE", opener))
        elif stack and stack[-1][0] == "ELSE":
            report(index, f"second ELSE for the IF at step {stack[-1][1] + 1}")
        else:
            report(index, "ELSE without IF")
    elif command in ("END", "ENDIF"):
        if not stack or stack[-1][0] == "DO":
            where = f" (the DO at step {stack[-1][1] + 1} needs UNTIL first)" if stack else ""
            openers = "IF, WHILE, FOR or CASE" if result.dialect == "v+" else "IF or WHILE"
            report(index, f"{command} without {openers}{where}")
        else:
            kind, opener = stack.pop()
            if kind == "WHILE" and command == "ENDIF":
                report(index, f"ENDIF closes the WHILE at step {opener + 1}: use END")
            result.partner[opener] = index
            result.partner[index] = opener
    elif command == "UNTIL":
        if stack and stack[-1][0] == "DO":
            opener = stack.pop()[1]
            result.partner[index] = opener
            result.partner[opener] = index
        else:
            where = f" (the {stack[-1][0]} at step {stack[-1][1] + 1} needs END first)" if stack else ""
            report(index, f"UNTIL without DO{where}")


def _vplus_structure(statement: Statement, index: int, stack: list[tuple[str, int]], result: Analysis,
                     report: Callable[[int, str], None]) -> None:
    """FOR ... END, CASE ... OF / VALUE ... : / ANY / END, and AUTO/LOCAL declarations."""
    command = statement.command
    if command == "AUTO":
        result.autos.extend(name for name in statement.args[0] if name not in result.autos)
    elif command in ("FOR", "CASE"):
        stack.append((command, index))
        if command == "CASE":
            result.cases[index] = []
    elif not stack or stack[-1][0] not in ("CASE", "CASE.ANY"):
        report(index, f"{command} without CASE")
    elif stack[-1][0] == "CASE.ANY":
        report(index, f"{command} after ANY (ANY is the last choice of the CASE at step {stack[-1][1] + 1})")
    else:
        opener = stack[-1][1]
        result.cases[opener].append(index)
        result.case_of[index] = opener
        if command == "ANY":
            stack[-1] = ("CASE.ANY", opener)


def _jump_label(statement: Statement) -> int | None:
    label: int | None = None
    if statement.command == "GOTO":
        label = statement.args[0]
    elif statement.command == "GRASP" and len(statement.args) > 1 or (
            statement.command == "IF" and "GOTO" in statement.keywords):
        label = statement.args[1]
    return label


def step_text(program: Program, index: int) -> str:
    """A step as it scrolls on the screen: its label, then the statement without comment."""
    step = program.steps[index]
    statement = strip_comment(step.text, quoted=program.dialect == "v+")
    return f"{step.label} {statement}" if step.label is not None else statement
