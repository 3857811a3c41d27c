"""The ``v+`` dialect: the VAL-II of real controllers (Adept V+), decoded and built.

The 1985 dialect reads its statements from COMMAND.DAT; V+ statements do not fit those
shapes (``FOR i = 1 TO n STEP 2``, ``CASE x OF``, ``VALUE 1, 2:``, ``CALL p(a, b)``,
``MOVET loc, TRUE``), so this module decodes them itself (``parse_vplus``) into the same
``Statement`` the compiler and the builders use, and adds builders (``VPLUS_BUILDERS``).
Arguments are kept as text, checked here (``machine=None``) and compiled again by the
builder against the interpreter's ``Machine``.

V+ semantics (Adept V+ Language Reference) where the thesis is silent:
- TRUE is -1, FALSE 0; a condition is true when not 0;
- ``FOR`` evaluates its limits each pass, the body is skipped when the start is past the end;
- ``CASE`` runs the first VALUE list holding the value, else ANY, else nothing;
- ``CALL p(a, b)``: a plain variable, location or string argument is passed by reference
  (the caller sees what the subroutine leaves in its parameter), anything else by value;
  parameters and AUTO/LOCAL variables are the subroutine's own, saved and restored around
  the call, so recursion works;
- ``BREAK`` waits for the motion to finish: simulated motions always have;
- ``SPEED n`` stays in force (as in the 1985 dialect), ``ALWAYS`` is accepted;
- ``MOVET loc, hand`` / ``MOVEST``: the motion, then the hand opened (hand not 0) or closed;
- ``REACT``/``REACTI n, prog``: when signal n changes to the wanted state during a motion,
  WAIT, DELAY or SIGNAL step, prog is CALLed after that step (once; ``IGNORE`` disarms);
- locations are X Y Z yaw pitch roll (``core/transform.py``): TRANS, DECOMPOSE, WHERE;
- ``WAIT cond`` lets simulated time pass until cond holds (``first_true``);
- ``EXIT n`` / ``NEXT n`` leave or continue the n-th enclosing FOR, WHILE or DO loop.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import TypeVar

import numpy as np

from valterm.core.errors import ValtermError
from valterm.core.events import Delay, Error, Message, TypeOut, Where
from valterm.core.files.commandfile import CommandSpec, default_commands
from valterm.core.kinematics import CONFIG_WORDS, Location
from valterm.core.transform import Transform, convert_orientation
from valterm.core.val import builders as b85
from valterm.core.val.builders import Build, Builder
from valterm.core.val.compiler import Analysis
from valterm.core.val.expr import ControllerFunction, ExprError, Fn, Values
from valterm.core.val.machine import TICK, Machine, MachineError
from valterm.core.val.ops import (
    Action,
    Assign,
    Branch,
    CompiledProgram,
    Control,
    Events,
    Op,
    ProgramError,
    Run,
    RunStop,
)
from valterm.core.val.parser import (
    ASSIGN,
    MAX_LABEL,
    ControllerOnly,
    Statement,
    ValSyntaxError,
    strip_comment,
)
from valterm.core.val.typeout import NO_LINE_END
from valterm.core.val.vexpr import (
    NAME,
    array_key,
    compile_location,
    compile_number,
    compile_precision,
    compile_string,
    output_list,
    render_output,
)

T = TypeVar("T")
DIALECT = "v+"
MAX_CALL_DEPTH = 20
WAIT_POLL = 0.1  # seconds between two looks at a WAIT condition (simulated time)
MAJOR_CYCLE = TICK  # seconds: V+'s trajectory cycle, the time a WAIT with no condition lets pass
NEVER_AFTER = 1e9  # seconds: a WAIT with no run limit looks no further (the clock's own horizon)

_N = NAME
_ASSIGN = re.compile(rf"^(?:(SET)\s+)?([$#]?{_N})\s*(\[(.*)\])?\s*=(?!=)\s*(.*)$", re.DOTALL)
_FOR = re.compile(rf"^FOR\s+({_N})\s*=\s*(.+?)\s+TO\s+(.+?)(?:\s+STEP\s+(.+))?$", re.DOTALL)
_CASE = re.compile(r"^CASE\s+(.+?)\s+OF$", re.DOTALL)
_VALUE = re.compile(r"^VALUE\s+(.+?)\s*:$", re.DOTALL)
_WHILE = re.compile(r"^WHILE\s+(.+?)\s+DO$", re.DOTALL)
_IF_THEN = re.compile(r"^IF\s+(.+?)\s+THEN$", re.DOTALL)
_IF_GOTO = re.compile(r"^IF\s+(.+?)\s+GOTO\s+(\d+)$", re.DOTALL)
_CALL = re.compile(rf"^CALL\s+({_N})\s*(?:\((.*)\))?$", re.DOTALL)
_WORD = re.compile(rf"^({_N})\s*(.*)$", re.DOTALL)
_DECOMPOSE = re.compile(rf"^DECOMPOSE\s+({_N})\s*\[\s*(.*?)\s*\]\s*=\s*(.+)$", re.DOTALL)
_TIMER = re.compile(r"^TIMER\s+(.+?)\s*=\s*(.+)$", re.DOTALL)
_PARAMETER = re.compile(rf"^PARAMETER\s+({_N})\s*=\s*(.+)$", re.DOTALL)
_BITS = re.compile(r"^BITS\s+(.+?)\s*=\s*(.+)$", re.DOTALL)
_DECLARE_TYPES = ("REAL", "DOUBLE", "LOC", "PRECISION", "TRANS")

_NO_ARGS = ("ELSE", "END", "DO", "RETURN", "BREAK", "READY", "ALIGN", "WHERE", "STATUS", "ANY",
            *CONFIG_WORDS)
_TEXT_ARGS = ("STOP", "HALT", "PAUSE")
_ONE_VALUE = ("DELAY", "DEPART", "DEPARTS")
_HAND = ("OPEN", "OPENI", "CLOSE", "CLOSEI", "RELAX", "RELAXI")
_MOTIONS = ("MOVE", "MOVES", "MOVET", "MOVEST")
# How the real arm accelerates and settles: the simulated motion is the same (accepted, no effect)
_TUNING = ("ACCEL", "DURATION", "COARSE", "FINE", "NONULL", "NULL", "SINGLE", "MULTIPLE")
COMMANDS = (*_NO_ARGS, *_TEXT_ARGS, *_ONE_VALUE, *_HAND, *_MOTIONS, "APPRO", "APPROS", "DRIVE", "DRAW",
            "FOR", "CASE", "VALUE", "WHILE", "UNTIL", "IF", "GOTO", "CALL", "CALLS", "AUTO", "LOCAL", "GLOBAL",
            "SPEED", "PARAMETER", "HERE", "SET", "DECOMPOSE", "TOOL", "TYPE", "SIGNAL", "WAIT",
            "WAIT.EVENT", "REACT", "REACTI", "IGNORE", "TIMER", "ENABLE", "DISABLE", "BASE", "EXIT", "NEXT",
            "BITS",
            *_TUNING)


def _spec(name: str) -> CommandSpec:
    return default_commands().lookup(name)


def _check(kind: str, text: str) -> str:
    """The text, after checking it compiles as a number, a location or a string."""
    try:
        if kind == "N":
            compile_number(text)
        elif kind == "L":
            compile_location(text)
        else:
            compile_string(text)
    except ControllerFunction as error:
        raise ControllerOnly(str(error)) from None
    except (ExprError, ValtermError, ValueError) as error:
        raise ValSyntaxError(str(error)) from None
    return text.strip()


def split_top(text: str) -> list[str]:
    """Comma-separated parts outside brackets and quotes."""
    parts, depth, quoted, start = [], 0, False, 0
    for i, ch in enumerate(text):
        if ch == '"':
            quoted = not quoted
        elif quoted:
            continue
        elif ch in "([":
            depth += 1
        elif ch in ")]":
            depth -= 1
        elif ch == "," and depth == 0:
            parts.append(text[start:i].strip())
            start = i + 1
    parts.append(text[start:].strip())
    return parts if any(parts) else []


def _value_kind(text: str) -> str:
    """N (number) or L (location) for a right-hand side: numbers first."""
    try:
        compile_number(text)
        return "N"
    except (ExprError, MachineError) as as_number:
        try:
            compile_location(text)
        except (ExprError, MachineError):
            kind = ControllerFunction if isinstance(as_number, ControllerFunction) else ExprError
            raise kind(str(as_number)) from None  # the reason it is not a number
        return "L"


def parse_vplus(text: str) -> Statement:
    """One V+ statement (no label; a ``;`` comment is dropped) or ValSyntaxError."""
    original = strip_comment(text, quoted=True)
    upper = upper_outside_quotes(original)  # names are case-insensitive; quoted text keeps its case
    if not upper:
        return Statement("", (), "")
    try:
        return _decode(upper, original)
    except (ControllerFunction, ControllerOnly) as error:  # real V+ takes it: a warning in pass 1
        raise ControllerOnly(_named(upper, str(error))) from None
    except (ExprError, ValSyntaxError, ValtermError, ValueError) as error:
        raise ValSyntaxError(_named(upper, str(error))) from None


def upper_outside_quotes(text: str) -> str:
    """The text with everything but quoted text in upper case."""
    parts = text.split('"')
    return '"'.join(part if index % 2 else part.upper() for index, part in enumerate(parts))


def _named(upper: str, message: str) -> str:
    """A step's error says which statement it is about (``SET: ...``, ``TYPE: ...``)."""
    match = _ASSIGN.match(upper)
    if match is not None and match.group(2) not in ("TIMER", "PARAMETER", "DECOMPOSE"):
        word = "SET" if match.group(1) else f"ASSIGNMENT TO {match.group(2)}"
    else:
        word = upper.split()[0].split("(")[0]
        if not re.fullmatch(rf"[$#]?{_N}", word):
            return message
    if message.upper().startswith((word + ":", word + " ")):
        return message
    return f"{word}: {message}"


# V+ statements of the controller's devices and tasks, which the simulator does not have:
# `check` names them as such (a real controller accepts them; a program using them cannot run here).
_DEVICE_IO = ("ATTACH", "DETACH", "READ", "WRITE", "GETC", "FOPEN", "FOPENR", "FOPENW", "FOPENA", "FOPEND",
              "FCLOSE", "FCMND", "FEMPTY", "FSEEK", "SETDEVICE")
_TASKS = ("EXECUTE", "ABORT", "KILL", "CYCLE.END", "PRIME", "SELECT")
# SELECT ROBOT = n; ATTACH / DETACH of the robot (no logical unit, or unit 0)
_SELECT_ROBOT = re.compile(r"^SELECT\s+ROBOT\s*=\s*(.+)$", re.DOTALL)
_ROBOT_ATTACH = re.compile(r"^(ATTACH|DETACH)\s*(?:\(\s*0?\s*\))?\s*$")


def _decode(upper: str, original: str) -> Statement:
    for decoder in (_structure, _assignment, _command, _robot_selection):
        found = decoder(upper, original)
        if found is not None:
            return found
    word = upper.split()[0]
    if word in _DEVICE_IO:
        raise ControllerOnly(f"{word} IS A V+ STATEMENT FOR THE CONTROLLER'S I/O DEVICES (DISK, NETWORK, "
                             "SERIAL LINES), WHICH THE SIMULATOR DOES NOT HAVE")
    if word in _TASKS:
        raise ControllerOnly(f"{word} IS A V+ STATEMENT FOR OTHER PROGRAM TASKS OR ROBOTS, WHICH THE "
                             "SIMULATOR DOES NOT HAVE (ONE TASK, ONE ROBOT)")
    raise ValSyntaxError(f"{word} IS NOT A V+ INSTRUCTION THE SIMULATOR KNOWS")


def _robot_selection(upper: str, original: str) -> Statement | None:
    """SELECT ROBOT = n (the simulator's robot is robot 1); ATTACH () / DETACH () of the robot."""
    if match := _SELECT_ROBOT.match(upper):
        return Statement("SELECT", (_check("N", match.group(1).strip()),), original)
    if match := _ROBOT_ATTACH.match(upper):
        return Statement(match.group(1), (), original)
    return None


def _structure(upper: str, original: str) -> Statement | None:
    if match := _FOR.match(upper):
        var, start, stop, step = match.groups()
        return Statement("FOR", (var, _check("N", start), _check("N", stop),
                                 _check("N", step) if step else None), original)
    if match := _CASE.match(upper):
        return Statement("CASE", (_check("N", match.group(1)),), original)
    if match := _VALUE.match(upper):
        return Statement("VALUE", tuple(_check("N", v) for v in split_top(match.group(1))), original)
    if re.fullmatch(r"ANY\s*:?", upper):
        return Statement("ANY", (), original)
    if match := _WHILE.match(upper):
        return Statement("WHILE", (_check("N", match.group(1)),), original)
    if upper.startswith("WHILE"):
        raise ValSyntaxError("WHILE: EXPECTED WHILE <condition> DO")
    if match := _IF_GOTO.match(upper):
        label = int(match.group(2))
        if label > MAX_LABEL:
            raise ValSyntaxError(f"step label {label} is too large (at most {MAX_LABEL})")
        return Statement("IF", (_check("N", match.group(1)), label), original, _spec("IF"), 1)
    if match := _IF_THEN.match(upper):
        return Statement("IF", (_check("N", match.group(1)),), original, _spec("IF"), 0)
    if upper.startswith("IF ") or upper == "IF":
        raise ValSyntaxError("IF: EXPECTED IF <condition> THEN (OR IF <condition> GOTO <label>)")
    if upper.startswith("UNTIL"):
        return Statement("UNTIL", (_check("N", upper[5:]),), original)
    if match := re.fullmatch(r"(EXIT|NEXT)(?:\s+(\d+))?", upper):
        count = int(match.group(2) or 1)
        if count < 1:
            raise ValSyntaxError(f"{match.group(1)}: THE LOOP COUNT IS 1 OR MORE")
        return Statement(match.group(1), (count,), original)
    if match := re.fullmatch(r"GOTO\s+(\d+)", upper):
        return Statement("GOTO", (int(match.group(1)),), original)
    if match := _CALL.match(upper):
        return Statement("CALL", (match.group(1), _call_arguments(match.group(2) or "")), original)
    if match := re.fullmatch(r"CALLS\s+(.+)", upper, re.DOTALL):
        name, args = _calls_parts(match.group(1).strip())
        return Statement("CALLS", (_check("S", name), _call_arguments(args)), original)
    return None


def _call_arguments(text: str) -> tuple[str, ...]:
    args = tuple(split_top(text))
    for arg in args:
        if arg and not arg.endswith("[]"):
            _argument_kind(arg)
    return args


def _calls_parts(text: str) -> tuple[str, str]:
    """CALLS $name(a, b): the string naming the program, and the argument list (the last
    bracketed group, when what is before it is a string by itself)."""
    if text.endswith(")"):
        depth, quoted = 0, False
        for index in range(len(text) - 1, -1, -1):
            ch = text[index]
            quoted = quoted != (ch == '"')
            if quoted:
                continue
            depth += (ch == ")") - (ch == "(")
            if depth == 0:
                name = text[:index].strip()
                try:
                    compile_string(name)
                except (ExprError, ValtermError):
                    break  # $MID($a, 1, 3): the brackets are the string's own
                return name, text[index + 1:-1]
    return text, ""


def _argument_kind(text: str) -> str:
    if text.startswith(("$", '"')):
        return _check("S", text) and "S"
    try:
        return _value_kind(text)
    except ExprError as error:
        raise ValSyntaxError(f"CALL argument {text}: {error}") from None


def _assignment(upper: str, original: str) -> Statement | None:
    match = _ASSIGN.match(upper)  # a name right before '=' is assigned to, whatever word it is
    if match is None:
        return None
    is_set, target, _brackets, index, value = match.groups()
    value = original[match.start(5):]  # quoted text keeps its case
    if not value.strip():
        raise ValSyntaxError(f"{target}= needs a value")
    if target in ("TIMER", "PARAMETER", "DECOMPOSE", "BITS"):
        return None
    indexes = tuple(_check("N", i) for i in split_top(index)) if index is not None else ()
    if target.startswith("$"):
        return Statement(ASSIGN, ("S", target, indexes, _check("S", value)), original)
    if target.startswith("#"):
        try:
            compile_precision(value)
        except ExprError as error:
            raise ValSyntaxError(f"{target}: {error}") from None
        return Statement(ASSIGN, ("P", target, indexes, value.strip()), original)
    kind = "L" if is_set else _value_kind(value)
    if kind == "L":
        _check("L", value)
    return Statement(ASSIGN, (kind, target, indexes, value.strip()), original)


def _command(upper: str, original: str) -> Statement | None:
    if match := _BITS.match(upper):  # BITS first, count = value
        signals = split_top(match.group(1))
        _count("BITS", signals, 1, 2, "<first signal>{, <count>} = <value>")
        return Statement("BITS", (*(_check("N", t) for t in signals), _check("N", match.group(2))), original)
    for special in (_DECOMPOSE, _TIMER, _PARAMETER):
        if match := special.match(upper):
            groups = match.groups()
            if special is _DECOMPOSE:
                return Statement("DECOMPOSE", (groups[0], _check("N", groups[1] or "0"),
                                               _check("L", groups[2])), original)
            if special is _TIMER:
                number = compile_number(_check("N", groups[0])).const
                if number is not None and int(number) <= 0:
                    raise ValSyntaxError(f"TIMER {int(number)} IS THE SYSTEM CLOCK'S: IT CANNOT BE SET "
                                         "(TIMERS 1 AND UP CAN)")
                return Statement("TIMER", (_check("N", groups[0]), _check("N", groups[1])), original)
            return Statement("PARAMETER", (groups[0], _check("N", groups[1])), original)
    match = _WORD.match(upper)
    if match is None:
        return None
    word, rest = match.group(1), match.group(2).strip()
    if word not in COMMANDS:
        return None
    parts = split_top(rest)
    if word in _NO_ARGS:
        if rest:
            raise ValSyntaxError(f"{word} TAKES NO ARGUMENTS")
        return Statement(word, (), original)
    if word in _TEXT_ARGS:
        return Statement(word, (original[len(word):].strip() or None,), original)
    return _with_arguments(word, rest, parts, original)


def _count(word: str, parts: list[str], low: int, high: int, usage: str) -> None:
    if not low <= len(parts) <= high or any(not p for p in parts[:low]):
        raise ValSyntaxError(f"{word}: EXPECTED {word} {usage}")


def _with_arguments(word: str, rest: str, parts: list[str], original: str) -> Statement:
    if word in _ONE_VALUE:
        _count(word, parts, 1, 1, "<value>")
        return Statement(word, (_check("N", parts[0]),), original)
    if word in _HAND:
        _count(word, parts, 0, 1, "{<value>}")
        return Statement(word, (_check("N", parts[0]) if parts else None,), original)
    if word in _MOTIONS:
        with_hand = word.endswith("T")
        _count(word, parts, 2 if with_hand else 1, 2 if with_hand else 1,
               "<location>, <hand>" if with_hand else "<location>")
        return Statement(word, (_check("L", parts[0]), _check("N", parts[1]) if with_hand else None), original)
    if word in ("APPRO", "APPROS"):
        _count(word, parts, 2, 2, "<location>, <distance>")
        return Statement(word, (_check("L", parts[0]), _check("N", parts[1])), original)
    if word in ("DRIVE", "DRAW", "BASE"):
        _count(word, parts, 3 if word == "DRIVE" else 0, 4 if word == "BASE" else 3, "<values>")
        values = tuple(_check("N", p) if p else None for p in parts)
        if word == "DRIVE":
            joint = compile_number(values[0] or "0").const
            if joint is not None and (joint != int(joint) or not 1 <= joint <= 6):
                raise ValSyntaxError(f"DRIVE: JOINT NUMBER {joint:g} IS NOT 1 TO 6")
        return Statement(word, values, original)
    if word in ("AUTO", "LOCAL", "GLOBAL"):
        return Statement("AUTO" if word != "GLOBAL" else "GLOBAL", (_declared(word, rest),), original)
    if word in _TUNING:
        profile = re.match(r"\s*\(([^()]*)\)\s*(?=[^,\s])", rest) if word == "ACCEL" else None
        if profile is not None:  # ACCEL (profile) acc, dec: the profile number is checked, not modelled
            _check("N", profile.group(1))
            rest = rest[profile.end():]
        tuning = [p for p in split_top(re.sub(r"\bALWAYS\s*$", "", rest).strip()) if p]
        _count(word, tuning, 0, 2 if word in ("ACCEL", "FINE", "COARSE") else 1, "{<value>} {ALWAYS}")
        return Statement(word, tuple(_check("N", v) for v in tuning), original)
    if word == "SPEED":
        return _speed_statement(rest, original)
    if word in ("HERE", "TOOL"):
        _count(word, parts, 1, 1, "<location>")
        target = parts[0]
        element = re.fullmatch(rf"({_N})\s*\[(.+)\]", target)
        if word == "HERE" and element is not None:
            for index in split_top(element.group(2)):
                _check("N", index)
        elif word == "HERE" and not re.fullmatch(rf"#?{_N}", target):
            raise ValSyntaxError(f"HERE: {target} IS NOT A LOCATION NAME")
        return Statement(word, (target if word == "HERE" else _check("L", target),), original)
    if word == "TYPE":
        try:
            output_list(original[4:], None)
        except ControllerFunction as error:
            raise ControllerOnly(str(error)) from None
        except (ExprError, ValtermError, ValueError) as error:
            raise ValSyntaxError(str(error)) from None
        return Statement("TYPE", (original[4:].strip(),), original, None, 1)
    if word == "SIGNAL":
        _count(word, parts, 1, 64, "<signal>, ...")
        return Statement("SIGNAL", tuple(_check("N", p) for p in parts), original)
    if word == "WAIT":
        return Statement("WAIT", (_check("N", rest) if rest else None,), original)
    if word == "WAIT.EVENT":
        seconds = parts[-1] if len(parts) == 2 else ""
        if len(parts) != 2 or not seconds:
            raise ValSyntaxError("WAIT.EVENT: EXPECTED WAIT.EVENT , <seconds>")
        return Statement(word, (_check("N", seconds),), original)
    if word in ("REACT", "REACTI", "IGNORE"):
        _count(word, parts, 1, 3, "<signal>, <program>")
        return Statement(word, (_check("N", parts[0]), *parts[1:]), original)
    if word in ("ENABLE", "DISABLE"):
        _count(word, parts, 1, 32, "<switch>, ...")
        return Statement(word, tuple(p for p in parts), original)
    if word == "SET":
        raise ValSyntaxError("SET: EXPECTED SET <location> = <location expression>")
    raise ValSyntaxError(f"{word}: NOT UNDERSTOOD")


def _declared(word: str, rest: str) -> tuple[str, ...]:
    words = rest.split(None, 1)
    if words and words[0] in _DECLARE_TYPES:
        rest = words[1] if len(words) > 1 else ""
    names = []
    for part in split_top(rest):
        name = re.sub(r"\[.*\]$", "", part.strip())
        if not re.fullmatch(rf"[$#]?{_N}", name):
            raise ValSyntaxError(f"{word}: {part!r} IS NOT A VARIABLE NAME")
        names.append(name)
    if not names:
        raise ValSyntaxError(f"{word}: EXPECTED {word} <name>, ...")
    return tuple(names)


# -- builders ------------------------------------------------------------------------------

def _machine(c: Build) -> Machine:
    machine = c.machine
    if machine is None:
        raise ProgramError("V+ STATEMENTS NEED THE V+ CONTROLLER")
    return machine


def _num(c: Build, text: str) -> Fn:
    return compile_number(text, _machine(c)).function()


def _loc(c: Build, text: str) -> Callable[[Values], Transform]:
    return compile_location(text, _machine(c))


def _store_location(c: Build, name: str, transform: Transform) -> None:
    c.sim.locations[name] = transform.location()


def _assign(c: Build, st: Statement) -> Op:
    kind, target, index_texts, value_text = st.args
    machine = _machine(c)
    if kind == "N" and not index_texts:
        return Assign(c.step, c.next, c.next, target, _num(c, value_text))
    indexes = [_num(c, i) for i in index_texts]

    def key(V: Values) -> str:
        return array_key(target, [i(V) for i in indexes]) if indexes else target

    if kind == "S":
        value_s = compile_string(value_text, machine)

        def run_s() -> Events:
            machine.strings[key(c.variables)] = value_s(c.variables)
            return c.next
            yield
        return c.action(run_s)
    if kind == "P":  # SET #p = #PPOINT(...) or #q
        value_p = compile_precision(value_text, machine)

        def run_p() -> Events:
            machine.precision[key(c.variables)] = value_p(c.variables)
            return c.next
            yield
        return c.action(run_p)
    if kind == "L":
        value_l = _loc(c, value_text)

        def run_l() -> Events:
            _store_location(c, key(c.variables), value_l(c.variables))
            return c.next
            yield
        return c.action(run_l)
    value_n = _num(c, value_text)

    def run_n() -> Events:
        c.variables[key(c.variables)] = float(value_n(c.variables))
        return c.next
        yield
    return c.action(run_n)


def _for(c: Build, st: Statement) -> Op:
    var, start_text, stop_text, step_text = st.args
    start, stop = _num(c, start_text), _num(c, stop_text)
    step = _num(c, step_text) if step_text else (lambda V: 1.0)
    end = c.after(c.partner())
    V = c.variables

    def run() -> Events:
        V[var] = float(start(V))
        return c.next if _within(V[var], stop(V), step(V)) else end
        yield
    return c.action(run)


def _within(value: float, stop: float, step: float) -> bool:
    if step == 0:
        raise ProgramError("FOR: STEP IS 0")
    return value <= stop + 1e-9 if step > 0 else value >= stop - 1e-9


def _end(c: Build, st: Statement) -> Op:
    assert c.analysis is not None
    opener = c.analysis.partner.get(c.index)
    statement = c.analysis.statements[opener] if opener is not None else None
    if statement is None or statement.command != "FOR" or opener is None:
        return b85._end(c, st)
    var, _start, stop_text, step_text = statement.args
    stop = _num(c, stop_text)
    step = _num(c, step_text) if step_text else (lambda V: 1.0)
    body = c.op_index[opener + 1]
    V = c.variables

    def run() -> Events:
        increment = float(step(V))
        V[var] = V[var] + increment
        return body if _within(V[var], stop(V), increment) else c.next
        yield
    return c.action(run)


def _case(c: Build, st: Statement) -> Op:
    assert c.analysis is not None
    value = _num(c, st.args[0])
    end = c.after(c.partner())
    choices: list[tuple[list[Fn] | None, int]] = []
    for index in c.analysis.cases.get(c.index, []):
        statement = c.analysis.statements[index]
        assert statement is not None
        values = None if statement.command == "ANY" else [_num(c, t) for t in statement.args]
        choices.append((values, c.after(index)))

    def run() -> Events:
        V = c.variables
        wanted = value(V)
        for values, target in choices:
            if values is None or any(v(V) == wanted for v in values):
                return target
        return end
        yield
    return c.action(run)


def _value_or_any(c: Build, st: Statement) -> Op:
    """Reached by falling out of the previous choice: the CASE is done."""
    assert c.analysis is not None
    case = c.analysis.case_of[c.index]
    return c.jump(c.after(c.analysis.partner[case]))


def _condition(c: Build, text: str) -> Fn:
    fn = _num(c, text)
    return lambda V: bool(fn(V))


def _branch(c: Build, text: str, if_true: int, if_false: int, error: int | None = None) -> Branch:
    return Branch(c.step, c.next, c.next if error is None else error, _condition(c, text), if_true, if_false)


def _if(c: Build, st: Statement) -> Op:
    if st.shape == 1:
        target = c.target_of(st.args[1])
        if target is None:
            return b85._if_goto(c, Statement("IF", (compile_number(st.args[0], c.machine), st.args[1])))
        return _branch(c, st.args[0], target, c.next)
    assert c.analysis is not None
    end = c.after(c.partner())
    otherwise = c.analysis.else_of.get(c.index)
    return _branch(c, st.args[0], c.next, c.after(otherwise) if otherwise is not None else end, end)


def _while(c: Build, st: Statement) -> Op:
    end = c.after(c.partner())
    return _branch(c, st.args[0], c.next, end, end)


def _until(c: Build, st: Statement) -> Op:
    return _branch(c, st.args[0], c.next, c.after(c.partner()))


def _exit_or_next(c: Build, st: Statement) -> Op:
    """EXIT n: past the end of the n-th enclosing loop; NEXT n: that loop's next pass (FOR:
    its END steps the variable; WHILE: the condition again; DO: its UNTIL)."""
    assert c.analysis is not None
    loops, count = c.analysis.loops.get(c.index, []), st.args[0]
    if count > len(loops):
        return b85.failed(c, f"{st.command} {count}: NOT INSIDE {count} LOOP(S)")
    opener = loops[count - 1]
    closer = c.analysis.partner.get(opener)
    if closer is None:
        return b85.failed(c, f"{st.command}: ITS LOOP IS NOT CLOSED")
    if st.command == "EXIT":
        return c.jump(c.after(closer))
    kind = c.analysis.statements[opener]
    return c.jump(c.op_index[opener if kind is not None and kind.command == "WHILE" else closer])


def _nothing(c: Build, st: Statement) -> Op:
    return c.jump(c.next)


# -- CALL with arguments --------------------------------------------------------------------

@dataclass(frozen=True)
class Argument:
    """One CALL argument: its value now, and (by reference) where the result goes back."""

    kind: str  # N number, L location, S string, A array
    read: Callable[[], object]
    write_back: Callable[[object], None] | None = None


@dataclass(frozen=True, slots=True)
class VCall(Control):
    """CALL name(args): parameters and AUTO variables saved, bound, restored on return."""

    program: str = ""
    arguments: tuple[Callable[[], Argument], ...] = ()
    machine: Machine | None = field(default=None, repr=False)
    variables: dict[str, float] = field(default_factory=dict, repr=False)
    locations: dict[str, Location] = field(default_factory=dict, repr=False)

    def callee(self) -> str:
        return self.program

    def control(self, run: Run, call: Callable[[str], CompiledProgram]) -> Events:
        caller, program = run.program.name, self.callee()
        if len(run.frames) >= MAX_CALL_DEPTH:
            raise RunStop(f"CALL {program}: MORE THAN {MAX_CALL_DEPTH} NESTED CALLS", caller, self.step.step)
        try:
            sub = call(program)
        except RunStop as stop:
            raise RunStop(f"CALL {program}: {stop.message}", caller, self.step.step) from None
        if not sub.analysis.structure_ok:
            for diagnostic in sub.analysis.fatal:
                yield Error(sub.name, diagnostic.step, diagnostic.message)
            raise RunStop(f"CALL {program}: THE PROGRAM CANNOT RUN", caller, self.step.step)
        parameters = list(sub.analysis.program.parameters)
        if len(self.arguments) > len(parameters):
            raise RunStop(f"CALL {program}: {len(self.arguments)} ARGUMENTS FOR "
                          f"{len(parameters)} PARAMETERS", caller, self.step.step)
        values = [argument() for argument in self.arguments]  # in the caller's scope
        restore = self._bind(parameters, values, sub.analysis.autos)
        return run.enter(sub, self.next, restore)

    def _bind(self, parameters: list[str], values: list[Argument], autos: list[str]) -> Callable[[], None]:
        V, L = self.variables, self.locations
        strings = self.machine.strings if self.machine is not None else {}
        own = [p.removesuffix("[]") for p in parameters] + [a for a in autos if a not in parameters]
        saved = {name: (V.get(name), L.get(name), strings.get(name)) for name in own}
        saved_arrays = {name: {k: v for k, v in V.items() if k.startswith(name + "[")} for name in own}
        for name in own:
            V.pop(name, None)
            for key in saved_arrays[name]:
                V.pop(key, None)
        for name, argument in zip(parameters, values):
            name = name.removesuffix("[]")
            value = argument.read()
            if argument.kind == "N":
                if value is not None:  # an undefined variable passed to be set
                    V[name] = float(value)  # type: ignore[arg-type]
            elif argument.kind == "L":
                assert isinstance(value, Location)
                L[name] = value
            elif argument.kind == "S":
                if value is not None:  # an undefined string passed to be set
                    strings[name] = str(value)
            else:
                assert isinstance(value, dict)
                for index, element in value.items():
                    V[f"{name}[{index}]"] = element

        def restore() -> None:
            results: list[tuple[Argument, object]] = []
            for name, argument in zip(parameters, values):
                name = name.removesuffix("[]")
                if argument.write_back is None:
                    continue
                if argument.kind == "N":
                    results.append((argument, V.get(name)))
                elif argument.kind == "L":
                    results.append((argument, L.get(name)))
                elif argument.kind == "S":
                    results.append((argument, strings.get(name)))
                else:
                    prefix = name + "["
                    results.append((argument, {k[len(prefix):-1]: v for k, v in V.items() if k.startswith(prefix)}))
            for name in own:
                for key in [k for k in V if k.startswith(name + "[")]:
                    del V[key]
                V.update(saved_arrays[name])
                number, location, string = saved[name]
                _put(V, name, number)
                _put(L, name, location)
                _put(strings, name, string)
            for argument, result in results:
                if result is not None and argument.write_back is not None:
                    argument.write_back(result)
        return restore


@dataclass(frozen=True, slots=True)
class VCallS(VCall):
    """CALLS $name(args): CALL of the program whose name is the string's value as the step runs."""

    named: Callable[[Values], str] = field(default=lambda V: "", repr=False)

    def callee(self) -> str:
        name = self.named(self.variables).strip().upper()
        if not re.fullmatch(_N, name):
            raise RunStop(f"CALLS: {name!r} IS NOT A PROGRAM NAME", self.step.program, self.step.step)
        return name


def _put(store: dict[str, T], name: str, old: T | None) -> None:
    """Put back what a name held before a CALL (nothing: the name is removed)."""
    if old is None:
        store.pop(name, None)
    else:
        store[name] = old


def _argument(c: Build, text: str) -> Callable[[], Argument]:
    machine, V, L = _machine(c), c.variables, c.sim.locations
    if text.endswith("[]"):
        name = text[:-2]
        prefix = name + "["

        def array() -> Argument:
            elements = {k[len(prefix):-1]: v for k, v in V.items() if k.startswith(prefix)}

            def back(result: object) -> None:
                assert isinstance(result, dict)
                V.update({f"{name}[{k}]": v for k, v in result.items()})
            return Argument("A", lambda: elements, back)
        return array
    if text.startswith(("$", '"')):
        value = compile_string(text, machine)
        element = re.fullmatch(rf"(\${_N})\s*\[([^\[\]]*)\]", text)  # $a[i], by reference too
        indexes = [_num(c, i) for i in element.group(2).split(",")] if element else []
        named = text if re.fullmatch(rf"\${_N}", text) else None

        def string() -> Argument:
            where = array_key(element.group(1), [i(V) for i in indexes]) if element else named
            if where is None:
                return Argument("S", lambda: value(V))

            def back(result: object) -> None:
                machine.strings[where] = str(result)
            # by reference: a string not yet defined is passed to be set
            return Argument("S", lambda: machine.strings.get(where), back)
        return string
    plain = text if re.fullmatch(_N, text) else None
    number = _try_number(text, machine)
    location = _try_location(text, machine)

    element = re.fullmatch(rf"({_N})\s*\[([^\[\]]*)\]", text)
    indexes = [_num(c, i) for i in element.group(2).split(",")] if element else []

    def argument() -> Argument:
        if plain is not None:  # by reference: a variable (perhaps not yet defined) or a location
            return _by_reference(plain, V, L)
        if element is not None:  # a[i], p[i]: an element of a number or location array, likewise
            return _by_reference(array_key(element.group(1), [i(V) for i in indexes]), V, L)
        if number is not None:
            result = float(number(V))
            return Argument("N", lambda: result)
        if location is not None:
            where = location(V).location()
            return Argument("L", lambda: where)
        raise ProgramError(f"CALL ARGUMENT {text} IS NOT A NUMBER OR A LOCATION")
    return argument


def _by_reference(name: str, V: dict[str, float], L: dict[str, Location]) -> Argument:
    if name in V or name not in L:
        def number_back(result: object) -> None:
            assert isinstance(result, float)
            V[name] = result
        current = V.get(name)
        return Argument("N", lambda: current, number_back)

    def location_back(result: object) -> None:
        assert isinstance(result, Location)
        L[name] = result
    here = L[name]
    return Argument("L", lambda: here, location_back)


def _try_number(text: str, machine: Machine) -> Fn | None:
    try:
        return compile_number(text, machine).function()
    except (ExprError, MachineError):
        return None


def _try_location(text: str, machine: Machine) -> Callable[[Values], Transform] | None:
    try:
        return compile_location(text, machine)
    except (ExprError, MachineError):
        return None


def _call(c: Build, st: Statement) -> Op:
    name, texts = st.args
    arguments = tuple(_argument(c, t) for t in texts if t)
    if st.command == "CALLS":  # the program a string names when the step runs
        named = compile_string(name, _machine(c))
        return VCallS(c.step, c.next, c.next, "", arguments, _machine(c), c.variables, c.sim.locations,
                      named)
    return VCall(c.step, c.next, c.next, name, arguments, _machine(c), c.variables,
                 c.sim.locations)


# -- motions, the hand, settings -----------------------------------------------------------

@dataclass(frozen=True)
class Joints:
    """A precision point's six joint angles as a motion's target."""

    angles: tuple[float, ...]


def _target(c: Build, text: str) -> Callable[[], Location | Joints]:
    """A motion's target: a precision point's joints, or the location the 1985 tool must reach."""
    machine = _machine(c)
    if text.startswith("#"):
        joints = _precision(c, text)
        if joints is not None:
            return lambda: Joints(joints(c.variables))
    where = _loc(c, text)
    return lambda: machine.through_tool(where(c.variables)).location()


def _precision(c: Build, text: str) -> Callable[[Values], tuple[float, ...]] | None:
    """A precision point's joints (#name, #PPOINT(...)); None for a compound like #p:TRANS(...)."""
    try:
        return compile_precision(text, _machine(c))
    except ExprError:
        return None


def _go(c: Build, target: Location | Joints, straight: bool) -> Events:
    machine = _machine(c)
    if isinstance(target, Joints):
        move_joints = getattr(c.sim, "move_joints", None)
        if move_joints is None:
            raise ProgramError("PRECISION POINTS NEED THE SIMULATOR")
        if straight:
            yield from machine.observe(c.sim.move(_point(c, target), straight=True))
        else:
            yield from machine.observe(move_joints(target.angles))
    else:
        yield from machine.observe(c.sim.move(target, straight=straight))
    return 0


def _point(c: Build, joints: Joints) -> Location:
    """Where the tool is at a precision point (for straight motions and APPRO)."""
    return _machine(c).pose_location(joints.angles)


def _move(c: Build, st: Statement) -> Op:
    straight = st.command in ("MOVES", "MOVEST")
    target = _target(c, st.args[0])
    hand = _num(c, st.args[1]) if st.args[1] else None
    machine = _machine(c)

    def run() -> Events:
        yield from _go(c, target(), straight)
        if hand is not None:
            action = c.sim.open if hand(c.variables) else c.sim.close
            yield from machine.observe(action(immediate=False))
        return c.next
    return _reacting(c, run)


def _appro(c: Build, st: Statement) -> Op:
    straight = st.command == "APPROS"
    target = _target(c, st.args[0])
    distance = _num(c, st.args[1])
    machine = _machine(c)

    def run() -> Events:
        goal = target()
        where = _point(c, goal) if isinstance(goal, Joints) else goal
        yield from machine.observe(c.sim.appro(where, float(distance(c.variables)), straight=straight))
        return c.next
    return _reacting(c, run)


def _depart(c: Build, st: Statement) -> Op:
    distance = _num(c, st.args[0])
    machine = _machine(c)

    def run() -> Events:
        yield from machine.observe(c.sim.depart(float(distance(c.variables)), straight=st.command == "DEPARTS"))
        return c.next
    return _reacting(c, run)


def _hand(c: Build, st: Statement) -> Op:
    machine = _machine(c)
    closing = st.command.startswith(("CLOSE", "RELAX")) and not st.command.startswith("RELAX")
    action = c.sim.close if closing else c.sim.open
    immediate = st.command.endswith("I")

    def run() -> Events:
        yield from machine.observe(action(immediate=immediate))
        return c.next
    return _reacting(c, run)


def _delay(c: Build, st: Statement) -> Op:
    seconds = _num(c, st.args[0])
    machine = _machine(c)

    def run() -> Events:
        value = float(seconds(c.variables))
        if value > 0:
            yield from machine.observe(iter([Delay(value)]))
        return c.next
    return _reacting(c, run)


def _select(c: Build, st: Statement) -> Op:
    """SELECT ROBOT = n: the simulator has one robot, robot 1."""
    robot = _num(c, st.args[0])

    def run() -> Events:
        number = float(robot(c.variables))
        if number != 1:
            raise ProgramError(f"SELECT ROBOT = {number:g}: THE SIMULATOR HAS ONE ROBOT, ROBOT 1")
        return c.next
        yield
    return c.action(run)


def _with_numbers(c: Build, st: Statement) -> Op:
    """DRIVE, DRAW, BASE: the 1985 builders on the V+ values."""
    machine = _machine(c)
    values = tuple(None if t is None else compile_number(t, machine) for t in st.args)
    built = b85.BUILDERS[st.command](c, Statement(st.command, values, st.text))
    assert isinstance(built, Action)
    inner = built.run

    def run() -> Events:
        return (yield from machine.timed(inner()))
    return _reacting(c, run)


_SPEED_UNITS = {"MMPS": 1.0, "IPS": 25.4}  # tool tip speed units, in mm/s


def _speed_statement(rest: str, original: str) -> Statement:
    """SPEED speed {, rotation} {MMPS | IPS | MONITOR} {ALWAYS} (the V+ reference); MONITOR, the
    monitor's speed, stays in force. Args: speed, ALWAYS, mm/s per unit (0: percent)."""
    words = rest.split()
    always = bool(words) and words[-1].upper() == "ALWAYS"
    words = words[:-1] if always else words
    unit = words[-1].upper() if words and words[-1].upper() in (*_SPEED_UNITS, "MONITOR") else ""
    values = split_top(" ".join(words[:-1] if unit else words))
    _count("SPEED", values, 1, 2, "<speed> {, <rotation speed>} {MMPS | IPS} {ALWAYS}")
    for value in values[1:]:
        _check("N", value)  # the rotation factor of straight lines: checked, not modelled
    return Statement("SPEED", (_check("N", values[0]), always or unit == "MONITOR", _SPEED_UNITS.get(unit, 0.0)),
                     original)


def _speed(c: Build, st: Statement) -> Op:
    speed, always, per_unit = _num(c, st.args[0]), bool(st.args[1]), float(st.args[2])
    set_program_speed = getattr(c.sim, "set_program_speed", None)

    def run() -> Events:
        wanted = float(speed(c.variables)) * (per_unit or 1.0)
        if set_program_speed is None:  # a stand-in simulator: the 1985 SPEED
            got = c.sim.set_speed(wanted)
        else:
            got = set_program_speed(wanted, bool(per_unit), always)
        if got != wanted:
            range_said = "(10 TO 100)" if not per_unit else "MM/S (THE ROBOT'S TOOL SPEED)"
            yield Message(f"SPEED SET TO {b85.format_value(got)} {range_said}", "warning")
        return c.next
    return c.action(run)


def _parameter(c: Build, st: Statement) -> Op:
    name, value = st.args[0], _num(c, st.args[1])
    machine = _machine(c)

    def run() -> Events:
        machine.set_parameter(name, float(value(c.variables)))
        return c.next
        yield
    return c.action(run)


def _here(c: Build, st: Statement) -> Op:
    """HERE name, HERE loc[i] (an array element), HERE #point (the joints)."""
    name = st.args[0]
    machine = _machine(c)
    element = re.fullmatch(rf"({_N})\s*\[(.+)\]", name)
    indexes = [_num(c, i) for i in split_top(element.group(2))] if element is not None else []

    def run() -> Events:
        if element is not None:
            from valterm.core.val.vexpr import compile_location as here

            key = array_key(element.group(1), [i(c.variables) for i in indexes])
            _store_location(c, key, here("HERE", machine)(c.variables))
            return c.next
        if name.startswith("#"):
            joints = getattr(c.sim, "joints", None)
            if joints is None:
                raise ProgramError("PRECISION POINTS NEED THE SIMULATOR")
            machine.precision[name] = tuple(float(j) for j in joints)
        else:
            from valterm.core.val.vexpr import compile_location as here

            _store_location(c, name, here("HERE", machine)(c.variables))
        return c.next
        yield
    return c.action(run)


def _decompose(c: Build, st: Statement) -> Op:
    """DECOMPOSE a[i] = loc: X Y Z yaw pitch roll; of a precision point (#p, #PPOINT): its joints."""
    name, start_text, location_text = st.args
    start, where = _num(c, start_text), _loc(c, location_text)
    point = _precision(c, location_text) if location_text.startswith("#") else None

    def run() -> Events:
        first = int(start(c.variables))
        values = point(c.variables) if point is not None else where(c.variables).decompose()
        for offset, value in enumerate(values):
            c.variables[array_key(name, [first + offset])] = round(value, 9)
        return c.next
        yield
    return c.action(run)


def _tool(c: Build, st: Statement) -> Op:
    where = _loc(c, st.args[0])
    machine = _machine(c)

    def run() -> Events:
        tool = where(c.variables)
        machine.tool = None if abs(tool.matrix - np.eye(4)).max() < 1e-9 else tool  # TOOL NULL
        return c.next
        yield
    return c.action(run)


def _type(c: Build, st: Statement) -> Op:
    machine = _machine(c)
    items = output_list(st.args[0], machine)
    open_line = any(fn is None and fmt == NO_LINE_END for _text, fn, fmt in items)  # TYPE ..., /S

    def run() -> Events:
        lines = (machine.typed + render_output(items, c.variables)).split("\n")
        machine.typed = lines.pop() if open_line else ""
        for line in lines:
            yield TypeOut(line)
        return c.next
    return c.action(run)


def typed_rest(machine: Machine) -> Events:
    """The line a TYPE ..., /S left open, typed when the run ends (nothing typed is lost)."""
    if machine.typed:
        yield TypeOut(machine.typed)
        machine.typed = ""
    return 0


def _signal(c: Build, st: Statement) -> Op:
    numbers = [_num(c, t) for t in st.args]
    machine = _machine(c)

    def run() -> Events:
        for number in numbers:
            value = number(c.variables)
            if value != int(value) or value == 0:
                raise ProgramError(f"SIGNAL {b85.format_value(value)}: NOT A SIGNAL NUMBER")
            try:
                yield machine.set_signal(int(value))
            except ValtermError as error:
                raise ProgramError(str(error).upper()) from None
        return c.next
    return _reacting(c, run)


def _bits(c: Build, st: Statement) -> Op:
    """BITS first, count = value: signals first .. first+count-1 set to value's bits (the
    lowest bit to the first signal)."""
    first, value = _num(c, st.args[0]), _num(c, st.args[-1])
    count = _num(c, st.args[1]) if len(st.args) == 3 else (lambda V: 1.0)
    machine = _machine(c)

    def run() -> Events:
        start, bits, number = int(first(c.variables)), int(value(c.variables)), int(count(c.variables))
        if not 1 <= number <= 32:
            raise ProgramError(f"BITS: {number} SIGNALS (1 TO 32)")
        for offset in range(number):
            signal = start + offset
            try:
                yield machine.set_signal(signal if bits >> offset & 1 else -signal)
            except ValtermError as error:
                raise ProgramError(str(error).upper()) from None
        return c.next
    return _reacting(c, run)


def _wait(c: Build, st: Statement) -> Op:
    """WAIT cond: simulated time passes until cond is true (a TIMER reaches a value, a
    scripted input changes); with neither possible the program stops and says so."""
    machine = _machine(c)
    if st.args[0] is None:  # WAIT alone: until the next major cycle (a polling loop's pause)
        def cycle() -> Events:
            yield from machine.observe(iter([Delay(MAJOR_CYCLE)]))
            return c.next
        return _reacting(c, cycle)
    condition = _condition(c, st.args[0])
    text = st.args[0]

    def holds() -> bool:
        return bool(condition(c.variables))

    def run() -> Events:
        started = machine.time
        while not holds():
            coming = machine.next_input_time()
            if coming is None and machine.waits_for_keyboard():
                # the app waits in real time (the user may set an input), a TIMER to the microsecond
                when = first_true(machine, holds, machine.time + WAIT_POLL)
                yield Delay(WAIT_POLL if when is None else when - machine.time)
                yield from machine.apply_inputs()
                started = machine.time  # no time limit: the user ends it (an input, or CTRL-C)
                continue
            if coming is None and machine.keyboard:
                return c.next  # CTRL-C: the run stops after this step
            limit = min(machine.deadline, started + NEVER_AFTER)  # the run's limit of robot time
            until = limit if coming is None else min(coming, limit)
            when = first_true(machine, holds, until)
            if when is not None:  # the clock makes it true before any input changes
                yield from machine.wait(when - machine.time)
            elif coming is None and first_true(machine, holds, NEVER_AFTER, NEVER_AFTER) is None:
                raise ProgramError(f"WAIT {text}: IT NEVER BECOMES TRUE (NO MORE INPUTS ARE SCRIPTED)")
            elif coming is None or coming > limit:
                yield from machine.wait(max(0.0, limit - machine.time))  # the robot waited up to the limit
                raise ProgramError(f"WAIT {text}: STILL FALSE AT THE LIMIT: {machine.deadline_said}")
            else:
                yield from machine.wait(coming - machine.time)  # the input changes now
            if machine.pending:  # a REACT program runs first, then this WAIT looks again
                return c.op_index[c.index]
        return c.next
    return _reacting(c, run)


def first_true(machine: Machine, condition: Callable[[], bool], until: float,
               poll: float = WAIT_POLL) -> float | None:
    """The first time (to a microsecond) up to ``until`` at which ``condition`` holds, the
    inputs as they are now; None if it never does. The controller looks at a WAIT's
    condition continually: polls ``poll`` apart find it, halving the last one pins it."""
    clock, now = machine.clock, machine.clock.seconds
    try:
        low = now
        while low < until:
            high = min(low + poll, until)
            clock.seconds = high
            if condition():
                while high - low > 1e-6:
                    clock.seconds = middle = (low + high) / 2
                    low, high = (low, middle) if condition() else (middle, high)
                return high
            low = high
        return None
    finally:
        clock.seconds = now


def _wait_event(c: Build, st: Statement) -> Op:
    seconds = _num(c, st.args[0])
    machine = _machine(c)

    def run() -> Events:
        value = max(0.0, float(seconds(c.variables)))
        yield Delay(value)  # the interpreter adds its time to the clock
        yield from machine.apply_inputs()
        return c.next
    return _reacting(c, run)


def _react(c: Build, st: Statement) -> Op:
    """REACT/REACTI n, program: armed here; run by the next motion, WAIT or SIGNAL that sees it."""
    signal = _num(c, st.args[0])
    machine = _machine(c)
    program = st.args[1].upper() if len(st.args) > 1 else ""
    if st.command != "IGNORE" and not re.fullmatch(_N, program):
        return b85.failed(c, f"{st.command}: EXPECTED {st.command} <signal>, <program>")

    def run() -> Events:
        number = int(signal(c.variables))
        try:
            if st.command == "IGNORE":
                machine.ignore(number)
            else:
                machine.react(number, program)
        except ValtermError as error:
            raise ProgramError(str(error).upper()) from None
        return c.next
        yield
    return c.action(run)


def _no_events() -> Events:
    return 0
    yield


@dataclass(frozen=True, slots=True)
class Reacting(Control):
    """A V+ step during which signals may change (motions, WAIT, DELAY, SIGNAL): after it, a
    triggered REACT program is CALLed, returning to the next step (V+ reaction semantics,
    checked between steps rather than mid-motion)."""

    body: Callable[[], Events] = field(default=_no_events, repr=False)
    machine: Machine | None = field(default=None, repr=False)

    def control(self, run: Run, call: Callable[[str], CompiledProgram]) -> Events:
        pc = yield from self.body()
        if self.machine is None or not self.machine.pending:
            return pc
        signed, program = self.machine.pending.pop(0)
        yield Message(f"REACT {signed}: CALL {program}")
        try:
            sub = call(program)
        except RunStop as stop:
            raise RunStop(f"REACT {signed}: {stop.message}", run.program.name, self.step.step) from None
        return run.enter(sub, pc)


def _reacting(c: Build, body: Callable[[], Events]) -> Op:
    return Reacting(c.step, c.next, c.next, body, _machine(c))


def _timer(c: Build, st: Statement) -> Op:
    number, value = _num(c, st.args[0]), _num(c, st.args[1])
    machine = _machine(c)

    def run() -> Events:
        machine.set_timer(number(c.variables), float(value(c.variables)))
        return c.next
        yield
    return c.action(run)


def _switch(c: Build, st: Statement) -> Op:
    machine, on = _machine(c), st.command == "ENABLE"

    def run() -> Events:
        for name in st.args:
            machine.switches[name] = on
        return c.next
        yield
    return c.action(run)


def vplus_where(where: Where) -> Where:
    """A WHERE readout in V+'s convention: the same pose, yaw pitch roll instead of O A T."""
    return replace(where, ypr=convert_orientation(where.oat, "OAT", "YPR"))


def _where(c: Build, st: Statement) -> Op:
    def run() -> Events:
        yield vplus_where(c.sim.where())
        return c.next
    return c.action(run)


def _status(c: Build, st: Statement) -> Op:
    machine = _machine(c)

    def run() -> Events:
        yield c.status()
        yield TypeOut(signal_line(machine))
        return c.next
    return c.action(run)


def signal_line(machine: Machine) -> str:
    outputs = " ".join(str(n) for n in machine.signals.outputs_on()) or "NONE"
    inputs = " ".join(str(n) for n in machine.signals.inputs_on()) or "NONE"
    return f"SIGNALS ON: OUTPUTS {outputs}  INPUTS {inputs}"


VPLUS_BUILDERS: dict[str, Builder] = {
    **b85.BUILDERS,
    ASSIGN: _assign, "FOR": _for, "END": _end, "CASE": _case, "VALUE": _value_or_any, "ANY": _value_or_any,
    "IF": _if, "WHILE": _while, "UNTIL": _until, "CALL": _call, "EXIT": _exit_or_next, "NEXT": _exit_or_next,
    "CALLS": _call,
    "AUTO": _nothing, "GLOBAL": _nothing, "BREAK": _nothing, **{word: _nothing for word in _TUNING},
    "MOVE": _move, "MOVES": _move, "MOVET": _move, "MOVEST": _move, "APPRO": _appro, "APPROS": _appro,
    "DEPART": _depart, "DEPARTS": _depart, **{word: _hand for word in _HAND}, "DELAY": _delay,
    "DRIVE": _with_numbers, "DRAW": _with_numbers, "BASE": _with_numbers,
    "SPEED": _speed, "PARAMETER": _parameter, "HERE": _here, "DECOMPOSE": _decompose, "TOOL": _tool,
    "TYPE": _type, "SIGNAL": _signal, "BITS": _bits, "WAIT": _wait, "WAIT.EVENT": _wait_event,
    "REACT": _react, "REACTI": _react, "IGNORE": _react, "TIMER": _timer,
    "ENABLE": _switch, "DISABLE": _switch, "STATUS": _status, "WHERE": _where,
    "SELECT": _select, "ATTACH": _nothing, "DETACH": _nothing,
}
"""The v+ instruction set: the 1985 builders where the meaning is the same, V+ ones otherwise."""


def is_vplus(analysis: Analysis) -> bool:
    return analysis.dialect == DIALECT


__all__ = ["DIALECT", "VPLUS_BUILDERS", "VCall", "parse_vplus", "signal_line", "split_top"]
