"""One VAL-II statement: the command word (any unique prefix, from COMMAND.DAT), its
arguments matched against the shapes COMMAND.DAT gives, expressions compiled once.

``parse_statement(text)`` returns a ``Statement`` or raises ``ValSyntaxError`` whose
message is the reason to report (`APPRO needs APPRO <location>, <value>`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

from valterm.core.errors import ValtermError
from valterm.core.files.commandfile import (
    AmbiguousCommand,
    CommandSpec,
    CommandTable,
    Item,
    Literal,
    Slot,
    UnknownCommand,
    default_commands,
)
from valterm.core.val.expr import (
    MAX_NAME,
    Expr,
    ExprError,
    compile_condition,
    compile_expr,
)

ASSIGN = "="  # the command of an assignment statement VAR=expr (section 6.7)
MAX_LABEL = 65535

_ASSIGNMENT = re.compile(r"^([A-Z][A-Z0-9]*)\s*=(?!=)(.*)$", re.DOTALL)
_WORD = re.compile(r"^([A-Z]+)(.*)$", re.DOTALL)
_IDENT = re.compile(r"^[A-Z][A-Z0-9]*$")
_SHIFT_LOC = re.compile(r"^SHIFT\s*\((.*)\)$", re.DOTALL)
_BY = re.compile(r"^([A-Z][A-Z0-9]*)\s+BY\s+(.*)$", re.DOTALL)
_PROG = re.compile(r"^([A-Z][A-Z0-9]*)(?:\.DAT)?$")
# A V+ program of a .v2/.pg file may have a dotted name (pick.place): EXECUTE, CALL, LISTP reach it.
_VPLUS_PROG = re.compile(r"^[A-Z][A-Z0-9_]*(?:\.[A-Z0-9_]+)+$")
VPLUS_NAME_LENGTH = 15
_VAR = re.compile(r"^([A-Z][A-Z0-9]*)\s*=$")
# Something assigned that is not a 1985 variable name: `Z_PICK = 80`, `A[I] = I`, `Z.PICK = 80`.
_BAD_ASSIGNMENT = re.compile(r"^([^\s=<>!]+?)\s*(\[[^\]]*\])?\s*=(?!=)")


class ValSyntaxError(ValtermError, ValueError):
    """A statement the simulator cannot decode; the message is the reason."""


class ControllerOnly(ValSyntaxError):
    """A statement real V+ accepts but the simulator cannot run (the controller's devices,
    tasks, error table): pass 1 warns of it (no error: the controller would take the line),
    and a program that reaches the step stops there with the reason."""


@dataclass(frozen=True)
class LocArg:
    """A location argument: a name, or SHIFT(name BY dx,dy,dz) (omitted increments = 0)."""

    name: str
    shift: tuple[Expr | None, Expr | None, Expr | None] | None = None

    def __str__(self) -> str:
        if self.shift is None:
            return self.name
        parts = ",".join("" if e is None else e.text for e in self.shift)
        return f"SHIFT({self.name} BY {parts})"


@dataclass(frozen=True)
class Statement:
    """A decoded statement: the command's full name and one value per argument slot."""

    command: str  # full command name, ASSIGN, or "" for an empty step (comment)
    args: tuple[Any, ...] = ()
    text: str = ""
    spec: CommandSpec | None = None
    shape: int = 0  # which alternative of the COMMAND.DAT shape matched

    @property
    def keywords(self) -> tuple[str, ...]:
        """The keywords of the matched shape (IF ... GOTO has GOTO)."""
        if self.spec is None:
            return ()
        return tuple(item.options[0] for item in self.spec.shapes[self.shape]
                     if isinstance(item, Literal) and item.options[0].isalpha())


def strip_comment(text: str, quoted: bool = False) -> str:
    """The statement without its `;` comment (``quoted``: V+, where a `;` inside quotes is text)."""
    if quoted:
        inside = False
        for index, ch in enumerate(text):
            if ch == '"':
                inside = not inside
            elif ch == ";" and not inside:
                return text[:index].strip()
        return text.strip()
    return text.split(";", 1)[0].strip()


def _check_name(name: str, what: str) -> str:
    if not _IDENT.match(name):
        raise ValSyntaxError(f"{name!r} is not a {what} name (a letter, then letters or digits)")
    if len(name) > MAX_NAME:
        raise ValSyntaxError(f"{what} name {name} is longer than {MAX_NAME} characters")
    return name


def _split_commas(text: str) -> list[str]:
    parts, depth, start = [], 0, 0
    for i, ch in enumerate(text):
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
        elif ch == "," and depth == 0:
            parts.append(text[start:i])
            start = i + 1
    parts.append(text[start:])
    return [p.strip() for p in parts]


def _optional_expr(text: str) -> Expr | None:
    return compile_expr(text) if text.strip() else None


def parse_location(text: str) -> LocArg:
    text = text.strip()
    if not text:
        raise ValSyntaxError("missing location")
    shifted = _SHIFT_LOC.match(text)
    if shifted:
        inner = _BY.match(shifted.group(1).strip())
        if inner is None:
            raise ValSyntaxError(f"expected SHIFT(<location> BY dx,dy,dz), not {text}")
        parts = _split_commas(inner.group(2))
        if len(parts) > 3:
            raise ValSyntaxError(f"SHIFT takes at most three increments: {text}")
        parts += [""] * (3 - len(parts))
        try:
            shift = tuple(_optional_expr(p) for p in parts)
        except ExprError as error:
            raise ValSyntaxError(str(error)) from None
        return LocArg(_check_name(inner.group(1), "location"), shift)  # type: ignore[arg-type]
    return LocArg(_check_name(text, "location"))


def _convert(kind: str, text: str, original: str) -> Any:
    """The value of one argument slot (text already stripped)."""
    try:
        if kind == "EXPR":
            return compile_expr(text)
        if kind == "COND":
            return compile_condition(text)
    except ExprError as error:
        raise ValSyntaxError(str(error)) from None
    if kind == "LOC":
        return parse_location(text)
    if kind == "NAME":
        return _check_name(text, "location")
    if kind == "LABEL":
        if not text.isdigit():
            raise ValSyntaxError(f"{text!r} is not a step label (a number)")
        label = int(text)
        if label > MAX_LABEL:
            raise ValSyntaxError(f"step label {text} is too large (at most {MAX_LABEL})")
        return label
    if kind == "PROG":
        match = _PROG.match(text)
        if match is None and _VPLUS_PROG.match(text) and len(text) <= VPLUS_NAME_LENGTH:
            return text  # a dotted V+ name: only a workspace .v2/.pg file can define it
        if match is None:
            raise ValSyntaxError(f"{text!r} is not a program name")
        return _check_name(match.group(1), "program")
    if kind == "VAR":
        match = _VAR.match(text)
        if match is None:
            raise ValSyntaxError(f"expected <variable>=, not {text!r}")
        return _check_name(match.group(1), "variable")
    if kind == "TEXT":
        return original
    raise AssertionError(kind)


def _literal_at(text: str, pos: int, options: tuple[str, ...]) -> int | None:
    """End of the literal starting at pos (after blanks), or None."""
    while pos < len(text) and text[pos].isspace():
        pos += 1
    for option in options:
        if option in (",", "="):
            if text.startswith(option, pos):
                return pos + 1
        elif text.startswith(option, pos):
            end = pos + len(option)
            alone_after = end == len(text) or not text[end].isalnum()
            if alone_after and (pos == 0 or not text[pos - 1].isalnum()):
                return end
    return None


def _candidate_ends(text: str, pos: int, options: set[str]) -> list[int]:
    """Top-level (outside parentheses) positions from pos where one of the literals starts."""
    ends, depth = [], 0
    for i in range(pos, len(text)):
        ch = text[i]
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
        elif depth == 0 and _literal_at(text, i, tuple(options)) is not None and (
                ch in (",", "=") or not text[i].isspace()):
            ends.append(i)
    ends.append(len(text))
    return ends


def _match(items: tuple[Item, ...], text: str, original: str, i: int, pos: int,
           out: list[Any], errors: list[str]) -> list[Any] | None:
    rest = text[pos:]
    if i == len(items):
        return out if not rest.strip() else None
    # At the end of the text, left-out optional arguments and their commas are fine
    # (BASE ,,300), a keyword (THEN, DO) is not.
    if not rest.strip() and all(it.optional or (isinstance(it, Literal) and it.options[0] in (",", "="))
                                for it in items[i:]):
        return out + [None] * sum(isinstance(it, Slot) for it in items[i:])
    item = items[i]
    if isinstance(item, Literal):
        end = _literal_at(text, pos, item.options)
        if end is not None:
            result = _match(items, text, original, i + 1, end, out, errors)
            if result is not None:
                return result
        if item.optional:
            return _match(items, text, original, i + 1, pos, out, errors)
        return None
    # A slot runs up to one of the literals that may follow it.
    options: set[str] = set()
    for follower in items[i + 1:]:
        if isinstance(follower, Literal):
            options.update(follower.options)
            if not follower.optional:
                break
    ends = _candidate_ends(text, pos, options) if options else [len(text)]
    for end in ends:
        value_text = text[pos:end].strip()
        if not value_text:
            if not item.optional:
                continue
            value: Any = None
        else:
            try:
                value = _convert(item.kind, value_text, original[pos:end].strip())
            except ValSyntaxError as error:
                errors.append(str(error))
                continue
        result = _match(items, text, original, i + 1, end, out + [value], errors)
        if result is not None:
            return result
    return None


def _refuse_bad_assignment(upper: str) -> None:
    """A clear reason for an assignment to a name the 1985 dialect does not have."""
    bad = _BAD_ASSIGNMENT.match(upper)
    if bad is None:
        return
    name, index = bad.group(1), bad.group(2)
    if index and _IDENT.match(name):
        raise ValSyntaxError(f"{name}{index}: ARRAYS ARE V+ (NOT IN THE 1985 DIALECT; USE --dialect v+)")
    if "." in name or name.startswith(("$", "#")):
        raise ValSyntaxError(f"{name}: DOTTED, $STRING AND #PRECISION NAMES ARE V+ "
                             "(NOT IN THE 1985 DIALECT; USE --dialect v+)")
    if not _IDENT.match(name):
        raise ValSyntaxError(f"{name} IS NOT A VARIABLE NAME (A LETTER, THEN LETTERS OR DIGITS)")


def parse_statement(text: str, table: CommandTable | None = None) -> Statement:
    """Decode one statement (no label; a `;` comment is dropped)."""
    table = table or default_commands()
    original = strip_comment(text)
    upper = original.upper()
    if len(upper) != len(original):  # a character whose capital is longer: give up keeping case
        original = upper
    if not upper:
        return Statement("", (), "")
    assignment = _ASSIGNMENT.match(upper)
    if assignment:
        name = _check_name(assignment.group(1), "variable")
        value_text = assignment.group(2).strip()
        if not value_text:
            raise ValSyntaxError(f"{name}= needs a value")
        try:
            value = compile_expr(value_text)
        except ExprError as error:
            raise ValSyntaxError(str(error)) from None
        return Statement(ASSIGN, (name, value), original)
    _refuse_bad_assignment(upper)
    word_match = _WORD.match(upper)
    if word_match is None:
        raise ValSyntaxError(f"{original.split()[0]!r} is not a VAL-II command")
    word = word_match.group(1)
    try:
        spec = table.lookup(word)
    except AmbiguousCommand as error:
        raise ValSyntaxError(f"{word} is ambiguous: it could be {', '.join(error.candidates)}") from None
    except UnknownCommand:
        if word == "ABORT":
            raise ValSyntaxError("the simulator does not accept ABORT: press CTRL-C") from None
        raise ValSyntaxError(f"{word} is not a command the simulator accepts (see COMMAND.DAT)") from None
    start = len(word)
    args_upper, args_original = upper[start:], original[start:]
    errors: list[str] = []
    for index, shape in enumerate(spec.shapes):
        values = _match(shape, args_upper, args_original, 0, 0, [], errors)
        if values is not None:
            return Statement(spec.name, tuple(values), original, spec, index)
    reason = errors[0] if errors else f"expected {spec.usage()}"
    if errors:
        reason = f"{reason} (expected {spec.usage()})"
    raise ValSyntaxError(f"{spec.name}: {reason}")
