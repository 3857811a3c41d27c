"""The two-pass VAL-II interpreter (App. C section 3, Chapter 6).

Pass 1 (``valterm.core.val.compiler.analyse``) decodes every step once, records the labels and
matches the structures.  From that, a builder per instruction (``builders.BUILDERS``) makes
each step one small typed op (``ops``), so pass 2 never decodes text again.

Everything is a generator of ``valterm.core.events``: the app draws them, ``valterm run`` prints
them, tests collect them.  PAUSE yields a ``Pause`` event; the app stops pulling, lets the
user type commands through ``command(text)`` and, on PROCEED, pulls again (pulling again
*is* proceeding; ``proceed()`` only clears the ``paused`` flag).  ``abort()`` (CTRL-C) is
checked before each step.  ``hook`` (None by default) is called before each step of a
program with the program and the op, and may yield events of its own; ``pass_end`` after
each execution pass.  The debugger (``debugger.Debugger``, the BPT, XSTEP, SSTEP, WATCH and
TRACE commands) sets them while it has something to do.

Dialects (docs/VPLUS.md, ``valterm.core.val.dialects``): a program is decoded and built by
its own dialect when it says one (``Program.dialect``: ``"v+"`` when read from a V+ file), by
the interpreter's otherwise (``Interpreter(dialect="v+")``); the default is the thesis's 1985
language. ``machine`` holds the controller's state (signals, strings, precision points).
"""

from __future__ import annotations

from collections.abc import Callable, Generator, Iterator, Mapping
from dataclasses import replace
from pathlib import Path
from typing import Protocol

from valterm.core.cycletime import CycleClock
from valterm.core.errors import ValtermError
from valterm.core.events import (
    Contact,
    Error,
    Event,
    Help,
    LimitReached,
    Located,
    Message,
    Monitor,
    Pause,
    PoseEvent,
    Status,
    Step,
    TypeOut,
)
from valterm.core.files.commandfile import CommandTable, default_commands
from valterm.core.files.programs import Program, ProgramLine, split_label
from valterm.core.files.variables import VARIABLE_NAME
from valterm.core.files.vplus import VplusData
from valterm.core.motion import MotionRefused
from valterm.core.val import dialects
from valterm.core.val.builders import (
    Build,
    Builder,
    build,
    failed,
    getter,
    number,
)
from valterm.core.val.compiler import Analysis, analyse, step_text
from valterm.core.val.debugger import DEBUG_COMMANDS, Debugger
from valterm.core.val.dialect import Dialect
from valterm.core.val.expr import MAX_NUMBER
from valterm.core.val.limits import RunLimits
from valterm.core.val.locstore import LocationFiles, load, rules, storel
from valterm.core.val.machine import Machine, signal_line, typed_rest
from valterm.core.val.ops import (
    MAX_CALL_DEPTH,
    Action,
    Assign,
    Branch,
    CompiledProgram,
    Control,
    Jump,
    Op,
    ProgramError,
    Run,
    RunStop,
    UndefinedVariable,
)
from valterm.core.val.parser import Statement, ValSyntaxError, parse_statement
from valterm.core.val.protocol import Simulator
from valterm.core.val.variables import VariableStore

__all__ = [
    "FOREVER_LOOPS", "MAX_CALL_DEPTH", "CompiledProgram", "Interpreter", "ProgramError", "RunStop",
    "StepHook", "UndefinedVariable", "program_from_lines",
]

STOPS_RUN = -1  # an op's error index that ends the run (V+: the controller stops at the step)
FOREVER_LOOPS = 1000  # EXECUTE name,-n: "the simulator repeats the program 1000 times"

StepHook = Callable[[CompiledProgram, Op], Iterator[Event]]
"""Called before each program step (debugger: breakpoints, XSTEP, WATCH, TRACE)."""

MonitorCommand = Callable[["Interpreter", Statement], Iterator[Event]]
"""A command typed at the VAL-II prompt that is not a program statement (EXECUTE, HELP...)."""


class Interpreter:
    """Runs VAL-II programs and typed commands against a simulator.

    ``sim``: the Simulator (or a stand-in with the same methods, ``protocol.Simulator``).
    ``load_program(name) -> Program``: reads NAME.DAT (raises for a missing program).
    ``variables``: the VAL-II variables (CHECK.DAT), a dict kept by reference.
    ``commands``, ``builders``, ``monitor``: the dialect (COMMAND.DAT, the op of each
    instruction, the typed-only commands); the 1985 ones by default.
    """

    def __init__(self, sim: Simulator, load_program: Callable[[str], Program],
                 variables: dict[str, float] | None = None,
                 commands: CommandTable | None = None,
                 keep_variables: Callable[[dict[str, float]], object] | None = None,
                 builders: Mapping[str, Builder] | None = None,
                 monitor: Mapping[str, MonitorCommand] | None = None,
                 dialect: str = "1985", limits: RunLimits | None = None,
                 location_files: LocationFiles | None = None) -> None:
        self.sim = sim
        # how far one EXECUTE may go (steps, robot seconds, lines): a runaway ends by itself
        self.limits = limits or RunLimits()
        self._steps_left = self._lines_left = 0.0  # counted down during an EXECUTE
        self._limit_hit = ""  # the limit that stopped the run ("" when none)
        self._limit_at: tuple[str, int] | None = None  # the step whose robot time passed the limit
        # "1985" (COMMAND.DAT, the thesis) or "v+": the dialect of programs that do not say
        # (a program read from a V+ file is v+ whatever this says)
        self.dialect = dialects.check_dialect(dialect)
        # the one clock of the robot's time: STATUS, run's cycle time, V+ TIMER and inputs
        self.clock = CycleClock(sim.timing)  # the robot's own hand time
        # the clock when the last EXECUTE began and ended (None while it runs): typed
        # motions after it take the robot's time but are not its cycle
        self._cycle_start: float = 0.0
        self._cycle_end: float | None = 0.0
        self.machine = Machine(sim, clock=self.clock)  # V+ signals, strings, precision points
        self.machine.stopping = lambda: self._abort  # CTRL-C ends a WAIT for the keyboard
        # CHECK.DAT is written when a program or a typed command ends (section 6.7), not per
        # assignment: a 100 000-pass loop must not write a file 100 000 times
        self.keep_variables = keep_variables
        self.location_files = location_files  # STOREL and LOAD: NAME.LOC in the workspace
        # batched (valterm monitor): a typed command only marks the variables to keep; keep()
        # writes them once per batch of input lines
        self.keep_batched = False
        self._unkept = False
        self.load_program = load_program
        # the data sections (.LOCATIONS, .REALS, .STRINGS) of the V+ file holding a program,
        # loaded the first time one of its programs is compiled (as the controller's LOAD)
        self.load_data: Callable[[str], tuple[str, VplusData] | None] | None = None
        self.data_loaded: set[str] = set()
        # a VariableStore, so that reading an undeclared name is UndefinedVariable
        self.variables: dict[str, float] = (variables if isinstance(variables, VariableStore)
                                            else VariableStore(variables or {}))
        self.commands = commands or default_commands()
        self.builders: dict[str, Builder] = dict(builders or dialects.dialect(dialects.DEFAULT).builders)
        self.monitor: dict[str, MonitorCommand] = dict(monitor or MONITOR_COMMANDS)
        self._hook: StepHook | None = None
        self.pass_end: Callable[[], Iterator[Event]] | None = None
        self.debugger: Debugger = Debugger(self)
        self._run: Run | None = None  # the pass being run (its CALL frames: call_depth)
        self.program = ""      # the program EXECUTE runs ("" when none)
        self.loops_total = 0
        self.loops_done = 0
        self._running = False
        self._paused = False
        self._abort = False
        # whether the run must look before its next step: CTRL-C, a limit reached or a hook
        # (one flag the loop reads a step, not both of them: issue 25)
        self._watch = False
        self._cache: dict[str, CompiledProgram] = {}

    @classmethod
    def for_workspace(cls, sim: Simulator, workspace: _Workspace) -> Interpreter:
        """An interpreter reading NAME.DAT from the workspace, its variables from CHECK.DAT.

        The variables are written back to CHECK.DAT whenever a program or a typed command
        ends, so they are kept for the next session (section 6.7).
        """
        variables = VariableStore(workspace.read_variables())
        interpreter = cls(sim, workspace.read_program, variables, keep_variables=workspace.merge_variables,
                          location_files=LocationFiles(workspace))
        interpreter.load_data = workspace.vplus_data
        return interpreter

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
            self._abort = self._watch = True

    @property
    def hook(self) -> StepHook | None:
        """Called before each step while set (the debugger's); may be set while the program is paused."""
        return self._hook

    @hook.setter
    def hook(self, hook: StepHook | None) -> None:
        self._hook = hook
        self._watch = self._abort or hook is not None

    def proceed(self) -> bool:
        """PROCEED: the paused program may go on (the app pulls its generator again)."""
        if not self._paused:
            return False
        self._paused = False
        return True

    @property
    def call_depth(self) -> int:
        """How many CALLs deep the running program is (0 in the program EXECUTE started)."""
        return len(self._run.frames) if self._run is not None else 0

    @property
    def cycle_seconds(self) -> float:
        """The last EXECUTE's robot time, so far while it runs (the cycle time STATUS shows)."""
        end = self.clock.seconds if self._cycle_end is None else self._cycle_end
        return end - self._cycle_start

    def status(self) -> Status:
        left = max(0, self.loops_total - self.loops_done) if self._running else 0
        return Status(float(self.sim.speed), self.program, self.loops_done, left,
                      round(self.cycle_seconds, 3), str(self.sim.rules),
                      self.sim.arm.name, self.sim.arm.key)

    def pause(self, event: Pause) -> Iterator[Event]:
        """Yield `event` with the program paused: the app stops pulling; pulling again goes on."""
        self._paused = True
        yield event
        self._paused = False

    def _set_paused(self, paused: bool) -> None:
        self._paused = paused

    # -- pass 1 and the executable form ----------------------------------------
    def compile(self, name: str) -> CompiledProgram:
        """Pass 1 and the ops of program `name` (cached for the present EXECUTE)."""
        name = name.upper()
        compiled = self._cache.get(name)
        if compiled is not None:
            return compiled
        try:
            program = self.load_program(name)
        except (OSError, ValtermError) as error:  # a missing or damaged file ends the run with its reason
            raise RunStop(str(error) or f"PROGRAM {name} DOES NOT EXIST", name) from None
        if dialects.dialect(program.dialect).data_sections and self.load_data is not None:
            self._load_data_of(name)
        compiled = self.compile_program(program)
        self._cache[name] = compiled
        return compiled

    def _load_data_of(self, name: str) -> None:
        assert self.load_data is not None
        try:
            found = self.load_data(name)
        except (OSError, ValtermError):
            return  # the program itself was read: a file that cannot be read again has no data
        if found is not None and found[0] not in self.data_loaded:
            self.data_loaded.add(found[0])
            self.machine.load_data(found[1], self.variables)

    def compile_program(self, program: Program) -> CompiledProgram:
        language = self._dialect_of(program)
        analysis = analyse(program, self.commands, language.grammar)
        builders = self._builders(language)
        quoted = dialects.dialect(program.dialect).grammar.quoted_comments  # as the program's own file writes it
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
            return CompiledProgram(program.name, analysis, code)  # pass 1 failed: it will not run
        for index, statement in enumerate(analysis.statements):
            if statement is not None and not statement.command:
                continue
            step = Step(program.name, index + 1, step_text(program, index, quoted))
            context = self._context(step, index, analysis, op_index)
            if statement is None:
                code.append(failed(context, analysis.syntax[index]))
            else:
                code.append(build(context, statement, builders))
        if language.stops_at_error:  # the controller stops the program there (no "report and go on")
            code = [replace(op, error=STOPS_RUN) for op in code]
        return CompiledProgram(program.name, analysis, code)

    def _dialect_of(self, program: Program) -> Dialect:
        """A program's own dialect when it says one (a V+ file's), else the interpreter's."""
        return dialects.dialect(program.dialect if program.dialect != dialects.DEFAULT else self.dialect)

    def _builders(self, language: Dialect) -> Mapping[str, Builder]:
        """The dialect's statement table; instructions added to the interpreter's (``builders=``) too."""
        base = dialects.dialect(dialects.DEFAULT)
        if language is base:
            return self.builders
        return {**language.builders, **{k: v for k, v in self.builders.items() if k not in base.builders}}

    def _context(self, step: Step, index: int, analysis: Analysis | None, op_index: list[int]) -> Build:
        return Build(step, index, analysis, op_index, self.variables, self.sim, self.status,
                     self._set_paused, self.machine)

    # -- pass 2 ------------------------------------------------------------------
    def execute(self, name: str, loops: int = 1, start_step: int = 0) -> Generator[Event, None, None]:
        """EXECUTE name,loops: run the program `loops` times (negative: 1000) as events; ``start_step``:
        the first pass starts at that step (XSTEP name,step), the others at the top. A pass's steps
        run here, not in a generator of their own (a `yield from` a step, issue 25)."""
        ready = self._ready(name, start_step)
        if isinstance(ready, list):  # it cannot run: why
            yield from ready
            return
        name, main, start = ready
        total = self._begin(name, loops)
        V, low, high = self.variables, -MAX_NUMBER, MAX_NUMBER  # a number past these is refused, never inf or NaN
        try:
            while self.loops_done < total:  # a pass from op `start`, `finished` when it ends normally
                run = self._run = Run(main)
                prog, pc, code, steps = main, start, main.code, main.steps
                budget = counted = self._budget()  # steps until the limits are looked at again
                finished = False  # until the pass ends normally
                while True:
                    try:
                        op = code[pc]
                    except IndexError:  # past the last op (no test a step: the end is rare)
                        pc = run.leave()  # the end of a subroutine returns like RETURN
                        if run.ended:
                            self._spend(counted - budget)
                            finished = True
                            break
                        prog, code, steps = run.program, run.program.code, run.program.steps
                        continue
                    budget -= 1
                    if budget < 0:
                        budget, counted = self._recount(counted)
                    # CTRL-C, a limit, a hook (one flag a step: a breakpoint may be set while paused)
                    if self._watch and (yield from self._stops(prog, op, counted - budget - 1)):
                        break
                    yield steps[pc]
                    # the plain ops are final classes: their type says which (cheaper than isinstance)
                    if type(op) is Assign:
                        try:
                            evaluate = op.value  # a field read, then called (op.value(V) looks it up as a method)
                            value = evaluate(V)
                            if not low <= value <= high:
                                raise NumberTooLarge(f"NUMBER TOO LARGE: {op.name} WOULD BE {value:g}")
                            V[op.name] = value
                            pc = op.next
                        except (UndefinedVariable, ArithmeticError, ValueError) as error:
                            pc = yield from self._failed(op, _plain_reason(error))
                            if pc < 0:  # a V+ step's error stops the program
                                break
                    elif type(op) is Branch:
                        try:
                            condition = op.condition
                            pc = op.if_true if condition(V) else op.if_false
                        except (UndefinedVariable, ArithmeticError, ValueError) as error:
                            pc = yield from self._failed(op, _plain_reason(error))
                            if pc < 0:
                                break
                    elif type(op) is Jump:
                        pc = op.next
                    elif isinstance(op, Action):
                        pc = yield from self._act(op)
                        self._spend(counted - budget)  # the lines it printed are counted: look now
                        if pc < 0:
                            break
                        budget = counted = self._budget()
                    else:
                        pc = yield from self._control(op, run)
                        if run.failed or run.ended:
                            self._spend(counted - budget)
                            finished = not run.failed
                            break
                        prog, code, steps = run.program, run.program.code, run.program.steps
                start = 0
                finished = yield from self._pass_ended(finished)
                if not finished:
                    return
                self.loops_done += 1
            yield Message(f"PROGRAM {name} COMPLETED: {self.loops_done} LOOP{'S' if self.loops_done != 1 else ''}")
        finally:
            self._ended()

    def _pass_ended(self, finished: bool) -> Generator[Event, None, bool]:
        """A pass's end, however it ended: the stop of a last step that passed the robot-time
        limit, the line a TYPE ..., /S left open, then the hook; whether the pass finished."""
        if finished and self._limit_at is not None:
            yield self._stopped(*self._limit_at)
            finished = False
        yield from typed_rest(self.machine)
        if self.pass_end is not None:
            yield from self.pass_end()
        return finished

    def _begin(self, name: str, loops: int) -> int:
        """EXECUTE's state as its first pass begins; how many passes it runs."""
        total = FOREVER_LOOPS if int(loops) < 0 else max(1, int(loops))
        self.program, self.loops_total, self.loops_done = name, total, 0
        self._running, self._paused, self._abort, self._watch = True, False, False, self._hook is not None
        self._steps_left, self._lines_left = self.limits.allowed("steps"), self.limits.allowed("lines")
        self._limit_hit, self._limit_at = "", None
        self._cycle_start, self._cycle_end = self.clock.seconds, None
        self.machine.deadline = self._cycle_start + self.limits.allowed("seconds")
        self.machine.deadline_said = f"{self.limits.message('seconds')} ({self.limits.flag('seconds')})"
        return total

    def _ended(self) -> None:
        """EXECUTE's end, however it ended: the variables are kept (CHECK.DAT)."""
        self._running = self._paused = self._abort = False
        self._watch = self._hook is not None
        self._cycle_end = self.clock.seconds
        self._run = None
        self.debugger.run_ended()
        self._keep()

    def _stops(self, prog: CompiledProgram, op: Op, spent: int) -> Generator[Event, None, bool]:
        """Before a step when the run must look (``_watch``): the hook's events, then whether the run
        stops there (CTRL-C or a limit, maybe while the hook held the program paused)."""
        if not self._abort and self._hook is not None:
            yield from self._hook(prog, op)
        if not self._abort:
            return False
        self._spend(spent)
        yield self._stopped(prog.name, op.step.step)
        return True

    def _ready(self, name: str, start_step: int) -> tuple[str, CompiledProgram, int] | list[Event]:
        """The program EXECUTE runs (its name, code and first op), or the errors saying why it cannot."""
        if self._running:
            return [Error("", 0, f"A PROGRAM ({self.program}) IS ALREADY RUNNING")]
        name = name.strip().upper().removesuffix(".DAT")
        self._cache.clear()  # programs are decoded once per EXECUTE: edits show next time
        try:
            main = self.compile(name)
        except RunStop as stop:
            return [Error(name, 0, stop.message)]
        if not main.analysis.structure_ok:
            return [*(Error(name, diagnostic.step, diagnostic.message) for diagnostic in main.analysis.fatal),
                    Error(name, 0, "THE PROGRAM CANNOT RUN (PASS 1 FOUND THE ERRORS ABOVE)")]
        if start_step <= 0:
            return name, main, 0
        found = next((pc for pc, op in enumerate(main.code) if op.step.step >= start_step), None)
        if found is None:
            return [Error("", 0, f"PROGRAM {name} HAS NO STEP {start_step} THAT CAN RUN")]
        return name, main, found

    def _keep(self) -> None:
        if self.keep_batched:
            self._unkept = True
            return
        self.keep()

    def keep(self) -> None:
        """Write the variables to CHECK.DAT now (what a program's or a typed command's end does)."""
        self._unkept = False
        if self.keep_variables is not None:
            # CHECK.DAT keeps the 1985 kind of variable: V+ array elements and long names stay out
            local = {name for compiled in self._cache.values() for name in compiled.analysis.autos}
            kept = {k: v for k, v in self.variables.items() if VARIABLE_NAME.fullmatch(k) and k not in local}
            merged = self.keep_variables(kept)
            if isinstance(merged, dict):  # another session's variables and values, now shared
                self.variables.update({k: v for k, v in merged.items() if k not in local})

    @property
    def unkept(self) -> bool:
        """Batched: a command changed what CHECK.DAT should hold since the last keep()."""
        return self._unkept

    # -- the run's limits (valterm.core.val.limits) ----------------------------------
    SYNC = 1024  # steps between two looks at the limits: a local countdown in between

    def _budget(self) -> int:
        """Steps the loop may run before it looks at the limits again (then: the limit hit)."""
        left = min(self._steps_left, self._lines_left)
        if left <= 0:
            self._limit("steps" if self._steps_left <= 0 else "lines")
            return self.SYNC
        return int(min(left, self.SYNC))

    def _recount(self, counted: int) -> tuple[int, int]:
        """The `counted` steps are run: the budget left after this step, and the new count."""
        self._spend(counted)
        counted = self._budget()
        return counted - 1, counted  # this step is the first of the new count

    def _spend(self, steps: int) -> None:
        """``steps`` were run: each is a step and a scrolled line of the transcript."""
        self._steps_left -= steps
        self._lines_left -= steps

    def _limit(self, limit: str) -> None:
        """The run stops at its next step, saying ``limit`` ended it."""
        if not self._limit_hit:
            self._limit_hit = limit
        self._abort = self._watch = True

    def _stopped(self, program: str, step: int) -> Error:
        """Why the run stops here: a limit it reached, else CTRL-C."""
        if self._limit_hit:
            limit = self._limit_hit
            return LimitReached(program, step, self.limits.message(limit), limit, self.limits.flag(limit))
        return Error(program, step, "ABORTED")

    @staticmethod
    def _failed(op: Op, reason: str) -> Generator[Event, None, int]:
        """A plain op's error message; control goes to ``op.error``."""
        yield Error(op.step.program, op.step.step, reason)
        return op.error

    def _act(self, op: Action) -> Generator[Event, None, int]:
        """An op that yields events (the cycle clock sees them); -1 when its error stops the program."""
        program, number = op.step.program, op.step.step
        try:
            return (yield from self._timed(op.run(), op.step))
        except UndefinedVariable as error:
            yield Error(program, number, error.message)
        except ZeroDivisionError:
            yield Error(program, number, "DIVISION BY ZERO")
        except MotionRefused as refused:
            # The controller stops the program at the step; everything else is kept.
            yield Error(program, number, str(refused))
            return -1
        except ProgramError as error:
            yield Error(program, number, error.message)
            return -1
        except ValueError as error:  # a V+ function's domain (SQRT(-1)), a number it cannot read
            yield Error(program, number, _reason(error))
            return -1
        except (ValtermError, OverflowError) as error:  # V+: a signal, a transformation, a huge number
            yield Error(program, number, str(error).upper())
            return -1
        return op.error

    def _timed(self, events: Generator[Event, None, int], step: Step | None = None) -> Generator[Event, None, int]:
        """An op's events passed on, each one's time added to the one clock; returns its pc.

        The collision check's findings and grasps are located at ``step`` with the clamp's
        position; lines of output and the robot's time count against the run's limits."""
        observe = self.clock.observe
        while True:
            try:
                event = next(events)
            except StopIteration as done:
                if self._running and self.clock.seconds - self._cycle_start > self.limits.allowed("seconds"):
                    self._limit("seconds")
                    if step is not None and self._limit_at is None:
                        self._limit_at = (step.program, step.step)
                return int(done.value)
            observe(event)
            if not isinstance(event, PoseEvent):  # the many poses go straight through
                event = self._counted(event, step)
            yield event

    def _counted(self, event: Event, step: Step | None) -> Event:
        """``event`` located at ``step`` (a finding, a grasp); its lines counted while running."""
        if isinstance(event, Located) and step is not None and step.program:
            event = replace(event, program=step.program, step=step.step, clamp=self.sim.where().xyz)
        if self._running and isinstance(event, (TypeOut, Message, Contact)):
            self._lines_left -= event.text.count("\n") + 1
            if self._lines_left < 0:
                self._limit("lines")
        return event

    def _control(self, op: Op, run: Run) -> Generator[Event, None, int]:
        if not isinstance(op, Control):
            raise TypeError(f"{type(op).__name__} is not an op the run loop knows")
        try:
            return (yield from self._timed(op.control(run, self.compile), op.step))
        except RunStop as stop:
            yield Error(stop.program, stop.step, stop.message)
            run.failed = True
            return 0
        except (ValtermError, ValueError, ZeroDivisionError) as error:  # a V+ CALL's arguments
            message = error.message if isinstance(error, ProgramError) else _reason(error)
            yield Error(op.step.program, op.step.step, message)
            run.failed = True
            return 0

    # -- typed commands ------------------------------------------------------------
    def command(self, text: str) -> Generator[Event, None, None]:
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
        if not st.command:
            return
        if st.spec is not None and not st.spec.typed:
            yield Error("", 0, f"{st.command} CAN ONLY BE USED IN A PROGRAM STEP")
            return
        handler = self.monitor.get(st.command)
        if handler is not None:
            yield from handler(self, st)
        else:
            yield from self._run_typed(st)

    def _run_typed(self, st: Statement) -> Iterator[Event]:
        context = self._context(Step("", 0, st.text), 0, None, [0, 1])
        op = build(context, st, self.builders)
        try:
            if isinstance(op, Assign):
                value = op.value(self.variables)
                if not -MAX_NUMBER <= value <= MAX_NUMBER:
                    raise ProgramError(f"NUMBER TOO LARGE: {op.name} WOULD BE {value:g}")
                self.variables[op.name] = value
            elif isinstance(op, Action):
                yield from self._timed(op.run())  # a typed motion takes the robot's time too
        except ZeroDivisionError:
            yield Error("", 0, "DIVISION BY ZERO")
        except MotionRefused as refused:
            yield Error("", 0, str(refused))  # typed: it just reports (SPEC section 3)
        except ProgramError as error:
            yield Error("", 0, error.message)
        except (ValtermError, ValueError) as error:  # a location not defined, a V+ domain error
            yield Error("", 0, _reason(error))

    def help(self, topic: str = "") -> Help:
        from valterm.core.files.helpfile import NoHelpTopic, default_help

        topics = default_help()
        if not topic.strip():
            return Help("", tuple(topics.menu()))
        try:
            found = topics.find(topic)
        except NoHelpTopic as error:
            return Help(topic.upper(), (str(error), "", *topics.menu()))
        return Help(found.name, tuple(found.lines()))


class _Workspace(Protocol):  # what for_workspace reads from a Workspace
    def read_variables(self) -> dict[str, float]: ...
    def read_program(self, name: str) -> Program: ...
    def merge_variables(self, values: dict[str, float]) -> dict[str, float]: ...
    def path(self, name: str, ext: str) -> Path: ...
    def vplus_data(self, name: str) -> tuple[str, VplusData] | None: ...


# -- the commands only typed at the prompt ---------------------------------------------

def _execute(interpreter: Interpreter, st: Statement) -> Iterator[Event]:
    loops = 1
    if len(st.args) > 1 and st.args[1] is not None:
        try:
            loops = int(number(getter(st.args[1]), interpreter.variables))
        except UndefinedVariable as error:
            yield Error("", 0, error.message)
            return
    yield from interpreter.execute(st.args[0], loops)


def _help(interpreter: Interpreter, st: Statement) -> Iterator[Event]:
    yield interpreter.help(st.args[0] or "")


def _monitor_event(interpreter: Interpreter, st: Statement) -> Iterator[Event]:
    """The app's commands; POINT NAME, X, Y, Z, O, A, T (HELP POINT's one-line form) passes
    all seven items."""
    items = [str(getattr(arg, "text", arg) or "") for arg in st.args]
    yield Monitor(st.command, ", ".join(items) if len(items) > 1 else (items[0] if items else ""))


def _status_typed(interpreter: Interpreter, st: Statement) -> Iterator[Event]:
    """STATUS at the prompt; the I/O panel's line too once a signal is on (or in V+)."""
    yield interpreter.status()
    if dialects.dialect(interpreter.dialect).signals_in_status or interpreter.machine.signals.on:
        yield TypeOut(signal_line(interpreter.machine))


def _stop_typed(interpreter: Interpreter, st: Statement) -> Iterator[Event]:
    if st.args[0]:
        yield TypeOut(st.args[0])


MONITOR_COMMANDS: dict[str, MonitorCommand] = {
    "EXECUTE": _execute, "HELP": _help, **DEBUG_COMMANDS,  # PROCEED is the debugger's
    **{name: _monitor_event for name in ("LISTP", "LISTF", "LISTL", "EDIT", "POINT")},
    "STOP": _stop_typed, "HALT": _stop_typed, "STATUS": _status_typed,
    "STOREL": storel, "LOAD": load, "RULES": rules,
}


class NumberTooLarge(ArithmeticError):
    """A value past +-MAX_NUMBER given to a variable (refused: never inf or NaN); says which."""


def _plain_reason(error: UndefinedVariable | ArithmeticError | ValueError) -> str:
    if isinstance(error, (UndefinedVariable, NumberTooLarge)):
        return error.message if isinstance(error, UndefinedVariable) else str(error)
    if isinstance(error, ZeroDivisionError):
        return "DIVISION BY ZERO"
    if isinstance(error, OverflowError):
        return "NUMBER TOO LARGE"
    return f"NOT A NUMBER ({str(error).upper()})"  # V+ functions: SQRT(-1), MOD(1, 0)


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
    for number_, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        label, text = split_label(line.expandtabs())
        steps.append(ProgramLine(label, text, number_))
    return Program(name.upper(), steps)
