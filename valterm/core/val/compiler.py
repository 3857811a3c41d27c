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


@dataclass(frozen=True)
class Grammar:
    """How pass 1 reads a dialect's steps (``Dialect.grammar``); the defaults are the 1985
    dialect's: COMMAND.DAT decodes each step."""

    name: str = "1985"  # as ``Program.dialect`` and ``--dialect`` spell it
    parse: Parse | None = None  # one step (no label) -> Statement; None: COMMAND.DAT's parser
    # the block a step that does not decode opens (IF, WHILE, DO, FOR, CASE) or None;
    # None here: the COMMAND.DAT word's
    opener: Callable[[str], str | None] | None = None
    ends_close: str = "IF or WHILE"  # what END may close, as a stray END's error says it
    quoted_comments: bool = False  # a ';' between quotes is text, not a comment


COMMAND_DAT = Grammar()


def analyse(program: Program, table: CommandTable | None = None, grammar: Grammar = COMMAND_DAT) -> Analysis:
    """Pass 1 over a program: every bad step, every structure error, GOTOs to missing labels.

    ``grammar`` decodes the steps (the dialect's; the 1985 COMMAND.DAT one by default).
    """
    table = table or default_commands()
    name = program.name
    result = Analysis(program, [], dialect=grammar.name)
    parse = grammar.parse
    diagnostics = result.diagnostics

    def report(index: int, message: str, severity: str = "error", fatal: bool = True) -> None:
        line = program.steps[index].line if 0 <= index < len(program.steps) else 0
        diagnostic = Diagnostic(name, index + 1, message, severity, line)
        diagnostics.append(diagnostic)
        if fatal and severity == "error":
            result.fatal.append(diagnostic)

    stack: list[tuple[str, int]] = []  # open structures: (IF | ELSE | WHILE | DO | FOR | CASE, step index)
    blocks = _Blocks(stack, result, report, grammar)
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
            opening = grammar.opener(step.text) if grammar.opener is not None else _opener_word(step.text, table)
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
        _structure(statement, index, blocks)
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


def _opener_word(text: str, table: CommandTable) -> str | None:
    """IF (with THEN), WHILE or DO when a step that failed to decode starts with one."""
    words = strip_comment(text).upper().replace(",", " ").split()
    if not words:
        return None
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


@dataclass(frozen=True)
class _Blocks:
    """Pass 1's view of the block structure: the open blocks, innermost last, as (IF | ELSE |
    WHILE | DO | FOR | CASE | CASE.ANY, step index of the opener); where it records what it
    matches, and how it reports a mismatch."""

    stack: list[tuple[str, int]]
    result: Analysis
    report: Callable[[int, str], None]
    grammar: Grammar


def _structure(statement: Statement, index: int, blocks: _Blocks) -> None:
    """Record a CALL, or match one step of a block structure (IF/ELSE/END, WHILE/END, DO/UNTIL,
    FOR/END, CASE/VALUE/ANY/END) on the open blocks; AUTO/LOCAL and EXIT/NEXT are recorded too.
    Every VAL dialect's blocks are these words: a dialect has those its parser decodes."""
    matcher = _BLOCK_WORDS.get(statement.command)
    if matcher is not None:
        matcher(statement, index, blocks)


def _open(statement: Statement, index: int, blocks: _Blocks) -> None:
    """WHILE, DO, FOR: a block opens."""
    blocks.stack.append((statement.command, index))


def _open_if(statement: Statement, index: int, blocks: _Blocks) -> None:
    if "THEN" in statement.keywords:  # IF ... GOTO opens nothing
        blocks.stack.append(("IF", index))


def _open_case(statement: Statement, index: int, blocks: _Blocks) -> None:
    blocks.stack.append(("CASE", index))
    blocks.result.cases[index] = []


def _call(statement: Statement, index: int, blocks: _Blocks) -> None:
    blocks.result.calls.append((index, statement.args[0]))


def _auto(statement: Statement, index: int, blocks: _Blocks) -> None:
    """AUTO/LOCAL: the subroutine's own variables (saved across a CALL)."""
    autos = blocks.result.autos
    autos.extend(name for name in statement.args[0] if name not in autos)


def _loop_control(statement: Statement, index: int, blocks: _Blocks) -> None:
    """EXIT n / NEXT n: the loops around the step, innermost first."""
    loops = [opener for kind, opener in reversed(blocks.stack) if kind in ("FOR", "WHILE", "DO")]
    count = statement.args[0]
    if count > len(loops):
        what = "A LOOP" if count == 1 else f"{count} NESTED LOOPS"
        blocks.report(index, f"{statement.command} {count}: NOT INSIDE {what} (FOR, WHILE or DO)")
    blocks.result.loops[index] = loops


def _else(statement: Statement, index: int, blocks: _Blocks) -> None:
    stack = blocks.stack
    if stack and stack[-1][0] == "IF":
        opener = stack.pop()[1]
        blocks.result.else_of[opener] = index
        stack.append(("ELSE", opener))
    elif stack and stack[-1][0] == "ELSE":
        blocks.report(index, f"second ELSE for the IF at step {stack[-1][1] + 1}")
    else:
        blocks.report(index, "ELSE without IF")


def _end(statement: Statement, index: int, blocks: _Blocks) -> None:
    """END (ENDIF) closes the innermost block but a DO (which UNTIL closes)."""
    stack, command = blocks.stack, statement.command
    if not stack or stack[-1][0] == "DO":
        where = f" (the DO at step {stack[-1][1] + 1} needs UNTIL first)" if stack else ""
        blocks.report(index, f"{command} without {blocks.grammar.ends_close}{where}")
        return
    kind, opener = stack.pop()
    if kind == "WHILE" and command == "ENDIF":
        blocks.report(index, f"ENDIF closes the WHILE at step {opener + 1}: use END")
    blocks.result.partner[opener] = index
    blocks.result.partner[index] = opener


def _until(statement: Statement, index: int, blocks: _Blocks) -> None:
    stack = blocks.stack
    if stack and stack[-1][0] == "DO":
        opener = stack.pop()[1]
        blocks.result.partner[index] = opener
        blocks.result.partner[opener] = index
    else:
        where = f" (the {stack[-1][0]} at step {stack[-1][1] + 1} needs END first)" if stack else ""
        blocks.report(index, f"UNTIL without DO{where}")


def _choice(statement: Statement, index: int, blocks: _Blocks) -> None:
    """VALUE ... : / ANY, a choice of the innermost CASE (ANY is its last)."""
    stack, command = blocks.stack, statement.command
    if not stack or stack[-1][0] not in ("CASE", "CASE.ANY"):
        blocks.report(index, f"{command} without CASE")
    elif stack[-1][0] == "CASE.ANY":
        blocks.report(index, f"{command} after ANY (ANY is the last choice of the CASE at step {stack[-1][1] + 1})")
    else:
        opener = stack[-1][1]
        blocks.result.cases[opener].append(index)
        blocks.result.case_of[index] = opener
        if command == "ANY":
            stack[-1] = ("CASE.ANY", opener)


_BLOCK_WORDS: dict[str, Callable[[Statement, int, _Blocks], None]] = {
    "IF": _open_if, "ELSE": _else, "END": _end, "ENDIF": _end, "WHILE": _open, "DO": _open, "UNTIL": _until,
    "FOR": _open, "CASE": _open_case, "VALUE": _choice, "ANY": _choice, "EXIT": _loop_control,
    "NEXT": _loop_control, "AUTO": _auto, "CALL": _call,
}


def _jump_label(statement: Statement) -> int | None:
    label: int | None = None
    if statement.command == "GOTO":
        label = statement.args[0]
    elif statement.command == "GRASP" and len(statement.args) > 1 or (
            statement.command == "IF" and "GOTO" in statement.keywords):
        label = statement.args[1]
    return label


def step_text(program: Program, index: int, quoted: bool = False) -> str:
    """A step as it scrolls on the screen: its label, then the statement without comment
    (``quoted``: a ';' between quotes is text, as in V+)."""
    step = program.steps[index]
    statement = strip_comment(step.text, quoted=quoted)
    return f"{step.label} {statement}" if step.label is not None else statement
