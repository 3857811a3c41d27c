"""Arithmetic and logical expressions, parsed once into typed nodes and closures.

Expressions (section 6.7, App. C): numbers, variables (at most 9 characters),
+ - * / with the usual precedence, parentheses, unary minus; conditions with
.EQ. .NE. .LT. .LE. .GT. .GE. (or == <> < <= > >=), AND, OR, NOT.  The thesis's
own spellings are accepted: `COL.EQ.2`, `COL .EQ. ROW.` (a stray dot after an
operand), `COL. LT. ROW.` (blanks inside the dotted operator).

The parser builds a tree of small nodes (``Num``, ``Var``, ``Neg``, ``Binary``, ``Not``,
``Logical``); each node makes one closure ``fn(V) -> value`` reading the variables from
the dict ``V``, so a statement never decodes text again (no Python source is generated).
An undeclared variable is the variables' own error when it runs (``VariableStore`` raises
``UndefinedVariable``, a KeyError).  Constant expressions are
folded by running their closure; a number that is not finite is refused ("NUMBER TOO LARGE").
"""

from __future__ import annotations

import operator
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any, Generic, TypeVar

from valterm.core.errors import ValtermError

Values = Mapping[str, float]
Fn = Callable[[Values], float]  # a compiled expression: the variables -> its value

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


class ControllerFunction(ExprError):
    """A V+ function real V+ accepts that needs what only a controller has (its devices, tasks,
    error table): ``check`` warns of it, a program that reaches it stops there."""


class NumberTooLarge(ExprError):
    """A number (written, or a constant expression's value) that is not a finite number."""


#: The largest magnitude a VAL-II number may have (anything past it is refused, never inf).
MAX_NUMBER = 1.0e300


def finite(value: float, what: str) -> float:
    """`value`, or NumberTooLarge naming `what` when it is infinite, NaN or absurdly large."""
    if -MAX_NUMBER <= value <= MAX_NUMBER:
        return value
    raise NumberTooLarge(f"NUMBER TOO LARGE: {what}")


# Each operator written out for the operand shapes that occur most, so an expression
# like `I+1` or `I .LT. N` is one Python call: (variable, constant), (variable, variable),
# (any, constant), (any, any).
_Shapes = tuple[
    Callable[[str, float], Fn], Callable[[str, str], Fn], Callable[[Fn, float], Fn], Callable[[Fn, Fn], Fn],
]
_OPERATORS: dict[str, _Shapes] = {
    "+": (lambda n, b: lambda V: V[n] + b, lambda n, m: lambda V: V[n] + V[m],
          lambda f, b: lambda V: f(V) + b, lambda f, g: lambda V: f(V) + g(V)),
    "-": (lambda n, b: lambda V: V[n] - b, lambda n, m: lambda V: V[n] - V[m],
          lambda f, b: lambda V: f(V) - b, lambda f, g: lambda V: f(V) - g(V)),
    "*": (lambda n, b: lambda V: V[n] * b, lambda n, m: lambda V: V[n] * V[m],
          lambda f, b: lambda V: f(V) * b, lambda f, g: lambda V: f(V) * g(V)),
    "/": (lambda n, b: lambda V: V[n] / b, lambda n, m: lambda V: V[n] / V[m],
          lambda f, b: lambda V: f(V) / b, lambda f, g: lambda V: f(V) / g(V)),
    "==": (lambda n, b: lambda V: V[n] == b, lambda n, m: lambda V: V[n] == V[m],
           lambda f, b: lambda V: f(V) == b, lambda f, g: lambda V: f(V) == g(V)),
    "!=": (lambda n, b: lambda V: V[n] != b, lambda n, m: lambda V: V[n] != V[m],
           lambda f, b: lambda V: f(V) != b, lambda f, g: lambda V: f(V) != g(V)),
    "<": (lambda n, b: lambda V: V[n] < b, lambda n, m: lambda V: V[n] < V[m],
          lambda f, b: lambda V: f(V) < b, lambda f, g: lambda V: f(V) < g(V)),
    "<=": (lambda n, b: lambda V: V[n] <= b, lambda n, m: lambda V: V[n] <= V[m],
           lambda f, b: lambda V: f(V) <= b, lambda f, g: lambda V: f(V) <= g(V)),
    ">": (lambda n, b: lambda V: V[n] > b, lambda n, m: lambda V: V[n] > V[m],
          lambda f, b: lambda V: f(V) > b, lambda f, g: lambda V: f(V) > g(V)),
    ">=": (lambda n, b: lambda V: V[n] >= b, lambda n, m: lambda V: V[n] >= V[m],
           lambda f, b: lambda V: f(V) >= b, lambda f, g: lambda V: f(V) >= g(V)),
}


@dataclass(frozen=True)
class Num:
    value: float

    def closure(self) -> Fn:
        value = self.value
        return lambda V: value


@dataclass(frozen=True)
class Var:
    name: str

    def closure(self) -> Fn:
        return operator.itemgetter(self.name)  # V[name]: UndefinedVariable when undeclared


@dataclass(frozen=True)
class Neg:
    operand: Node

    def closure(self) -> Fn:
        inner = self.operand.closure()
        return lambda V: -inner(V)


@dataclass(frozen=True)
class Binary:
    """Arithmetic (+ - * /) or a relation (== != < <= > >=) of two operands."""

    op: str
    left: Node
    right: Node

    def closure(self) -> Fn:
        var_const, var_var, any_const, any_any = _OPERATORS[self.op]
        left, right = self.left, self.right
        if isinstance(right, Num):
            if isinstance(left, Var):
                return var_const(left.name, right.value)
            return any_const(left.closure(), right.value)
        if isinstance(left, Var) and isinstance(right, Var):
            return var_var(left.name, right.name)
        return any_any(left.closure(), right.closure())


@dataclass(frozen=True)
class Not:
    operand: Node

    def closure(self) -> Fn:
        inner = self.operand.closure()
        return lambda V: not inner(V)


@dataclass(frozen=True)
class Logical:
    """AND / OR, short-circuit as in the thesis's compiler."""

    op: str  # AND | OR
    left: Node
    right: Node

    def closure(self) -> Fn:
        a, b = self.left.closure(), self.right.closure()
        if self.op == "AND":
            return lambda V: a(V) and b(V)
        return lambda V: a(V) or b(V)


@dataclass(frozen=True)
class Opaque:
    """A node a dialect compiled itself (a V+ function call, an array element): text and closure."""

    text: str
    fn: Fn = field(compare=False, repr=False)

    def closure(self) -> Fn:
        return self.fn


Node = Num | Var | Neg | Binary | Not | Logical | Opaque


@dataclass(frozen=True)
class Expr:
    """A compiled expression: its tree, the variables it reads, its text, its constant value."""

    node: Node
    names: tuple[str, ...]
    text: str
    const: float | None = None
    fn: Fn = field(compare=False, repr=False, default=lambda V: 0.0)

    @property
    def src(self) -> str:
        """The expression written out fully parenthesised (for reading, never run)."""
        return render(self.node)

    def function(self) -> Fn:
        """The closure `V -> value` (a constant one when the expression is constant)."""
        if self.const is not None:
            const = self.const
            return lambda V: const
        return self.fn

    def __call__(self, variables: Values) -> float:
        if self.const is not None:
            return self.const
        return self.fn(variables)


def render(node: Node) -> str:
    """`node` as text with every operation parenthesised: `((I * 2.0) - 1.0)`."""
    if isinstance(node, Num):
        return repr(node.value)
    if isinstance(node, Var):
        return node.name
    if isinstance(node, Neg):
        return f"(-{render(node.operand)})"
    if isinstance(node, Not):
        return f"(NOT {render(node.operand)})"
    if isinstance(node, Opaque):
        return node.text
    return f"({render(node.left)} {node.op} {render(node.right)})"


def _tokens(text: str) -> list[tuple[str, str]]:
    out: list[tuple[str, str]] = []
    pos = 0
    text = text.upper()
    while pos < len(text):
        match = _TOKEN.match(text, pos)
        if match is None or match.end() == pos:  # only trailing blanks are left
            break
        pos = match.end()
        kind = match.lastgroup or "bad"
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


Token = TypeVar("Token", bound=tuple[Any, ...])  # (kind, value, ...) as a tokenizer gives it

#: The deepest nesting of brackets and signs an expression may have: the parsers recurse
#: once a level (about eight calls), so a deeper one is refused before Python's own limit.
MAX_NESTING = 32
_OPENING, _CLOSING, _SIGNS = frozenset("(["), frozenset(")]"), frozenset({"+", "-", "NOT"})


def _refuse_deep_nesting(text: str, items: list[Any]) -> None:
    """ExprError when brackets and prefix signs (``-(-(...))``, ``NOT NOT``) nest deeper than
    MAX_NESTING."""
    depth = signs = 0
    operand_before = False
    for token in items:
        value = token[1] if token[0] == "op" else None
        if value in _OPENING:
            depth, signs, operand_before = depth + signs + 1, 0, False
        elif value in _CLOSING:
            depth, operand_before = depth - 1, True
        elif value in _SIGNS and not operand_before:
            signs += 1
        elif value is not None:
            operand_before = False
        else:
            signs, operand_before = 0, True
        if depth + signs > MAX_NESTING:
            shown = text.strip() if len(text.strip()) <= 40 else text.strip()[:40] + "..."
            raise ExprError(f"expression nested deeper than {MAX_NESTING} levels "
                            f"(brackets and signs) in {shown!r}")


class TokenCursor(Generic[Token]):
    """The one cursor over an expression's tokens (the 1985 and the V+ parsers both read
    through it): ``items`` as the tokenizer gave them, ``pos`` the next one."""

    def __init__(self, text: str, items: list[Token]) -> None:
        self.text = text
        self.items = items
        self.pos = 0
        _refuse_deep_nesting(text, items)

    def peek(self) -> Token | None:
        return self.items[self.pos] if self.pos < len(self.items) else None

    def take(self, *values: str) -> str | None:
        """The next token if it is one of the operators ``values`` (then it is used up)."""
        token = self.peek()
        if token is not None and token[0] == "op" and token[1] in values:
            self.pos += 1
            return str(token[1])
        return None

    def expect(self, value: str) -> None:
        if not self.take(value):
            token = self.peek()
            found = f"{token[1]!r}" if token else "the end"
            raise ExprError(f"expected {value!r}, found {found} in {self.text.strip()!r}")

    def done(self) -> None:
        token = self.peek()
        if token is not None:
            raise ExprError(f"unexpected {token[1]!r} in {self.text.strip()!r}")


class _Parser(TokenCursor[tuple[str, str]]):
    def __init__(self, text: str) -> None:
        super().__init__(text.strip(), _tokens(text.strip()))
        self.names: list[str] = []

    def finish(self, node: Node) -> Node:
        self.done()
        return node

    # condition := or ; or := and {OR and} ; and := not {AND not} ; not := NOT not | relation
    def condition(self) -> Node:
        left = self.conjunction()
        while self.take("OR"):
            left = Logical("OR", left, self.conjunction())
        return left

    def conjunction(self) -> Node:
        left = self.negation()
        while self.take("AND"):
            left = Logical("AND", left, self.negation())
        return left

    def negation(self) -> Node:
        if self.take("NOT"):
            return Not(self.negation())
        return self.relation()

    def relation(self) -> Node:
        left = self.sum()
        op = self.take(*_RELATIONS)
        if op is None:
            return left
        return Binary(_RELATIONS[op], left, self.sum())

    def sum(self) -> Node:
        left = self.term()
        while True:
            op = self.take("+", "-")
            if op is None:
                return left
            left = self.fold(Binary(op, left, self.term()))

    def term(self) -> Node:
        left = self.unary()
        while True:
            op = self.take("*", "/")
            if op is None:
                return left
            left = self.fold(Binary(op, left, self.unary()))

    def fold(self, node: Binary | Neg) -> Node:
        """A constant part is computed once, here, and must be a finite number."""
        operands = (node.operand,) if isinstance(node, Neg) else (node.left, node.right)
        if not all(isinstance(operand, Num) for operand in operands):
            return node
        try:
            return Num(finite(float(node.closure()({})), self.text))
        except ZeroDivisionError:
            raise ExprError(f"division by zero in {self.text!r}") from None

    def unary(self) -> Node:
        op = self.take("-", "+")
        if op == "-":
            return self.fold(Neg(self.unary()))
        if op == "+":
            return self.unary()
        return self.primary()

    def primary(self) -> Node:
        token = self.peek()
        if token is None:
            raise ExprError(f"expression ends too soon: {self.text!r}" if self.text else "missing value")
        kind, value = token
        if kind == "number":
            self.pos += 1
            return Num(finite(float(value), value))
        if kind == "name":
            if len(value) > MAX_NAME:
                raise ExprError(f"variable name {value} is longer than {MAX_NAME} characters")
            self.pos += 1
            if value not in self.names:
                self.names.append(value)
            return Var(value)
        if self.take("("):
            inner = self.condition()
            if not self.take(")"):
                raise ExprError(f"missing ')' in {self.text!r}")
            return inner
        raise ExprError(f"unexpected {value!r} in {self.text!r}")


def _build(text: str, node: Node, names: list[str]) -> Expr:
    fn = node.closure()
    const = None
    if not names:  # folded by running the closure once: no variables to read
        try:
            const = finite(float(fn({})), text.strip())
        except ZeroDivisionError:
            raise ExprError(f"division by zero in {text.strip()!r}") from None
    return Expr(node, tuple(names), text.strip(), const, fn)


def compile_expr(text: str) -> Expr:
    """An arithmetic expression (a number, variable, + - * / and parentheses)."""
    parser = _Parser(text)
    return _build(text, parser.finish(parser.sum()), parser.names)


def compile_condition(text: str) -> Expr:
    """A logical expression; a bare arithmetic one is true when it is not zero."""
    parser = _Parser(text)
    return _build(text, parser.finish(parser.condition()), parser.names)


def is_variable_name(name: str) -> bool:
    return bool(re.fullmatch(r"[A-Z][A-Z0-9]{0,8}", name.upper()))
