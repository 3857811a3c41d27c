"""``valterm run PROGRAM.DAT [--cell X.SET] [--loc X.LOC] [--loops N] [--json] [--collisions]``

Runs a VAL-II program headless, as EXECUTE would in the VAL-II mode: the transcript shows
each step as it scrolls, TYPE output, messages and errors, then a final WHERE. ``--json``
prints one JSON object a line per event (``{"event": ...}``), the last an ``end`` event
with the final WHERE and the variables.

Files are paths or names in the workspace. Without --cell / --loc, a setup or location
file with the program's own name is used if the workspace has one. CALLed programs are
read from the program's folder first, then the workspace. CHECK.DAT's variables are read
and, when the program ends, written back as EXECUTE does (section 6.7: an assignment
updates CHECK.DAT, so variables are kept across sessions). DELAY is not waited.

A V+ file (``.v2``/``.pg``, ``.PROGRAM`` blocks) runs its main program, the one no other
program of the file CALLs (several: they are listed; ``--program NAME`` chooses); every program of
the file can be CALLed; the file is checked whole first (a bad step anywhere: every error with its
line, exit 1, no step run), and they are v+ (``--dialect v+`` makes .DAT programs v+ too).
``--rules 1985|controller`` picks the joint-state rules (SPEC §3a, docs/MOTION.md; by default
the dialect's: 1985 for .DAT programs, controller for v+); ``--config LEFTY,BELOW`` sets the
user's indicators first; ``--inputs FILE`` scripts the
input signals ("TIME SIGNAL VALUE" lines); precision points (``POINT #SAFE, j1..j6``) in the
location files are read too. Signal changes are in the transcript (``SIGNAL 1 ON``) and JSON.

``--json``'s last event, ``end``, also lists every part of the cell with its final position
(its reference point, world mm) and whether the clamp holds it; collision findings and
grasps carry the program, step and clamp position where they happened.

The run stops at its limits (docs/LIMITS.md): ``--max-steps``, ``--max-seconds`` (robot
time), ``--max-lines`` (transcript lines), with a message naming the limit reached.

Exit 0: the program ended normally; 1: a run-time error, a limit reached, or a bad or missing input file
(``valterm: FILE:LINE: reason`` on stderr); 130: aborted with CTRL-C (after the current step).
"""

from __future__ import annotations

import argparse
import signal
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from valterm.core.errors import RefusedValue
from valterm.commands import FAILURE, OK, USAGE, fail
from valterm.commands.limits import add_limit_flags, limits_from
from valterm.commands.robots import add_robot_option, robot_from
from valterm.core.val import dialects

if TYPE_CHECKING:  # annotations only
    from valterm.core.files.programs import Program


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    parser = subparsers.add_parser("run", help="run a VAL-II program headless and print the transcript")
    parser.add_argument("program", metavar="PROGRAM.DAT", help="a path, or a program name in the workspace")
    parser.add_argument("--cell", metavar="X.SET", help="the work-cell setup file")
    parser.add_argument("--loc", metavar="X.LOC", action="append", help="a location file (may repeat)")
    parser.add_argument("--loops", type=int, default=1, metavar="N",
                        help="execution passes (EXECUTE name,N; negative = 1000)")
    parser.add_argument("--json", action="store_true", help="JSON lines, one event each")
    parser.add_argument("--collisions", action="store_true", help="check collisions at every motion step")
    parser.add_argument("--dialect", choices=dialects.NAMES, default=None,
                        help="the language of .DAT programs (default 1985; a .v2/.pg file is always v+)")
    parser.add_argument("--rules", choices=("1985", "controller"), default=argparse.SUPPRESS,
                        help="the joint-state rules (default: 1985 for the 1985 dialect, controller for v+; "
                             "docs/MOTION.md)")
    parser.add_argument("--config", metavar="LEFTY,ABOVE,NOFLIP",
                        help="the user's configuration indicators at the start (default RIGHTY,ABOVE,NOFLIP)")
    parser.add_argument("--program", metavar="NAME", dest="main_program",
                        help="the main program of a V+ file (default: the one no other program CALLs)")
    parser.add_argument("--inputs", metavar="FILE",
                        help='input signals scripted as "TIME SIGNAL VALUE" lines (V+ SIG, WAIT)')
    add_robot_option(parser)
    add_limit_flags(parser)
    parser.set_defaults(func=run)


def _vplus_setup(args: argparse.Namespace, sim: Any, interpreter: Any, loc_paths: list[Path]) -> None:
    """--config, --inputs, and the precision points of the location files (RefusedValue, FileFormatError)."""
    from valterm.core.files.locations import read_location_file
    from valterm.core.kinematics import CONFIG_WORDS
    from valterm.core.signals import read_inputs

    if args.config:
        for word in (w.strip().upper() for w in args.config.split(",")):
            if word not in CONFIG_WORDS:
                raise RefusedValue(f"--config: {word or '(empty)'} is not one of {', '.join(CONFIG_WORDS)}")
            sim.set_indicator(word)
    if args.inputs:
        interpreter.machine.inputs = read_inputs(args.inputs)
    for path in loc_paths:
        interpreter.machine.precision.update(read_location_file(path)[1])


def _vplus_data(path: Path, sim: Any, interpreter: Any) -> None:
    """A V+ file's .LOCATIONS, .REALS and .STRINGS (as the controller's LOAD would); its
    problems (a bad data line or header) are said on stderr and the run goes on."""
    from valterm.core.files.vplus import EXTENSIONS, read_vplus_file

    if path.suffix.upper() not in EXTENSIONS:
        return
    found = read_vplus_file(path)
    data = found.data
    interpreter.machine.load_data(data, interpreter.variables)  # --loc files' locations win
    interpreter.data_loaded.add(str(path.resolve()))
    for problem in [*data.problems, *(b.problem for b in found.blocks if b.problem)]:
        print(f"valterm: warning: {problem}", file=sys.stderr)


def _errors_of_file(path: Path, in_file: dict[str, Any], dialect: str | None) -> list[str]:
    """Every error of the file's programs, located (``FILE:LINE: PROG step N: reason``), as
    ``check`` reports them: a bad step or .PROGRAM header. Warnings (a step only the real
    controller runs, a CALL of a missing program) are no reason to refuse the file."""
    from valterm.core.files.vplus import EXTENSIONS, read_vplus_file
    from valterm.core.val.checker import check_program

    found: list[str] = []
    if path.suffix.upper() in EXTENSIONS:
        found += [block.problem for block in read_vplus_file(path).blocks if block.problem]
    for program in in_file.values():
        for diagnostic in check_program(program, dialect=dialect).errors:
            found.append(f"{path.name}:{diagnostic.line}: {diagnostic}" if diagnostic.line else str(diagnostic))
    return found


def _locate(argument: str, workspace: Any, chosen: str | None = None) -> tuple[Path, Program, dict[str, Program]]:
    """The program file, its main program (``chosen``, else the one no other program CALLs) and
    the file's programs: a path, NAME.DAT, or a program of one of the workspace's V+ files (any
    name LISTF lists; EXECUTE finds the same)."""
    from valterm.core.files.vplus import read_program_file

    try:
        path = _find(argument, "DAT", workspace)
    except FileNotFoundError:
        found = _workspace_vplus(argument, workspace)
        if found is None:
            raise
        program, path = found
        in_file = {p.name: p for p in read_program_file(path, program.name)[1].values()}
        return path, in_file.get(program.name, program), in_file
    main, in_file = read_program_file(path, chosen)
    return path, main, in_file


def _workspace_vplus(argument: str, workspace: Any) -> Any:
    from valterm.core.errors import ValtermError

    if any(sep in argument for sep in ("/", "\\")):
        return None
    try:
        return workspace.vplus_source(argument)
    except (ValtermError, ValueError):
        return None


def _find(argument: str, ext: str, workspace: Any) -> Path:
    """A path as given if it exists, else NAME.EXT in the workspace."""
    given = Path(argument).expanduser()
    if _there(given):
        return given
    if any(sep in argument for sep in ("/", "\\")) or given.suffix.upper() not in ("", f".{ext}"):
        raise FileNotFoundError(f"{argument}: no such file")
    path: Path = workspace.path(argument, ext)
    if not _there(path):
        raise FileNotFoundError(f"{path.name}: not in the workspace {workspace.root}")
    return path


def _there(path: Path) -> bool:
    """A file is there (a FIFO or a device too: its reader says what it is and refuses it)."""
    return path.exists() and not path.is_dir()


def run(args: argparse.Namespace) -> int:
    from valterm.core.files.errors import FileFormatError
    from valterm.core.files.locations import read_locations
    from valterm.core.files.setup import read_setup
    from valterm.core.rules import rules_of_dialect
    from valterm.core.simulator import Simulator
    from valterm.core.text.transcript import blocks_for, write_events
    from valterm.core.val.interpreter import Interpreter
    from valterm.core.val.variables import VariableStore
    from valterm.core.workspace import Workspace, WorkspaceError

    try:
        workspace = Workspace.open(getattr(args, "workspace", None))
        program_path, main, in_file = _locate(args.program, workspace, getattr(args, "main_program", None))
        cell_name = args.cell or (main.name if _in_workspace(workspace, main.name, "SET") else None)
        cell = read_setup(_find(cell_name, "SET", workspace)) if cell_name else None
        sim = Simulator(cell, robot=robot_from(args))
        loc_names = args.loc or ([main.name] if _in_workspace(workspace, main.name, "LOC") else [])
        loc_paths = [_find(name, "LOC", workspace) for name in loc_names]
        for path in loc_paths:
            sim.locations.update(read_locations(path))
        variables = VariableStore(workspace.read_variables())  # read: a merge writes only this run's changes
    except (FileFormatError, WorkspaceError, FileNotFoundError, OSError) as error:
        return fail(error, FAILURE)
    sim.collision_checks = bool(args.collisions)
    # the program's own dialect when it says one (a V+ file's), else --dialect's (as the interpreter)
    dialect = main.dialect if main.dialect != dialects.DEFAULT else (args.dialect or dialects.DEFAULT)
    sim.set_rules(getattr(args, "rules", None) or rules_of_dialect(dialect))  # SPEC §3a
    load_called = workspace.program_loader(program_path.resolve().parent)

    def load_program(name: str) -> Program:
        if name in in_file:
            return in_file[name]
        return load_called(name)  # through the workspace's checks (no links outside)

    interpreter = Interpreter(sim, load_program, variables, keep_variables=workspace.merge_variables,
                              dialect=args.dialect or "1985", limits=limits_from(args))
    try:
        refused = _errors_of_file(program_path, in_file, args.dialect)
    except (FileFormatError, OSError) as error:
        return fail(error, FAILURE)
    if refused:  # checked whole before any step runs (as the controller's LOAD would refuse it)
        print("\n".join(refused), file=sys.stderr)
        return fail(f"{program_path.name}: {len(refused)} error{'s' if len(refused) != 1 else ''}: "
                    "no step was run (valterm check lists them too)", FAILURE)
    try:
        _vplus_data(program_path, sim, interpreter)
        _vplus_setup(args, sim, interpreter, loc_paths)
    except (FileFormatError, OSError) as error:  # a bad --inputs file
        return fail(error, FAILURE)
    except RefusedValue as error:  # --config that names no indicators
        return fail(error, USAGE)
    aborted = False

    def on_sigint(signum: int, frame: Any) -> None:
        nonlocal aborted
        if aborted:  # a second CTRL-C does not wait for the step to finish
            raise KeyboardInterrupt
        aborted = True
        interpreter.abort()

    previous = signal.signal(signal.SIGINT, on_sigint)
    out = blocks_for(sys.stdout)  # blocks whatever PYTHONUNBUFFERED says; a terminal line by line
    try:
        errors = write_events(interpreter.execute(main.name, args.loops), out, args.json)
        _write_end(args, sim, interpreter, out, main)
    finally:
        signal.signal(signal.SIGINT, previous)
    if aborted:
        return 130
    return FAILURE if errors else OK


def _write_end(args: argparse.Namespace, sim: Any, interpreter: Any, out: Any, main: Any) -> None:
    """The end of a run: the final WHERE, the variables, the signals on and the cycle time."""
    from valterm.core.events import End
    from valterm.core.grading import part_positions
    from valterm.core.text.transcript import where_lines

    where = sim.where()
    readout = dialects.dialect(main.dialect if main.dialect != dialects.DEFAULT else interpreter.dialect).readout
    if readout is not None:
        where = readout(where)  # the dialect's convention (a V+ program's: X Y Z yaw pitch roll)
    panel = interpreter.machine.signals
    end = End(where=where.to_json(), variables=dict(interpreter.variables),
              cycle_time_s=round(interpreter.cycle_seconds, 3),  # the interpreter's clock
              signals_on=tuple(panel.outputs_on() + panel.inputs_on()), parts=part_positions(sim),
              robot=sim.arm.name, robot_key=sim.arm.key)
    if args.json:
        out.write(end.json_line())
    else:
        out.write("\n".join(["", "WHERE", *where_lines(where)]) + "\n")
        if interpreter.variables:
            values = "  ".join(f"{k}={_value(v)}" for k, v in interpreter.variables.items())
            out.write(f"VARIABLES  {values}\n")
        if end.signals_on:
            out.write(f"SIGNALS ON {' '.join(str(n) for n in end.signals_on)}\n")
        out.write(f"CYCLE TIME {interpreter.cycle_seconds:.2f} S (ESTIMATE FOR THE REAL PUMA)\n")
    out.flush()


def _in_workspace(workspace: Any, name: str, ext: str) -> bool:
    """Whether NAME.EXT is in the workspace (a V+ dotted name never is: not a workspace name)."""
    from valterm.core.errors import ValtermError

    try:
        return bool(workspace.exists(name, ext))
    except (ValtermError, ValueError):
        return False


def _value(value: float) -> str:
    return str(int(value)) if float(value).is_integer() else f"{value:g}"
