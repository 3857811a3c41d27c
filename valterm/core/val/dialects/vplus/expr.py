"""V+ expressions: numbers, transformations and strings (Adept V+ reference semantics).

Numeric expressions extend the 1985 ones (``expr``) with dotted names (``z.pick``), array
elements (``a[i]``, ``t[i,j]``: the variable ``A[3]``), TRUE/FALSE/ON/OFF (-1 and 0),
``MOD BAND BOR BXOR XOR ^``, and the functions SIN COS TAN ATAN2 SQRT ABS INT MOD SIGN
MAX MIN BMASK, SIG(n...), TIMER(n), DISTANCE(a, b), DX DY DZ(a), PARAMETER(name),
SWITCH(name), LAST(a[]), LEN VAL ASC($s), and string comparisons (``$a == "X"``).

A location expression is a compound ``a:b:c`` of named locations, ``#points``, and the
functions TRANS(x,y,z,yaw,pitch,roll), RX RY RZ(deg), INVERSE(l), FRAME(l1,l2,l3,l4),
SHIFT(l BY dx,dy,dz), #PPOINT(j1..j6), HERE, NULL; each evaluates to a ``Transform``.

A string expression joins ``"text"``, ``$name``, $ENCODE(list), $CHR(n), $LEFT($s, n) and
$MID($s, first, n) with ``+``. ``compile_precision`` reads ``#name`` / ``#PPOINT(...)``.

``compile_number(text, machine)`` / ``compile_location`` / ``compile_string`` compile once;
with ``machine=None`` they only check the text (the syntax checker), and a closure that
needs the machine says so if it is ever run.
"""

from __future__ import annotations

import math
import re
import struct
from collections.abc import Callable, Mapping, Sequence

from valterm.core.transform import (
    Transform,
    distance,
    frame,
    inverse,
    normalized,
    rx,
    ry,
    rz,
    scale,
    shift,
    trans,
    translation,
)
from valterm.core.val.expr import (
    Binary,
    ControllerFunction,
    Expr,
    ExprError,
    Fn,
    Neg,
    Node,
    Not,
    Num,
    Opaque,
    TokenCursor,
    Values,
    Var,
    finite,
)
from valterm.core.val.machine import TICK, Machine, MachineError

MAX_VNAME = 15
NAME = r"[A-Z][A-Z0-9_]*(?:\.[A-Z0-9_]+)*"
_NAME = re.compile(NAME)
_TOKEN = re.compile(
    rf"""\s*(?:
      (?P<string>"[^"]*")
    | (?P<number>(?:\d+(?:\.\d*)?|\.\d+)(?:E[+-]?\d+)?)
    | (?P<name>[$#]?{NAME})
    | (?P<op><=|>=|<>|==|=<|=>|[-+*/()<>=^,\[\]:])
    | (?P<bad>\S)
    )""",
    re.VERBOSE,
)
_RELATIONS = {"==": "==", "=": "==", "<>": "!=", "<": "<", "<=": "<=", "=<": "<=", ">": ">",
              ">=": ">=", "=>": ">="}
_KEYWORD_OPS = ("AND", "OR", "XOR", "NOT", "MOD", "BAND", "BOR", "BXOR")
_CONSTANTS = {"TRUE": -1.0, "FALSE": 0.0, "ON": -1.0, "OFF": 0.0, "PI": math.pi}

LocFn = Callable[[Values], Transform]
StrFn = Callable[[Values], str]

def _sin(degrees: float) -> float:
    """SIN in degrees, exactly 0 at whole multiples of 180 (never 1.2e-16)."""
    return 0.0 if degrees % 180.0 == 0.0 else math.sin(math.radians(degrees))


def _cos(degrees: float) -> float:
    """COS in degrees, exactly 0 at 90 plus whole multiples of 180 (never 6.1e-17)."""
    return 0.0 if (degrees - 90.0) % 180.0 == 0.0 else math.cos(math.radians(degrees))


_MATH: dict[str, tuple[int, int, Callable[..., float]]] = {  # name: (min args, max args, function)
    "SIN": (1, 1, _sin),
    "COS": (1, 1, _cos),
    "TAN": (1, 1, lambda d: 0.0 if d % 180.0 == 0.0 else math.tan(math.radians(d))),
    "ATAN2": (2, 2, lambda y, x: math.degrees(math.atan2(y, x))),
    "ASIN": (1, 1, lambda v: math.degrees(math.asin(v))),
    "ACOS": (1, 1, lambda v: math.degrees(math.acos(v))),
    "SQRT": (1, 1, math.sqrt),
    "SQR": (1, 1, lambda v: v * v),
    "ABS": (1, 1, abs),
    "INT": (1, 1, lambda v: float(math.trunc(v))),
    "FRACT": (1, 1, lambda v: v - math.trunc(v)),
    "MOD": (2, 2, lambda a, b: math.fmod(a, b)),
    "SIGN": (1, 1, lambda v: (v > 0) - (v < 0)),
    "MAX": (1, 99, max),
    "MIN": (1, 99, min),
    "BMASK": (1, 32, lambda *bits: _bmask(*bits)),
    "TPS": (0, 0, lambda: 1.0 / TICK),  # ticks of the system clock per second (TIMER(-1) counts them)
}
_LOC_FUNCTIONS = ("DISTANCE", "DX", "DY", "DZ", "INRANGE")
_STRING_NUMBERS = ("LEN", "VAL", "ASC")
_CONTROLLER_ONLY = {  # V+ functions of what only a real controller has (check names them as such)
    **dict.fromkeys(("IOSTAT", "GETC", "FEMPTY"), "the I/O devices (disk, network, serial lines)"),
    **dict.fromkeys(("TASK", "STATE", "ERROR", "PRIORITY", "SELECT"), "program tasks and the robot's state"),
}
# INTB LNGB FLTB DBLB($s {, first}): bytes of a string (the first the most significant) as a
# signed 16- or 32-bit integer or an IEEE single or double; $INTB ... $DBLB(value) the reverse.
_BYTE_FORMATS = {"INTB": ">h", "LNGB": ">i", "FLTB": ">f", "DBLB": ">d"}


def _bmask(*bits: float) -> float:
    """BMASK(bit, ...): a value with those bits set (bit 1 is the lowest)."""
    mask = 0
    for bit in bits:
        if bit != int(bit) or not 1 <= bit <= 32:
            raise ExprError(f"BMASK: BIT {bit:g} IS NOT 1 TO 32")
        mask |= 1 << (int(bit) - 1)
    return float(mask)


def _last(values: Mapping[str, object], name: str) -> float:
    prefix = name + "["
    found = [key[len(prefix):-1] for key in values if key.startswith(prefix) and key.endswith("]")]
    indexes = [int(k) for k in found if k.lstrip("-").isdigit()]
    return float(max(indexes)) if indexes else -1.0


def _bits(machine: Machine, first: int, count: int) -> float:
    if not 1 <= count <= 32:
        raise MachineError(f"BITS: {count} SIGNALS (1 TO 32)")
    return float(sum(1 << offset for offset in range(count) if machine.signals.sig(first + offset)))


def _from_bytes(name: str, text: str, first: float) -> float:
    """INTB/LNGB/FLTB/DBLB: the bytes of ``text`` from character ``first`` (1 is the first)."""
    layout = _BYTE_FORMATS[name]
    start = int(first) - 1
    size = struct.calcsize(layout)
    if start < 0 or start + size > len(text):
        raise ExprError(f"{name}: NEEDS {size} CHARACTERS FROM CHARACTER {int(first)}; THE STRING HAS {len(text)}")
    try:
        raw = text[start:start + size].encode("latin-1")
    except UnicodeEncodeError:
        raise ExprError(f"{name}: THE STRING HOLDS A CHARACTER THAT IS NOT A BYTE") from None
    return float(struct.unpack(layout, raw)[0])


def _to_bytes(name: str, value: float) -> str:
    """$INTB/$LNGB/$FLTB/$DBLB(value): the value's bytes, the most significant first."""
    layout = _BYTE_FORMATS[name[1:]]
    number: float | int = value
    if layout in (">h", ">i"):
        number = math.floor(value + 0.5)  # rounded to the nearest integer
        bits = 16 if layout == ">h" else 32
        if not -(1 << (bits - 1)) <= number < 1 << (bits - 1):
            raise ExprError(f"{name}: {value:g} IS NOT A {bits}-BIT INTEGER")
    try:
        return struct.pack(layout, number).decode("latin-1")
    except OverflowError:
        raise ExprError(f"{name}: {value:g} IS TOO LARGE FOR A SINGLE-PRECISION NUMBER") from None


def _val(text: str) -> float:
    """VAL($s): the number the string starts with (0 when none)."""
    match = re.match(r"\s*[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?", text)
    return float(match.group(0)) if match else 0.0


def _asc(text: str, index: float) -> float:
    """ASC($s, i): the code of the i-th character (1 is the first); -1 past the end."""
    position = int(index) - 1
    return float(ord(text[position])) if 0 <= position < len(text) else -1.0
_MACHINE_FUNCTIONS = ("SIG", "TIMER", "PARAMETER", "SWITCH")


def _truth(value: bool) -> float:
    return -1.0 if value else 0.0


_ARITH: dict[str, Callable[[float, float], float]] = {
    "MOD": math.fmod,
    "^": lambda a, b: float(a) ** float(b),
    "BAND": lambda a, b: float(int(a) & int(b)),
    "BOR": lambda a, b: float(int(a) | int(b)),
    "BXOR": lambda a, b: float(int(a) ^ int(b)),
    "XOR": lambda a, b: _truth(bool(a) != bool(b)),
}


def array_key(name: str, indexes: Sequence[float]) -> str:
    """The variable holding one array element: ``A[3]``, ``T[1,2]``."""
    return f"{name}[{','.join(str(int(i)) for i in indexes)}]"


def _needs_machine(what: str) -> Callable[[], Machine]:
    def missing() -> Machine:
        raise MachineError(f"{what} NEEDS THE V+ CONTROLLER")
    return missing


class _Tokens(TokenCursor[tuple[str, str, int, int]]):
    """V+ tokens: kind, value, start, end (strings keep the case as written)."""

    def __init__(self, text: str) -> None:
        items: list[tuple[str, str, int, int]] = []
        pos = 0
        upper = text.upper()
        while pos < len(upper):
            match = _TOKEN.match(upper, pos)
            if match is None or match.end() == pos:
                break
            kind = match.lastgroup or "bad"
            value = match.group(kind)
            start = match.start(kind)
            if kind == "bad":
                raise ExprError(f"unexpected character {value!r}")
            if kind == "string":
                value = text[start + 1:match.end() - 1]  # the case as written
            elif kind == "name" and value in _KEYWORD_OPS:
                kind = "op"
            items.append((kind, value, start, match.end()))
            pos = match.end()
        super().__init__(text, items)


class _Compiler:
    """One expression's parser: numbers, locations and strings share the tokens."""

    def __init__(self, text: str, machine: Machine | None) -> None:
        self.tokens = _Tokens(text)
        self.text = text.strip()
        self.machine = machine
        self.names: list[str] = []

    def get_machine(self, what: str) -> Callable[[], Machine]:
        machine = self.machine
        if machine is None:
            return _needs_machine(what)
        return lambda: machine

    # -- numbers --------------------------------------------------------------------
    def condition(self) -> Node:
        left = self.conjunction()
        while True:
            op = self.tokens.take("OR", "XOR")
            if op is None:
                return left
            right = self.conjunction()
            left = self.logical("OR", left, right) if op == "OR" else self.arith("XOR", left, right)

    def conjunction(self) -> Node:
        left = self.negation()
        while self.tokens.take("AND"):
            left = self.logical("AND", left, self.negation())
        return left

    def logical(self, op: str, left: Node, right: Node) -> Node:
        """AND / OR give TRUE (-1) or FALSE (0), never an operand (V+: ``6 AND 10`` is -1)."""
        f, g = left.closure(), right.closure()
        text = f"({self.src(left)} {op} {self.src(right)})"
        if op == "AND":
            return Opaque(text, lambda V: _truth(bool(f(V)) and bool(g(V))))
        return Opaque(text, lambda V: _truth(bool(f(V)) or bool(g(V))))

    def negation(self) -> Node:
        if self.tokens.take("NOT"):
            inner = self.negation()
            fn = inner.closure()
            return Opaque(f"NOT {self.src(inner)}", lambda V: _truth(not fn(V)))
        return self.relation()

    def relation(self) -> Node:
        token = self.tokens.peek()
        if token is not None and (token[0] == "string" or token[1].startswith("$")):
            return self.string_relation()
        left = self.sum()
        op = self.tokens.take(*_RELATIONS)
        if op is None:
            return left
        compare = Binary(_RELATIONS[op], left, self.sum()).closure()
        return Opaque(f"({self.src(left)} {op} ...)", lambda V: _truth(bool(compare(V))))

    def string_relation(self) -> Node:
        """$a == "TEXT", $a <> $b, $a < $b: strings compared character by character."""
        left = self.string()
        op = self.tokens.take(*_RELATIONS)
        if op is None:
            raise ExprError(f"a string is not a number: compare it ($a == \"TEXT\") in {self.text!r}")
        right = self.string()
        how = {"==": str.__eq__, "!=": str.__ne__, "<": str.__lt__, "<=": str.__le__,
               ">": str.__gt__, ">=": str.__ge__}[_RELATIONS[op]]
        return Opaque(f"(string {op} string)", lambda V: _truth(bool(how(left(V), right(V)))))

    def sum(self) -> Node:
        left = self.term()
        while True:
            op = self.tokens.take("+", "-", "BOR", "BXOR")
            if op is None:
                return left
            right = self.term()
            left = Binary(op, left, right) if op in "+-" else self.arith(op, left, right)

    def term(self) -> Node:
        left = self.power()
        while True:
            op = self.tokens.take("*", "/", "MOD", "BAND")
            if op is None:
                return left
            right = self.power()
            left = Binary(op, left, right) if op in "*/" else self.arith(op, left, right)

    def power(self) -> Node:
        base = self.unary()
        if self.tokens.take("^"):
            return self.arith("^", base, self.power())
        return base

    def unary(self) -> Node:
        op = self.tokens.take("-", "+")
        if op == "-":
            return Neg(self.unary())
        if op == "+":
            return self.unary()
        return self.primary()

    def arith(self, op: str, left: Node, right: Node) -> Node:
        f, g, how = left.closure(), right.closure(), _ARITH[op]
        return Opaque(f"({self.src(left)} {op} {self.src(right)})", lambda V: how(f(V), g(V)))

    @staticmethod
    def src(node: Node) -> str:
        from valterm.core.val.expr import render

        return render(node)

    def primary(self) -> Node:
        token = self.tokens.peek()
        if token is None:
            raise ExprError(f"expression ends too soon: {self.text!r}" if self.text else "missing value")
        kind, value, _start, _end = token
        if kind == "number":
            self.tokens.pos += 1
            return Num(finite(float(value), value))
        if self.tokens.take("("):
            inner = self.condition()
            self.tokens.expect(")")
            return inner
        if kind == "op" and value == "MOD" and self._next_is("("):  # MOD(a, b), the function
            self.tokens.pos += 1
            return self.function("MOD")
        if kind != "name" or value[0] in "$#":
            raise ExprError(f"unexpected {value!r} in {self.text!r}")
        self.tokens.pos += 1
        if value in _CONSTANTS:
            return Num(_CONSTANTS[value])
        after = self.tokens.peek()
        if after is not None and after[1] == "(":
            return self.function(value)
        if after is not None and after[1] == "[":
            return self.element(value)
        if len(value) > MAX_VNAME:
            raise ExprError(f"variable name {value} is longer than {MAX_VNAME} characters")
        if value not in self.names:
            self.names.append(value)
        return Var(value)

    def _next_is(self, value: str) -> bool:
        index = self.tokens.pos + 1
        return index < len(self.tokens.items) and self.tokens.items[index][1] == value

    def indexes(self) -> list[Fn]:
        """``[i]`` or ``[i, j]`` after an array's name."""
        self.tokens.expect("[")
        found = [self.sum().closure()]
        while self.tokens.take(","):
            found.append(self.sum().closure())
        self.tokens.expect("]")
        return found

    def element(self, name: str) -> Node:
        indexes = self.indexes()

        def read(V: Values) -> float:
            return V[array_key(name, [i(V) for i in indexes])]
        return Opaque(f"{name}[...]", read)

    def arguments(self) -> list[Node]:
        self.tokens.expect("(")
        if self.tokens.take(")"):
            return []
        found = [self.condition()]
        while self.tokens.take(","):
            found.append(self.condition())
        self.tokens.expect(")")
        return found

    def function(self, name: str) -> Node:
        if name in _LOC_FUNCTIONS:
            return self.location_function(name)
        if name == "LAST":
            return self.last()
        if name in _STRING_NUMBERS or name in _BYTE_FORMATS:
            return self.string_number(name)
        if name == "DEFINED":
            return self.defined()
        if name in ("PARAMETER", "SWITCH"):
            self.tokens.expect("(")
            token = self.tokens.peek()
            if token is None or token[0] != "name":
                raise ExprError(f"{name}(...) needs a name")
            self.tokens.pos += 1
            self.tokens.expect(")")
            return self.setting(name, token[1])
        args = [a.closure() for a in self.arguments()]
        if name == "BITS":  # BITS(first {, count}): those signals as a number, the first the lowest bit
            get_bits = self.get_machine("BITS()")
            if not 1 <= len(args) <= 2:
                raise ExprError("BITS takes the first signal and a count: BITS(first, count)")
            first, count = args[0], args[1] if len(args) == 2 else (lambda V: 1.0)
            return Opaque("BITS(...)", lambda V: _bits(get_bits(), int(first(V)), int(count(V))))
        if name in ("SIG", "TIMER"):
            get = self.get_machine(f"{name}()")
            if not args or (name == "TIMER" and len(args) != 1):
                raise ExprError(f"{name} needs {'one' if name == 'TIMER' else 'a'} signal number")
            if name == "SIG":
                return Opaque("SIG(...)", lambda V: get().sig(*(a(V) for a in args)))
            timer = args[0]
            return Opaque("TIMER(...)", lambda V: get().timer(timer(V)))
        if name not in _MATH:
            if name in _CONTROLLER_ONLY:
                raise ControllerFunction(f"{name} is a V+ function of {_CONTROLLER_ONLY[name]}, "
                                         "which the simulator does not have")
            raise ExprError(f"{name} is not a V+ function the simulator knows")
        low, high, how = _MATH[name]
        if not low <= len(args) <= high:
            raise ExprError(f"{name} takes {low}{'' if low == high else ' or more'} argument(s)")
        return Opaque(f"{name}(...)", lambda V: float(how(*(a(V) for a in args))))

    def last(self) -> Node:
        """LAST(a[]): the highest index of array a that has a value (-1: none); also $a[], loc[]."""
        self.tokens.expect("(")
        token = self.tokens.peek()
        if token is None or token[0] != "name" or token[1].startswith("#"):
            raise ExprError("LAST needs an array: LAST(name[])")
        self.tokens.pos += 1
        self.tokens.expect("[")
        self.tokens.expect("]")
        self.tokens.expect(")")
        name = token[1]
        if name.startswith("$"):
            get = self.get_machine(f"LAST({name}[])")
            return Opaque(f"LAST({name}[])", lambda V: _last(get().strings, name))
        if self.machine is None:
            return Opaque(f"LAST({name}[])", lambda V: _last(V, name))
        sim = self.machine.sim
        return Opaque(f"LAST({name}[])", lambda V: max(_last(V, name), _last(sim.locations, name)))

    def string_number(self, name: str) -> Node:
        """LEN($s), VAL($s), ASC($s {, i}): numbers of a string."""
        self.tokens.expect("(")
        text = self.string()
        index = self.sum().closure() if self.tokens.take(",") else None
        self.tokens.expect(")")
        if name in _BYTE_FORMATS:
            return Opaque(f"{name}(...)", lambda V: _from_bytes(name, text(V), index(V) if index is not None else 1.0))
        if name == "LEN":
            return Opaque("LEN(...)", lambda V: float(len(text(V))))
        if name == "VAL":
            return Opaque("VAL(...)", lambda V: _val(text(V)))
        return Opaque("ASC(...)", lambda V: _asc(text(V), index(V) if index is not None else 1.0))

    def defined(self) -> Node:
        """DEFINED(x), DEFINED($s), DEFINED(loc), DEFINED(#p), DEFINED(a[i]): TRUE once it has a value."""
        self.tokens.expect("(")
        token = self.tokens.peek()
        if token is None or token[0] != "name":
            raise ExprError("DEFINED needs a variable: DEFINED(name)")
        self.tokens.pos += 1
        name = token[1]
        indexes = self.indexes() if self._peek_is("[") else []
        self.tokens.expect(")")

        def key(V: Values) -> str:
            return array_key(name, [i(V) for i in indexes]) if indexes else name

        machine = self.machine
        if name[0] in "$#":
            get = self.get_machine(f"DEFINED({name})")
            return Opaque(f"DEFINED({name})", lambda V: _truth(
                key(V) in (get().strings if name[0] == "$" else get().precision)))
        if machine is None:
            return Opaque(f"DEFINED({name})", lambda V: _truth(key(V) in V))
        sim = machine.sim
        return Opaque(f"DEFINED({name})", lambda V: _truth(key(V) in V or key(V) in sim.locations))

    def _peek_is(self, value: str) -> bool:
        token = self.tokens.peek()
        return token is not None and token[1] == value

    def setting(self, kind: str, name: str) -> Node:
        get = self.get_machine(f"{kind}({name})")
        if kind == "SWITCH":
            return Opaque(f"SWITCH({name})", lambda V: _truth(get().switches.get(name, False)))

        return Opaque(f"PARAMETER({name})", lambda V: get().parameter(name))

    def location_function(self, name: str) -> Node:
        self.tokens.expect("(")
        first = self.location()
        if name == "DISTANCE":
            self.tokens.expect(",")
            second = self.location()
            self.tokens.expect(")")
            return Opaque("DISTANCE(...)", lambda V: distance(first(V), second(V)))
        self.tokens.expect(")")
        if name == "INRANGE":  # 0: reachable; else why not (Machine.inrange)
            get = self.get_machine("INRANGE()")
            return Opaque("INRANGE(...)", lambda V: get().inrange(first(V)))
        axis = "XYZ".index(name[1])
        return Opaque(f"{name}(...)", lambda V: first(V).xyz[axis])

    # -- locations ------------------------------------------------------------------
    def location(self) -> LocFn:
        """A compound a:b:c of location terms."""
        terms = [self.location_term()]
        while self.tokens.take(":"):
            terms.append(self.location_term())
        if len(terms) == 1:
            return terms[0]

        def compound(V: Values) -> Transform:
            result = terms[0](V)
            for term in terms[1:]:
                result = result @ term(V)
            return result
        return compound

    def location_term(self) -> LocFn:
        token = self.tokens.peek()
        if token is None:
            raise ExprError("missing location")
        if self.tokens.take("("):
            inner = self.location()
            self.tokens.expect(")")
            return inner
        kind, value = token[0], token[1]
        if kind != "name" or value.startswith("$"):
            raise ExprError(f"{value!r} is not a location")
        self.tokens.pos += 1
        after = self.tokens.peek()
        if after is not None and after[1] == "(":
            return self.location_call(value)
        get = self.get_machine(f"location {value}")
        if after is not None and after[1] == "[" and not value.startswith("#"):  # loc[i]: an array element
            indexes = self.indexes()
            return lambda V: get().location(array_key(value, [i(V) for i in indexes]))
        if value == "HERE":
            return lambda V: _here(get())
        if value == "NULL":
            return lambda V: translation()
        if len(value.lstrip("#")) > MAX_VNAME:
            raise ExprError(f"location name {value} is longer than {MAX_VNAME} characters")
        return lambda V: get().location(value)

    def precision(self) -> Callable[[Values], tuple[float, ...]]:
        """A precision point: #name, or #PPOINT(j1, ..., j6) (omitted angles are 0)."""
        token = self.tokens.peek()
        if token is None or token[0] != "name" or not token[1].startswith("#"):
            raise ExprError("expected a precision point (#name or #PPOINT(j1, ..., j6))")
        self.tokens.pos += 1
        name = token[1]
        if name == "#PPOINT":
            args = [a.closure() for a in self.arguments()]
            if not 1 <= len(args) <= 6:
                raise ExprError("#PPOINT takes one to six joint angles")
            return lambda V: tuple([*(float(a(V)) for a in args), *[0.0] * (6 - len(args))])
        get = self.get_machine(f"precision point {name}")
        return lambda V: get().point(name)

    def location_call(self, name: str) -> LocFn:
        if name == "#PPOINT":
            self.tokens.pos -= 1
            joints = self.precision()
            get = self.get_machine("#PPOINT")
            return lambda V: Transform.of(get().pose_location(joints(V)))
        if name in ("INVERSE",):
            self.tokens.expect("(")
            inner = self.location()
            self.tokens.expect(")")
            return lambda V: inverse(inner(V))
        if name == "FRAME":
            self.tokens.expect("(")
            points = [self.location()]
            for _ in range(3):
                self.tokens.expect(",")
                points.append(self.location())
            self.tokens.expect(")")
            return lambda V: frame(*(p(V) for p in points))
        if name == "NORM":
            self.tokens.expect("(")
            inner = self.location()
            self.tokens.expect(")")
            return lambda V: normalized(inner(V))
        if name == "SCALE":  # SCALE(l BY factor): the position scaled, the orientation kept
            self.tokens.expect("(")
            scaled = self.location()
            if not self._by():
                raise ExprError("expected SCALE(<location> BY <factor>)")
            factor = self.sum().closure()
            self.tokens.expect(")")
            return lambda V: scale(scaled(V), factor(V))
        if name == "SHIFT":
            self.tokens.expect("(")
            base = self.location()
            if not self.tokens.take("BY"):
                token = self.tokens.peek()
                if token is None or token[1] != "BY":
                    raise ExprError("expected SHIFT(<location> BY dx, dy, dz)")
                self.tokens.pos += 1
            offsets = [self.sum().closure()]
            while self.tokens.take(","):
                offsets.append(self.sum().closure())
            self.tokens.expect(")")
            if len(offsets) > 3:
                raise ExprError("SHIFT takes at most three increments")
            return lambda V: shift(base(V), *(o(V) for o in offsets))
        makers: dict[str, tuple[int, Callable[..., Transform]]] = {
            "TRANS": (6, trans), "RX": (1, rx), "RY": (1, ry), "RZ": (1, rz),
        }
        if name not in makers:
            raise ExprError(f"{name} is not a V+ transformation function")
        most, make = makers[name]
        args = [a.closure() for a in self.arguments()]
        if len(args) > most or (most == 1 and len(args) != 1):
            raise ExprError(f"{name} takes {most if most == 1 else 'up to ' + str(most)} argument(s)")
        if name == "TRANS" and len(args) <= 3:
            make = translation  # no angles: an offset, no rotation
        return lambda V: make(*(a(V) for a in args))

    def _by(self) -> bool:
        """The keyword BY (a name token) is next: taken."""
        token = self.tokens.peek()
        if token is None or token[1] != "BY":
            return False
        self.tokens.pos += 1
        return True

    # -- strings --------------------------------------------------------------------
    def string(self) -> StrFn:
        parts = [self.string_term()]
        while self.tokens.take("+"):
            parts.append(self.string_term())
        return lambda V: "".join(p(V) for p in parts)

    def string_term(self) -> StrFn:
        token = self.tokens.peek()
        if token is None:
            raise ExprError("missing string")
        kind, value = token[0], token[1]
        self.tokens.pos += 1
        if kind == "string":
            return lambda V: value
        if kind == "name" and value.startswith("$"):
            after = self.tokens.peek()
            if after is not None and after[1] == "(":
                return self.string_function(value)
            get = self.get_machine(f"string {value}")
            if after is not None and after[1] == "[":  # $a[i]: one string of an array
                indexes = self.indexes()
                return lambda V: get().string(array_key(value, [i(V) for i in indexes]))
            return lambda V: get().string(value)
        raise ExprError(f"{value!r} is not a string (\"text\" or $name)")

    def string_function(self, name: str) -> StrFn:
        if name == "$ENCODE":
            from valterm.core.val.typeout import format_number

            self.tokens.expect("(")
            start = self.tokens.items[self.tokens.pos][2] if self.tokens.peek() else len(self.tokens.text)
            depth, end_index = 1, self.tokens.pos
            while end_index < len(self.tokens.items):
                value = self.tokens.items[end_index][1]
                depth += value == "("
                depth -= value == ")"
                if depth == 0:
                    break
                end_index += 1
            if depth:
                raise ExprError("missing ')' after $ENCODE(")
            inner = self.tokens.text[start:self.tokens.items[end_index][2]]
            self.tokens.pos = end_index + 1
            try:
                items = output_list(inner, self.machine)
            except ValueError as error:  # a bad format: the error names $ENCODE, not TYPE
                raise ExprError(str(error).replace("TYPE:", "$ENCODE:", 1)) from None
            del format_number
            return lambda V: render_output(items, V)
        if name in ("$MID", "$LEFT"):
            return self.substring(name)
        if name == "$ERROR":  # its codes come from the devices and tasks the simulator does not have
            raise ControllerFunction("$ERROR is a V+ function of the controller's table of error messages, "
                                     "which the simulator does not have")
        # the name before its arguments: a string argument read as a number named the wrong error
        if name != "$CHR" and name[1:] not in _BYTE_FORMATS:
            raise ExprError(f"{name} is not a V+ string function the simulator knows")
        args = [a.closure() for a in self.arguments()]
        if len(args) != 1:
            raise ExprError(f"{name} takes one value: {name}(value)")
        if name == "$CHR":
            return lambda V: chr(int(args[0](V)))
        return lambda V: _to_bytes(name, args[0](V))

    def substring(self, name: str) -> StrFn:
        """$LEFT($s, n): the first n characters; $MID($s, first {, n}): n from the first-th (1-based)."""
        self.tokens.expect("(")
        text = self.string()
        numbers = []
        while self.tokens.take(","):
            numbers.append(self.sum().closure())
        self.tokens.expect(")")
        if name == "$LEFT":
            if len(numbers) != 1:
                raise ExprError("$LEFT takes a string and a count: $LEFT($s, n)")
            count = numbers[0]
            return lambda V: text(V)[:max(0, int(count(V)))]
        if len(numbers) not in (1, 2):
            raise ExprError("$MID takes a string, the first character and a count: $MID($s, first, n)")
        first = numbers[0]
        length = numbers[1] if len(numbers) == 2 else None

        def mid(V: Values) -> str:
            start = max(0, int(first(V)) - 1)
            whole = text(V)
            return whole[start:] if length is None else whole[start:start + max(0, int(length(V)))]
        return mid


def _here(machine: Machine) -> Transform:
    location = machine.sim.where()
    from valterm.core.kinematics import Location

    transform = Transform.of(Location(location.xyz, location.oat))
    return transform if machine.tool is None else transform @ machine.tool


def _finish(compiler: _Compiler) -> None:
    compiler.tokens.done()


def compile_number(text: str, machine: Machine | None = None) -> Expr:
    """A numeric V+ expression (conditions included: TRUE is -1, FALSE 0)."""
    if not text.strip():
        raise ExprError("missing value")
    compiler = _Compiler(text, machine)
    node = compiler.condition()
    _finish(compiler)
    fn: Fn = node.closure()
    const = None
    if isinstance(node, Num):
        const = node.value
    return Expr(node, tuple(compiler.names), text.strip(), const, fn)


def compile_location(text: str, machine: Machine | None = None) -> LocFn:
    compiler = _Compiler(text, machine)
    fn = compiler.location()
    _finish(compiler)
    return fn


def compile_precision(text: str, machine: Machine | None = None) -> Callable[[Values], tuple[float, ...]]:
    """``#name`` or ``#PPOINT(j1, ..., j6)``: six joint angles (degrees)."""
    compiler = _Compiler(text, machine)
    fn = compiler.precision()
    _finish(compiler)
    return fn


def compile_string(text: str, machine: Machine | None = None) -> StrFn:
    compiler = _Compiler(text, machine)
    fn = compiler.string()
    _finish(compiler)
    return fn


def is_string_expression(text: str) -> bool:
    stripped = text.strip()
    return stripped.startswith(('"', "$"))


# -- TYPE output lists with V+ values (strings included) --------------------------------

OutputItem = tuple[str, "Fn | StrFn | None", str]  # literal, value, format


def output_list(text: str, machine: Machine | None) -> list[tuple[str, Callable[[Values], object] | None, str]]:
    """TYPE / $ENCODE items: quoted text, $strings, numeric values, formats."""
    from valterm.core.val.typeout import parse_items

    def value(word: str) -> tuple[str, Callable[[Values], object]]:
        if word.startswith("$"):
            try:
                return ("S", compile_string(word, machine))
            except ExprError:
                if not any(op in word for op in ("=", "<", ">")):
                    raise
                # $a == $b: a comparison of strings is a number
        return ("", compile_number(word, machine).function())

    words, joined = _join_concatenations(text)

    def item_value(word: str) -> tuple[str, Callable[[Values], object]]:
        return ("S", compile_string(joined[word], machine)) if word in joined else value(word)

    out: list[tuple[str, Callable[[Values], object] | None, str]] = []
    for item in parse_items(words, item_value):
        if item.expr is None:
            out.append((item.text, None, item.fmt))
        else:
            assert isinstance(item.expr, tuple)
            kind, fn = item.expr
            out.append((kind, fn, item.fmt))
    return out


def _join_concatenations(text: str) -> tuple[str, dict[str, str]]:
    """TYPE "x: "+$ENCODE(a): a string expression joined by + is one item (V+ concatenates).

    The output list is rewritten with a placeholder name for each such item, so the
    items, formats and their order are decoded as before."""
    from valterm.core.val.typeout import split_items

    groups: list[str] = []
    for word in split_items(text):
        glued = word.startswith(("+$", '+"')) or (
            groups and groups[-1].endswith("+") and word.startswith(("$", '"')))
        if glued and groups:
            groups[-1] += word
        else:
            groups.append(word)
    joined: dict[str, str] = {}
    for index, group in enumerate(groups):
        if group.startswith(("$", '"')) and len(split_items(group)) > 1:
            joined[f"$_CAT{index}"] = group
            groups[index] = f"$_CAT{index}"
    return ", ".join(groups), joined


def render_output(items: list[tuple[str, Callable[[Values], object] | None, str]], V: Values) -> str:
    from valterm.core.val.typeout import format_number

    parts: list[str] = []
    after_number = False
    for literal, fn, fmt in items:
        if fn is None:
            parts.append(literal)
        elif literal == "S":
            parts.append(str(fn(V)))
        else:
            value = fn(V)
            assert isinstance(value, (int, float))
            text = format_number(float(value), fmt)
            if after_number and fmt == "D" and not text.startswith(" "):
                text = " " + text  # V+'s default format never runs two numbers together
            parts.append(text)
        after_number = fn is not None and literal != "S"
    return "".join(parts)


def is_name(text: str) -> bool:
    return bool(_NAME.fullmatch(text.strip().upper()))


__all__ = [
    "NAME", "Not", "array_key", "compile_location", "compile_number", "compile_precision", "compile_string",
    "is_name", "is_string_expression", "output_list", "render_output",
]
