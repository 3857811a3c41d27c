"""The two-pass VAL-II interpreter (App. C section 3, Chapter 6).

Pass 1 (``valterm.core.val.compiler.analyse``) decodes every step once, records the labels and
matches the structures.  From that, each step becomes one small executable op, so pass 2
never decodes text again:

    op = (Step event, kind, fn, error_pc, arg)

``kind`` SIMPLE: ``fn()`` returns the index of the next op (assignment, IF, WHILE, GOTO...);
GEN: ``pc = yield from fn()`` (anything that yields events: motions, TYPE, WHERE...);
CALL, RETURN, STOP and PAUSE are handled by the loop itself.  ``error_pc`` is where an
undeclared variable sends control (past END for IF and WHILE, section 6.4.7-8).

Everything is a generator of ``valterm.core.events``: the app draws them, ``valterm run`` prints
them, tests collect them.  PAUSE yields a ``Pause`` event; the app stops pulling, lets the
user type commands through ``command(text)`` and, on PROCEED, pulls again (pulling again
*is* proceeding; ``proceed()`` only clears the ``paused`` flag).  ``abort()`` (CTRL-C) is
checked before each step.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Iterator

from valterm.core.errors import ValtermError
from valterm.core.events import (
    Delay,
    Error,
    Event,
    Help,
    Message,
    Monitor,
    Pause,
    Status,
    Step,
    TypeOut,
)
from valterm.core.files.programs import Program, ProgramLine, split_label
from valterm.core.kinematics import Location
from valterm.core.val.commands import CommandTable, default_commands
from valterm.core.val.compiler import Analysis, analyse, step_text
from valterm.core.val.expr import Expr
from valterm.core.val.parser import ASSIGN, LocArg, Statement, ValSyntaxError, parse_statement
from valterm.core.val.variables import VariableStore

MAX_CALL_DEPTH = 20   # nested CALLs before "CALL DEPTH" stops the program
FOREVER_LOOPS = 1000  # EXECUTE name,-n: "the simulator repeats the program 1000 times"

SIMPLE, GEN, CALL, RETURN, STOP, PAUSE = range(6)

Op = tuple[Step | None, int, Callable[..., Any], int, Any]

_CONFIG_WORDS = ("RIGHTY", "LEFTY", "ABOVE", "BELOW", "FLIP", "NOFLIP")
_MOTION = {  # command -> (simulator method, straight line)
    "MOVE": ("move", False), "MOVES": ("move", True),
    "APPRO": ("appro", False), "APPROS": ("appro", True),
    "DEPART": ("depart", False), "DEPARTS": ("depart", True),
}
_MONITOR_EVENTS = ("LISTP", "LISTF", "LISTL", "EDIT", "POINT")


class UndefinedVariable(ValtermError):
    def __init__(self, name: str) -> None:
        super().__init__(name)
        self.name = name


class RunStop(Exception):
    """Something that ends the whole run (the message says what), e.g. a missing subroutine."""


def _format_value(value: float) -> str:
    value = float(value)
    if value.is_integer() and abs(value) < 1e15:
        return str(int(value))
    return f"{value:.6g}"


def _getter(expr: Expr | None, default: float | None = None) -> Callable[[dict], float | None]:
    """A fast evaluator: constants are folded, an omitted argument gives the default."""
    if expr is None:
        return lambda V: default
    if expr.const is not None:
        const = expr.const
        return lambda V: const
    return expr.function()


def _values(getters: tuple[Callable[[dict], Any], ...], V: dict) -> list[Any]:
    try:
        return [g(V) for g in getters]
    except KeyError as error:
        raise UndefinedVariable(str(error.args[0])) from None


@dataclass
class CompiledProgram:
    name: str
    analysis: Analysis
    code: list[Op]
    first: int = 0

    def step_number(self, pc: int) -> int:
        if 0 <= pc < len(self.code) and self.code[pc][0] is not None:
            return self.code[pc][0].step  # type: ignore[union-attr]
        return len(self.analysis.program.steps)


class Interpreter:
    """Runs VAL-II programs and typed commands against a simulator.

    ``sim``: the Simulator (or a stand-in with the same methods).
    ``load_program(name) -> Program``: reads NAME.DAT (raises for a missing program).
    ``variables``: the VAL-II variables (CHECK.DAT), a dict kept by reference.
    """

    def __init__(self, sim: Any, load_program: Callable[[str], Program],
                 variables: dict[str, float] | None = None,
                 commands: CommandTable | None = None,
                 keep_variables: Callable[[dict[str, float]], None] | None = None) -> None:
        self.sim = sim
        # CHECK.DAT is written when a program or a typed command ends (section 6.7), not per
        # assignment: a 100 000-pass loop must not write a file 100 000 times
        self.keep_variables = keep_variables
        self.load_program = load_program
        self.variables: dict[str, float] = variables if variables is not None else VariableStore()
        self.commands = commands or default_commands()
        self.program = ""      # the program EXECUTE runs ("" when none)
        self.loops_total = 0
        self.loops_done = 0
        self._running = False
        self._paused = False
        self._abort = False
        self._cache: dict[str, CompiledProgram] = {}

    @classmethod
    def for_workspace(cls, sim: Any, workspace: Any) -> "Interpreter":
        """An interpreter reading NAME.DAT from the workspace, its variables from CHECK.DAT.

        The variables are written back to CHECK.DAT whenever a program or a typed command
        ends, so they are kept for the next session (section 6.7).
        """
        variables = VariableStore(workspace.read_variables())
        return cls(sim, workspace.read_program, variables, keep_variables=workspace.write_variables)

    # -- state the app asks about ---------------------------------------------
    @property
    def running(self) -> bool:
        return self._running

    @property
    def paused(self) -> bool:
        return self._paused

    def abort(self) -> None:
        """CTRL-C: stop the running program after the step being simulated (section 6.4.10)."""
        if self._running:
            self._abort = True

    def proceed(self) -> bool:
        """PROCEED: the paused program may go on (the app pulls its generator again)."""
        if not self._paused:
            return False
        self._paused = False
        return True

    def status(self) -> Status:
        left = max(0, self.loops_total - self.loops_done) if self._running else 0
        return Status(float(self.sim.speed), self.program, self.loops_done, left)

    # -- pass 1 and the executable form ----------------------------------------
    def compile(self, name: str) -> CompiledProgram:
        """Pass 1 and the ops of program `name` (cached for the present EXECUTE)."""
        name = name.upper()
        compiled = self._cache.get(name)
        if compiled is not None:
            return compiled
        try:
            program = self.load_program(name)
        except Exception as error:  # a missing or damaged file ends the run with its reason
            raise RunStop(str(error) or f"PROGRAM {name} DOES NOT EXIST") from None
        compiled = self.compile_program(program)
        self._cache[name] = compiled
        return compiled

    def compile_program(self, program: Program) -> CompiledProgram:
        analysis = analyse(program, self.commands)
        name = program.name
        steps = program.steps
        # Comment and empty steps do nothing: they get no op; a jump to one lands on the next op.
        op_index: list[int] = []
        count = 0
        for statement in analysis.statements:
            op_index.append(count)
            if statement is None or statement.command:
                count += 1
        op_index.append(count)  # "past the last step"
        code: list[Op] = []
        if not analysis.structure_ok:
            return CompiledProgram(name, analysis, code)  # pass 1 failed: it will not run
        for index, statement in enumerate(analysis.statements):
            if statement is not None and not statement.command:
                continue
            step = Step(name, index + 1, step_text(program, index))
            if statement is None:
                code.append(self._error_op(step, analysis.syntax[index], op_index[index + 1]))
                continue
            code.append(self._build(statement, step, index, analysis, op_index))
        return CompiledProgram(name, analysis, code)

    def _error_op(self, step: Step | None, reason: str, nxt: int) -> Op:
        program, number = (step.program, step.step) if step is not None else ("", 0)

        def fn() -> Iterator[Event]:
            yield Error(program, number, reason)
            return nxt

        return (step, GEN, fn, nxt, None)

    def _build(self, st: Statement, step: Step | None, index: int,
               analysis: Analysis | None, op_index: list[int]) -> Op:
        """The op of one decoded statement; `analysis` None for a typed command."""
        V = self.variables
        sim = self.sim
        command, args = st.command, st.args
        nxt = op_index[index + 1]
        program, number = (step.program, step.step) if step is not None else ("", 0)

        def simple(body: str, err: int = nxt, **names: Any) -> Op:
            # One Python function per step: no decoding, no dispatch, at run time.
            namespace: dict[str, Any] = {"V": V, **names}
            exec(f"def _op():\n    {body}\n", namespace)
            return (step, SIMPLE, namespace["_op"], err, None)

        def gen(fn: Callable[[], Iterator[Event]], err: int = nxt, arg: Any = None) -> Op:
            return (step, GEN, fn, err, arg)

        def target_of(label: int) -> int | None:
            if analysis is None or label not in analysis.labels:
                return None
            return op_index[analysis.labels[label]]

        def missing_label(label: int) -> Error:
            return Error(program, number, f"GOTO {label}: NO STEP WITH LABEL {label} (CONTINUING WITH THE NEXT STEP)")

        if command == ASSIGN:
            name, expr = args
            return simple(f"V[{name!r}] = {expr.src}\n    return {nxt}")

        if command in ("IF", "WHILE", "UNTIL", "ELSE", "END", "ENDIF", "DO", "GOTO"):
            assert analysis is not None  # typed control statements are refused before this
            partner = analysis.partner.get(index)
            if command == "IF" and "GOTO" in st.keywords:
                cond, label = args
                target = target_of(label)
                if target is not None:
                    return simple(f"return {target} if {cond.src} else {nxt}")
                check = _getter(cond)

                def if_goto_missing() -> Iterator[Event]:
                    if _values((check,), V)[0]:
                        yield missing_label(label)
                    return nxt
                return gen(if_goto_missing)
            if command == "IF":
                end = op_index[partner + 1]  # type: ignore[operator]
                otherwise = analysis.else_of.get(index)
                false_pc = op_index[otherwise + 1] if otherwise is not None else end
                return simple(f"return {nxt} if {args[0].src} else {false_pc}", err=end)
            if command == "ELSE":
                opener = next(i for i, e in analysis.else_of.items() if e == index)
                return simple(f"return {op_index[analysis.partner[opener] + 1]}")
            if command in ("END", "ENDIF"):
                opener = partner
                if opener is not None and analysis.statements[opener].command == "WHILE":  # type: ignore[union-attr]
                    return simple(f"return {op_index[opener]}")
                return simple(f"return {nxt}")
            if command == "WHILE":
                end = op_index[partner + 1]  # type: ignore[operator]
                return simple(f"return {nxt} if {args[0].src} else {end}", err=end)
            if command == "DO":
                return simple(f"return {nxt}")
            if command == "UNTIL":
                body = op_index[partner + 1]  # type: ignore[operator]
                return simple(f"return {nxt} if {args[0].src} else {body}")
            # GOTO
            label = args[0]
            target = target_of(label)
            if target is not None:
                return simple(f"return {target}")

            def goto_missing() -> Iterator[Event]:
                yield missing_label(label)
                return nxt
            return gen(goto_missing)

        if command == "CALL":
            return (step, CALL, None, nxt, args[0])  # type: ignore[return-value]
        if command == "RETURN":
            return (step, RETURN, None, nxt, None)  # type: ignore[return-value]
        if command in ("STOP", "HALT"):
            return (step, STOP, None, nxt, args[0] or "")  # type: ignore[return-value]
        if command == "PAUSE":
            return (step, PAUSE, None, nxt, args[0] or "")  # type: ignore[return-value]

        if command in _CONFIG_WORDS:
            def indicator() -> Iterator[Event]:
                sim.set_indicator(command)
                return nxt
                yield
            return gen(indicator)
        if command == "HERE":
            here_name = args[0]

            def here() -> Iterator[Event]:
                sim.here(here_name)
                return nxt
                yield
            return gen(here)

        if command == "TYPE":
            if st.shape == 0:  # TYPE var=
                var = args[0]

                def type_var() -> Iterator[Event]:
                    try:
                        value = V[var]
                    except KeyError:
                        yield Error(program, number, f"VARIABLE {var} IS NOT DECLARED")
                        return nxt
                    yield TypeOut(f"{var} = {_format_value(value)}")
                    return nxt
                return gen(type_var)
            text = args[0] or ""

            def type_text() -> Iterator[Event]:
                yield TypeOut(text)
                return nxt
            return gen(type_text)

        if command == "WHERE":
            def where() -> Iterator[Event]:
                yield sim.where()
                return nxt
            return gen(where)

        if command == "STATUS":
            def status() -> Iterator[Event]:
                yield self.status()
                return nxt
            return gen(status)

        if command == "SPEED":
            speed = _getter(args[0])

            def set_speed() -> Iterator[Event]:
                wanted = float(_values((speed,), V)[0])
                got = sim.set_speed(wanted)
                if got != wanted:
                    yield Message(f"SPEED SET TO {_format_value(got)} (10 TO 100)", "warning")
                return nxt
            return gen(set_speed)

        if command == "DELAY":
            seconds = _getter(args[0])

            def delay() -> Iterator[Event]:
                value = float(_values((seconds,), V)[0])
                if value > 0:
                    yield Delay(value)
                return nxt
            return gen(delay)

        if command == "SET":
            dst, src = args

            def set_location() -> Iterator[Event]:
                if src.shift is None:
                    sim.set_location(dst, src.name)
                else:
                    sim.locations[dst] = self._location(src)
                return nxt
                yield  # a generator
            return gen(set_location)

        if command == "SHIFT":
            name = args[0]
            increments = tuple(_getter(e, 0.0) for e in args[1:])

            def shift() -> Iterator[Event]:
                dx, dy, dz = _values(increments, V)
                sim.shift(name, float(dx), float(dy), float(dz))
                return nxt
                yield
            return gen(shift)

        if command == "BASE":
            offsets = tuple(_getter(e) for e in args)

            def base() -> Iterator[Event]:
                values = [None if v is None else float(v) for v in _values(offsets, V)]
                result = sim.set_base(*values)
                if result is not None and hasattr(result, "__next__"):
                    yield from result
                return nxt
            return gen(base)

        if command in _MOTION:
            method, straight = _MOTION[command]
            if method == "depart":
                distance = _getter(args[0])

                def depart() -> Iterator[Event]:
                    d = float(_values((distance,), V)[0])
                    yield from sim.depart(d, straight=straight)
                    return nxt
                return gen(depart)
            loc: LocArg = args[0]
            if method == "move":
                def move() -> Iterator[Event]:
                    yield from sim.move(self._location(loc), straight=straight)
                    return nxt
                return gen(move)
            distance = _getter(args[1])

            def appro() -> Iterator[Event]:
                d = float(_values((distance,), V)[0])
                yield from sim.appro(self._location(loc), d, straight=straight)
                return nxt
            return gen(appro)

        if command in ("READY", "ALIGN"):
            action = getattr(sim, command.lower())

            def plain() -> Iterator[Event]:
                yield from action()
                return nxt
            return gen(plain)

        if command == "DRIVE":
            getters = tuple(_getter(e) for e in args)

            def drive() -> Iterator[Event]:
                joint, degrees, speed = _values(getters, V)
                if float(joint) != int(joint):
                    raise ValueError(f"JOINT NUMBER {_format_value(joint)} IS NOT 1 TO 6")
                yield from sim.drive(int(joint), float(degrees), float(speed))
                return nxt
            return gen(drive)

        if command == "DRAW":
            getters = tuple(_getter(e, 0.0) for e in args)

            def draw() -> Iterator[Event]:
                dx, dy, dz = _values(getters, V)
                yield from sim.draw(float(dx), float(dy), float(dz))
                return nxt
            return gen(draw)

        if command in ("OPEN", "OPENI", "CLOSE", "CLOSEI"):
            # The % argument is decoded (and its variables checked); the simulated clamp is
            # fully open or closed on the part, as in the thesis (section 6.3).
            action = sim.open if command.startswith("OPEN") else sim.close
            immediate = command.endswith("I")
            amount = _getter(args[0])

            def hand() -> Iterator[Event]:
                _values((amount,), V)
                yield from action(immediate=immediate)
                return nxt
            return gen(hand)

        if command == "GRASP":
            amount = _getter(args[0])
            label = args[1] if len(args) > 1 else None
            target = target_of(label) if label is not None else None

            def grasp() -> Iterator[Event]:
                _values((amount,), V)
                if not sim.grasp_possible():
                    return nxt
                yield from sim.close(immediate=True)
                if label is None:
                    return nxt
                if target is None:
                    yield missing_label(label)
                    return nxt
                return target
            return gen(grasp)

        return self._error_op(step, f"{command} cannot be used here", nxt)

    def _location(self, loc: LocArg) -> str | Location:
        """A location argument for the simulator: a name, or the shifted location itself."""
        if loc.shift is None:
            return loc.name
        base = self.sim.location(loc.name)
        dx, dy, dz = _values(tuple(_getter(e, 0.0) for e in loc.shift), self.variables)
        x, y, z = base.xyz
        return Location((x + float(dx), y + float(dy), z + float(dz)), base.oat)

    # -- pass 2 ------------------------------------------------------------------
    def execute(self, name: str, loops: int = 1) -> Iterator[Event]:
        """EXECUTE name,loops: run the program `loops` times (negative: 1000) as events."""
        if self._running:
            yield Error("", 0, f"A PROGRAM ({self.program}) IS ALREADY RUNNING")
            return
        name = name.strip().upper()
        if name.endswith(".DAT"):
            name = name[:-4]
        loops = int(loops)
        total = FOREVER_LOOPS if loops < 0 else max(1, loops)
        self._cache.clear()  # programs are decoded once per EXECUTE: edits show next time
        try:
            main = self.compile(name)
        except RunStop as stop:
            yield Error(name, 0, str(stop))
            return
        if not main.analysis.structure_ok:
            for diagnostic in main.analysis.fatal:
                yield Error(name, diagnostic.step, diagnostic.message)
            yield Error(name, 0, "THE PROGRAM CANNOT RUN (PASS 1 FOUND THE ERRORS ABOVE)")
            return
        self.program, self.loops_total, self.loops_done = name, total, 0
        self._running, self._paused, self._abort = True, False, False
        try:
            while self.loops_done < total:
                finished = yield from self._pass(main)
                if not finished:
                    return
                self.loops_done += 1
            yield Message(f"PROGRAM {name} COMPLETED: {self.loops_done} LOOP{'S' if self.loops_done != 1 else ''}")
        finally:
            self._running = self._paused = self._abort = False
            self._keep()

    def _keep(self) -> None:
        if self.keep_variables is not None:
            self.keep_variables(dict(self.variables))

    def _pass(self, main: CompiledProgram) -> Iterator[Event]:
        """One execution pass; returns True when it ends normally (STOP, end, RETURN)."""
        from valterm.core.motion import MotionRefused

        frames: list[tuple[CompiledProgram, int]] = []
        prog = main
        code = prog.code
        size = len(code)
        pc = 0
        V = self.variables
        while True:
            if pc >= size:
                if not frames:
                    return True
                prog, pc = frames.pop()  # the end of a subroutine returns like RETURN
                code, size = prog.code, len(prog.code)
                continue
            if self._abort:
                yield Error(prog.name, prog.step_number(pc), "ABORTED")
                return False
            step, kind, fn, err, arg = code[pc]
            yield step
            if kind == SIMPLE:
                try:
                    pc = fn()
                except KeyError as error:
                    yield Error(prog.name, step.step, f"VARIABLE {error.args[0]} IS NOT DECLARED")
                    pc = err
                except ZeroDivisionError:
                    yield Error(prog.name, step.step, "DIVISION BY ZERO")
                    pc = err
            elif kind == GEN:
                try:
                    pc = yield from fn()
                except UndefinedVariable as error:
                    yield Error(prog.name, step.step, f"VARIABLE {error.name} IS NOT DECLARED")
                    pc = err
                except ZeroDivisionError:
                    yield Error(prog.name, step.step, "DIVISION BY ZERO")
                    pc = err
                except MotionRefused as refused:
                    # The controller stops the program at the step; everything else is kept.
                    yield Error(prog.name, step.step, str(refused))
                    return False
                except (KeyError, ValueError) as error:
                    yield Error(prog.name, step.step, _reason(error))
                    return False
            elif kind == CALL:
                if len(frames) >= MAX_CALL_DEPTH:
                    yield Error(prog.name, step.step, f"CALL {arg}: MORE THAN {MAX_CALL_DEPTH} NESTED CALLS")
                    return False
                try:
                    sub = self.compile(arg)
                except RunStop as stop:
                    yield Error(prog.name, step.step, f"CALL {arg}: {stop}")
                    return False
                if not sub.analysis.structure_ok:
                    for diagnostic in sub.analysis.fatal:
                        yield Error(sub.name, diagnostic.step, diagnostic.message)
                    yield Error(prog.name, step.step, f"CALL {arg}: THE PROGRAM CANNOT RUN")
                    return False
                frames.append((prog, err))
                prog, pc = sub, 0
                code, size = prog.code, len(prog.code)
            elif kind == RETURN:
                if not frames:
                    return True  # RETURN in the main program ends the pass, like STOP
                prog, pc = frames.pop()
                code, size = prog.code, len(prog.code)
            elif kind == STOP:
                if arg:
                    yield TypeOut(arg)
                return True
            else:  # PAUSE
                self._paused = True
                yield Pause(prog.name, step.step, arg)
                self._paused = False  # the app pulled again: PROCEED
                pc = err

    # -- typed commands ------------------------------------------------------------
    def command(self, text: str) -> Iterator[Event]:
        """One line typed at the VAL-II prompt (a statement or a monitor command), as events."""
        yield from self._command(text)
        if not self._running:  # EXECUTE kept them already; a typed ROW=10 is kept here
            self._keep()

    def _command(self, text: str) -> Iterator[Event]:
        try:
            _label, statement_text = split_label(text.expandtabs())
            st = parse_statement(statement_text, self.commands)
        except (ValSyntaxError, ValueError) as error:
            yield Error("", 0, str(error))
            return
        command = st.command
        if not command:
            return
        if st.spec is not None and not st.spec.typed:
            yield Error("", 0, f"{command} CAN ONLY BE USED IN A PROGRAM STEP")
            return
        if command == "EXECUTE":
            loops = 1
            if len(st.args) > 1 and st.args[1] is not None:
                try:
                    loops = int(_values((_getter(st.args[1]),), self.variables)[0])
                except UndefinedVariable as error:
                    yield Error("", 0, f"VARIABLE {error.name} IS NOT DECLARED")
                    return
            yield from self.execute(st.args[0], loops)
            return
        if command == "PROCEED":
            if not self.proceed():
                yield Error("", 0, "NO PROGRAM IS PAUSED")
            return
        if command == "HELP":
            yield self.help(st.args[0] or "")
            return
        if command in _MONITOR_EVENTS:
            yield Monitor(command, (st.args[0] or "") if st.args else "")
            return
        if command in ("STOP", "HALT"):
            if st.args[0]:
                yield TypeOut(st.args[0])
            return
        yield from self._run_typed(st)

    def _run_typed(self, st: Statement) -> Iterator[Event]:
        from valterm.core.motion import MotionRefused

        op = self._build(st, None, 0, None, [0, 1])
        _step, kind, fn, _err, _arg = op
        try:
            if kind == SIMPLE:
                fn()
            else:
                yield from fn()
        except KeyError as error:
            if type(error) is KeyError:
                yield Error("", 0, f"VARIABLE {error.args[0]} IS NOT DECLARED")
            else:
                yield Error("", 0, _reason(error))
        except UndefinedVariable as error:
            yield Error("", 0, f"VARIABLE {error.name} IS NOT DECLARED")
        except ZeroDivisionError:
            yield Error("", 0, "DIVISION BY ZERO")
        except MotionRefused as refused:
            yield Error("", 0, str(refused))  # typed: it just reports (SPEC section 3)
        except ValueError as error:
            yield Error("", 0, _reason(error))

    def help(self, topic: str = "") -> Help:
        from valterm.core.val.helptopics import default_help

        topics = default_help()
        if not topic.strip():
            return Help("", tuple(topics.menu()))
        try:
            found = topics.find(topic)
        except KeyError as error:
            return Help(topic.upper(), (str(error.args[0]), "", *topics.menu()))
        return Help(found.name, tuple(found.lines()))


def _reason(error: Exception) -> str:
    if isinstance(error, KeyError):
        text = str(error)
        if text.startswith("'") and text.endswith("'"):
            return f"LOCATION {text[1:-1]} IS NOT DEFINED"
        return text.upper() if text.islower() else text
    return str(error)


def program_from_lines(name: str, lines: list[str]) -> Program:
    """A Program from raw lines (tests, the typed EDIT buffer): labels as the file reader splits them."""
    steps = []
    for number, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        label, text = split_label(line.expandtabs())
        steps.append(ProgramLine(label, text, number))
    return Program(name.upper(), steps)
