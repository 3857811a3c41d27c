"""V+ statements decoded (``parse_vplus``): the text of one step -> a ``Statement``.

The 1985 dialect reads its statements from COMMAND.DAT; V+ statements do not fit those
shapes (``FOR i = 1 TO n STEP 2``, ``CASE x OF``, ``VALUE 1, 2:``, ``CALL p(a, b)``,
``MOVET loc, TRUE``), so they are decoded here into the same ``Statement`` the compiler
and the builders use. Arguments are kept as text, checked here (``machine=None``) and
compiled again by the builder against the interpreter's ``Machine``.
"""

from __future__ import annotations

import re
from collections.abc import Callable

from valterm.core.errors import ValtermError
from valterm.core.files.commandfile import CommandSpec, default_commands
from valterm.core.kinematics import CONFIG_WORDS
from valterm.core.val.dialects.vplus.expr import (
    NAME,
    compile_location,
    compile_number,
    compile_precision,
    compile_string,
    output_list,
)
from valterm.core.val.expr import ControllerFunction, ExprError
from valterm.core.val.machine import MachineError
from valterm.core.val.parser import (
    ASSIGN,
    MAX_LABEL,
    ControllerOnly,
    Statement,
    ValSyntaxError,
    strip_comment,
)

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
HAND = ("OPEN", "OPENI", "CLOSE", "CLOSEI", "RELAX", "RELAXI")
_MOTIONS = ("MOVE", "MOVES", "MOVET", "MOVEST")
# How the real arm accelerates and settles: the simulated motion is the same (accepted, no effect)
TUNING = ("ACCEL", "DURATION", "COARSE", "FINE", "NONULL", "NULL", "SINGLE", "MULTIPLE")
COMMANDS = (*_NO_ARGS, *_TEXT_ARGS, *_ONE_VALUE, *HAND, *_MOTIONS, "APPRO", "APPROS", "DRIVE", "DRAW",
            "FOR", "CASE", "VALUE", "WHILE", "UNTIL", "IF", "GOTO", "CALL", "CALLS", "AUTO", "LOCAL", "GLOBAL",
            "SPEED", "PARAMETER", "HERE", "SET", "DECOMPOSE", "TOOL", "TYPE", "SIGNAL", "WAIT",
            "WAIT.EVENT", "REACT", "REACTI", "IGNORE", "TIMER", "ENABLE", "DISABLE", "BASE", "EXIT", "NEXT",
            "BITS",
            *TUNING)


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
    for decoder in (_block_statement, _assignment, _command, _robot_selection):
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


def _block_statement(upper: str, original: str) -> Statement | None:
    """FOR, CASE, VALUE, ANY, WHILE, IF, UNTIL, EXIT, NEXT, GOTO, CALL, CALLS: the block
    structure and CALL, as V+ writes them (pass 1 matches the blocks: ``compiler``)."""
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
    shape = _SHAPES.get(word)
    if shape is None:
        raise ValSyntaxError(f"{word}: NOT UNDERSTOOD")
    return shape(word, rest, parts, original)


def _one_value(word: str, rest: str, parts: list[str], original: str) -> Statement:
    _count(word, parts, 1, 1, "<value>")
    return Statement(word, (_check("N", parts[0]),), original)


def _hand_value(word: str, rest: str, parts: list[str], original: str) -> Statement:
    _count(word, parts, 0, 1, "{<value>}")
    return Statement(word, (_check("N", parts[0]) if parts else None,), original)


def _motion(word: str, rest: str, parts: list[str], original: str) -> Statement:
    with_hand = word.endswith("T")
    _count(word, parts, 2 if with_hand else 1, 2 if with_hand else 1,
           "<location>, <hand>" if with_hand else "<location>")
    return Statement(word, (_check("L", parts[0]), _check("N", parts[1]) if with_hand else None), original)


def _approach(word: str, rest: str, parts: list[str], original: str) -> Statement:
    _count(word, parts, 2, 2, "<location>, <distance>")
    return Statement(word, (_check("L", parts[0]), _check("N", parts[1])), original)


def _values(word: str, rest: str, parts: list[str], original: str) -> Statement:
    """DRIVE, DRAW, BASE."""
    _count(word, parts, 3 if word == "DRIVE" else 0, 4 if word == "BASE" else 3, "<values>")
    values = tuple(_check("N", p) if p else None for p in parts)
    if word == "DRIVE":
        joint = compile_number(values[0] or "0").const
        if joint is not None and (joint != int(joint) or not 1 <= joint <= 6):
            raise ValSyntaxError(f"DRIVE: JOINT NUMBER {joint:g} IS NOT 1 TO 6")
    return Statement(word, values, original)


def _declaration(word: str, rest: str, parts: list[str], original: str) -> Statement:
    return Statement("AUTO" if word != "GLOBAL" else "GLOBAL", (_declared(word, rest),), original)


def _tuning(word: str, rest: str, parts: list[str], original: str) -> Statement:
    profile = re.match(r"\s*\(([^()]*)\)\s*(?=[^,\s])", rest) if word == "ACCEL" else None
    if profile is not None:  # ACCEL (profile) acc, dec: the profile number is checked, not modelled
        _check("N", profile.group(1))
        rest = rest[profile.end():]
    tuning = [p for p in split_top(re.sub(r"\bALWAYS\s*$", "", rest).strip()) if p]
    _count(word, tuning, 0, 2 if word in ("ACCEL", "FINE", "COARSE") else 1, "{<value>} {ALWAYS}")
    return Statement(word, tuple(_check("N", v) for v in tuning), original)


def _speed(word: str, rest: str, parts: list[str], original: str) -> Statement:
    return _speed_statement(rest, original)


def _location_target(word: str, rest: str, parts: list[str], original: str) -> Statement:
    """HERE name (loc[i], #point), TOOL location."""
    _count(word, parts, 1, 1, "<location>")
    target = parts[0]
    element = re.fullmatch(rf"({_N})\s*\[(.+)\]", target)
    if word == "HERE" and element is not None:
        for index in split_top(element.group(2)):
            _check("N", index)
    elif word == "HERE" and not re.fullmatch(rf"#?{_N}", target):
        raise ValSyntaxError(f"HERE: {target} IS NOT A LOCATION NAME")
    return Statement(word, (target if word == "HERE" else _check("L", target),), original)


def _type_list(word: str, rest: str, parts: list[str], original: str) -> Statement:
    try:
        output_list(original[4:], None)
    except ControllerFunction as error:
        raise ControllerOnly(str(error)) from None
    except (ExprError, ValtermError, ValueError) as error:
        raise ValSyntaxError(str(error)) from None
    return Statement("TYPE", (original[4:].strip(),), original, None, 1)


def _signals(word: str, rest: str, parts: list[str], original: str) -> Statement:
    _count(word, parts, 1, 64, "<signal>, ...")
    return Statement("SIGNAL", tuple(_check("N", p) for p in parts), original)


def _wait(word: str, rest: str, parts: list[str], original: str) -> Statement:
    return Statement("WAIT", (_check("N", rest) if rest else None,), original)


def _wait_event(word: str, rest: str, parts: list[str], original: str) -> Statement:
    seconds = parts[-1] if len(parts) == 2 else ""
    if len(parts) != 2 or not seconds:
        raise ValSyntaxError("WAIT.EVENT: EXPECTED WAIT.EVENT , <seconds>")
    return Statement(word, (_check("N", seconds),), original)


def _reaction(word: str, rest: str, parts: list[str], original: str) -> Statement:
    _count(word, parts, 1, 3, "<signal>, <program>")
    return Statement(word, (_check("N", parts[0]), *parts[1:]), original)


def _switches(word: str, rest: str, parts: list[str], original: str) -> Statement:
    _count(word, parts, 1, 32, "<switch>, ...")
    return Statement(word, tuple(p for p in parts), original)


def _set_alone(word: str, rest: str, parts: list[str], original: str) -> Statement:
    raise ValSyntaxError("SET: EXPECTED SET <location> = <location expression>")


_Shape = Callable[[str, str, list[str], str], Statement]
_SHAPES: dict[str, _Shape] = {
    **{word: _one_value for word in _ONE_VALUE}, **{word: _hand_value for word in HAND},
    **{word: _motion for word in _MOTIONS}, "APPRO": _approach, "APPROS": _approach,
    "DRIVE": _values, "DRAW": _values, "BASE": _values,
    "AUTO": _declaration, "LOCAL": _declaration, "GLOBAL": _declaration, **{word: _tuning for word in TUNING},
    "SPEED": _speed, "HERE": _location_target, "TOOL": _location_target, "TYPE": _type_list,
    "SIGNAL": _signals, "WAIT": _wait, "WAIT.EVENT": _wait_event,
    "REACT": _reaction, "REACTI": _reaction, "IGNORE": _reaction, "ENABLE": _switches, "DISABLE": _switches,
    "SET": _set_alone,
}
"""How each V+ statement with arguments is decoded (its word -> its shape)."""


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


def block_opened(text: str) -> str | None:
    """FOR, CASE, WHILE, DO or IF (with THEN) when a step that failed to decode starts with one:
    the block is still open (its END is not a stray one)."""
    words = strip_comment(text).upper().replace(",", " ").split()
    if not words:
        return None
    if words[0] in ("FOR", "CASE", "WHILE", "DO"):
        return words[0]
    return "IF" if words[0] == "IF" and "GOTO" not in words else None
