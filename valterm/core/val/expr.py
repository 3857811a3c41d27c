"""Arithmetic and logical expressions, compiled once to Python source.

Expressions (section 6.7, App. C): numbers, variables (at most 9 characters),
+ - * / with the usual precedence, parentheses, unary minus; conditions with
.EQ. .NE. .LT. .LE. .GT. .GE. (or == <> < <= > >=), AND, OR, NOT.  The thesis's
own spellings are accepted: `COL.EQ.2`, `COL .EQ. ROW.` (a stray dot after an
operand), `COL. LT. ROW.` (blanks inside the dotted operator).

The result is Python source reading variables as ``V['NAME']``, so a statement
can be compiled into one Python function and never decoded again; an undeclared
variable raises ``KeyError(name)`` when it runs.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Callable

from valterm.core.errors import ValtermError

MAX_NAME = 9

_DOTTED = r"\.\s*(EQ|NE|LT|LE|GT|GE|AND|OR|NOT)\s*\."
_TOKEN = re.compile(
    rf"""\s*(?:
      (?P<dotted>{_DOTTED})
    | (?P<number>(?:\d+(?:\.(?!\s*(?:EQ|NE|LT|LE|GT|GE|AND|OR|NOT)\s*\.)\d*)?|\.\d+)(?:E[+-]?\d+)?)
    | (?P<name>[A-Z][A-Z0-9]*)
    | (?P<op><=|>=|<>|==|!=|[-+*/()<>=])
    | (?P<dot>\.)
    | (?P<bad>\S)
    )""",
    re.VERBOSE,
)

_RELATIONS = {
    "EQ": "==", "NE": "!=", "LT": "<", "LE": "<=", "GT": ">", "GE": ">=",
    "==": "==", "=": "==", "<>": "!=", "!=": "!=", "<": "<", "<=": "<=", ">": ">", ">=": ">=",
}
_LOGICAL = ("AND", "OR", "NOT")


class ExprError(ValtermError, ValueError):
    """An expression that cannot be compiled; the message says what is wrong."""


@dataclass(frozen=True)
class Expr:
    """A compiled expression: its Python source, the variables it reads, its text."""

    src: str
    names: tuple[str, ...]
    text: str
    const: float | None = None

    def function(self) -> Callable[[dict], float]:
        return eval(f"lambda V: {self.src}", {"__builtins__": {}})  # src built from checked tokens only

    def __call__(self, variables: dict) -> float:
        if self.const is not None:
            return self.const
        return self.function()(variables)


def _tokens(text: str) -> list[tuple[str, str]]:
    out: list[tuple[str, str]] = []
    pos = 0
    text = text.upper()
    while pos < len(text):
        match = _TOKEN.match(text, pos)
        if match is None or match.end() == pos:  # only trailing blanks are left
            break
        pos = match.end()
        kind = match.lastgroup
        value = match.group(kind)
        if kind == "bad":
            raise ExprError(f"unexpected character {value!r}")
        if kind == "dotted":
            value = match.group(2)
            kind = "op"
        elif kind == "name" and value in _LOGICAL or kind == "name" and value in _RELATIONS and value.isalpha():
            kind = "op"
        elif kind == "dot":
            # The thesis's trailing dot (`UNTIL COL .EQ. ROW.`) follows an operand; drop it.
            if out and (out[-1][0] in ("number", "name") or out[-1][1] == ")"):
                continue
            raise ExprError("unexpected '.'")
        out.append((kind, value))
    return out


class _Parser:
    def __init__(self, text: str) -> None:
        self.text = text.strip()
        self.tokens = _tokens(self.text)
        self.pos = 0
        self.names: list[str] = []

    def peek(self) -> tuple[str, str] | None:
        return self.tokens[self.pos] if self.pos < len(self.tokens) else None

    def take(self, *values: str) -> str | None:
        token = self.peek()
        if token is not None and token[0] == "op" and token[1] in values:
            self.pos += 1
            return token[1]
        return None

    def finish(self, src: str) -> str:
        token = self.peek()
        if token is not None:
            raise ExprError(f"unexpected {token[1]!r} in {self.text!r}")
        return src

    # condition := or ; or := and {OR and} ; and := not {AND not} ; not := NOT not | relation
    def condition(self) -> str:
        left = self.conjunction()
        while self.take("OR"):
            left = f"({left} or {self.conjunction()})"
        return left

    def conjunction(self) -> str:
        left = self.negation()
        while self.take("AND"):
            left = f"({left} and {self.negation()})"
        return left

    def negation(self) -> str:
        if self.take("NOT"):
            return f"(not {self.negation()})"
        return self.relation()

    def relation(self) -> str:
        left = self.sum()
        op = self.take(*_RELATIONS)
        if op is None:
            return left
        right = self.sum()
        return f"({left} {_RELATIONS[op]} {right})"

    def sum(self) -> str:
        left = self.term()
        while True:
            op = self.take("+", "-")
            if op is None:
                return left
            left = f"({left} {op} {self.term()})"

    def term(self) -> str:
        left = self.unary()
        while True:
            op = self.take("*", "/")
            if op is None:
                return left
            left = f"({left} {op} {self.unary()})"

    def unary(self) -> str:
        op = self.take("-", "+")
        if op is not None:
            return f"({op}{self.unary()})"
        return self.primary()

    def primary(self) -> str:
        token = self.peek()
        if token is None:
            raise ExprError(f"expression ends too soon: {self.text!r}" if self.text else "missing value")
        kind, value = token
        if kind == "number":
            self.pos += 1
            return repr(float(value))
        if kind == "name":
            if len(value) > MAX_NAME:
                raise ExprError(f"variable name {value} is longer than {MAX_NAME} characters")
            self.pos += 1
            if value not in self.names:
                self.names.append(value)
            return f"V[{value!r}]"
        if self.take("("):
            inner = self.condition()
            if not self.take(")"):
                raise ExprError(f"missing ')' in {self.text!r}")
            return inner
        raise ExprError(f"unexpected {value!r} in {self.text!r}")


def _build(text: str, src: str, names: list[str]) -> Expr:
    const = None
    if not names:
        try:
            const = float(eval(src, {"__builtins__": {}}))
        except ZeroDivisionError:
            raise ExprError(f"division by zero in {text.strip()!r}") from None
    return Expr(src, tuple(names), text.strip(), const)


def compile_expr(text: str) -> Expr:
    """An arithmetic expression (a number, variable, + - * / and parentheses)."""
    parser = _Parser(text)
    src = parser.finish(parser.sum())
    return _build(text, src, parser.names)


def compile_condition(text: str) -> Expr:
    """A logical expression; a bare arithmetic one is true when it is not zero."""
    parser = _Parser(text)
    src = parser.finish(parser.condition())
    return _build(text, src, parser.names)


def is_variable_name(name: str) -> bool:
    return bool(re.fullmatch(r"[A-Z][A-Z0-9]{0,8}", name.upper()))
