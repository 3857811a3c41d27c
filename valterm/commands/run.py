"""``valterm run PROGRAM.DAT [--cell X.SET] [--loc X.LOC] [--loops N] [--json] [--collisions]``

Runs a VAL-II program headless, as EXECUTE would in the VAL-II mode: the transcript shows
each step as it scrolls, TYPE output, messages and errors, then a final WHERE. ``--json``
prints one JSON object a line per event (``{"event": ...}``), the last an ``end`` event
with the final WHERE and the variables.

Files are paths or names in the workspace. Without --cell / --loc, a setup or location
file with the program's own name is used if the workspace has one. CALLed programs are
read from the program's folder first, then the workspace. CHECK.DAT's variables are read
(they are kept across sessions, section 6.7) but not written back. DELAY is not waited.

Exit 0: the program ended normally; 1: a run-time error, or a bad or missing input file
(``valterm: FILE:LINE: reason`` on stderr); 130: aborted with CTRL-C (after the current step).
"""

from __future__ import annotations

import argparse
import json
import signal
import sys
from pathlib import Path
from typing import Any

from valterm.commands import FAILURE, OK, fail


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("run", help="run a VAL-II program headless and print the transcript")
    parser.add_argument("program", metavar="PROGRAM.DAT", help="a path, or a program name in the workspace")
    parser.add_argument("--cell", metavar="X.SET", help="the work-cell setup file")
    parser.add_argument("--loc", metavar="X.LOC", action="append", help="a location file (may repeat)")
    parser.add_argument("--loops", type=int, default=1, metavar="N",
                        help="execution passes (EXECUTE name,N; negative = 1000)")
    parser.add_argument("--json", action="store_true", help="JSON lines, one event each")
    parser.add_argument("--collisions", action="store_true", help="check collisions at every motion step")
    parser.set_defaults(func=run)


def _find(argument: str, ext: str, workspace: Any) -> Path:
    """A path as given if it exists, else NAME.EXT in the workspace."""
    given = Path(argument).expanduser()
    if given.is_file():
        return given
    if any(sep in argument for sep in ("/", "\\")) or given.suffix.upper() not in ("", f".{ext}"):
        raise FileNotFoundError(f"{argument}: no such file")
    path = workspace.path(argument, ext)
    if not path.is_file():
        raise FileNotFoundError(f"{path.name}: not in the workspace {workspace.root}")
    return path


def run(args: argparse.Namespace) -> int:
    from valterm.core.events import End, Error, Pause
    from valterm.core.files.errors import FileFormatError
    from valterm.core.files.locations import read_locations
    from valterm.core.files.programs import read_program
    from valterm.core.files.setup import read_setup
    from valterm.core.simulator import Simulator
    from valterm.core.val.interpreter import Interpreter
    from valterm.core.val.transcript import event_lines, where_lines
    from valterm.core.val.variables import VariableStore
    from valterm.core.workspace import Workspace, WorkspaceError

    try:
        workspace = Workspace.open(getattr(args, "workspace", None))
        program_path = _find(args.program, "DAT", workspace)
        main = read_program(program_path)
        cell_name = args.cell or (main.name if workspace.exists(main.name, "SET") else None)
        cell = read_setup(_find(cell_name, "SET", workspace)) if cell_name else None
        sim = Simulator(cell)
        loc_names = args.loc or ([main.name] if workspace.exists(main.name, "LOC") else [])
        for name in loc_names:
            sim.locations.update(read_locations(_find(name, "LOC", workspace)))
        variables = VariableStore()
        check = workspace.path("CHECK", "DAT")
        if check.is_file():
            variables.load(check)
    except (FileFormatError, WorkspaceError, FileNotFoundError, OSError) as error:
        return fail(error, FAILURE)
    sim.collision_checks = bool(args.collisions)
    folder = program_path.resolve().parent

    def load_program(name: str):  # type: ignore[no-untyped-def]
        if name == main.name:
            return main
        beside = next((p for p in folder.iterdir() if p.name.upper() == f"{name}.DAT"), None)
        return read_program(beside if beside is not None else workspace.path(name, "DAT"))

    interpreter = Interpreter(sim, load_program, variables, keep_variables=workspace.write_variables)
    errors = 0
    aborted = False

    def on_sigint(signum: int, frame: Any) -> None:
        nonlocal aborted
        if aborted:  # a second CTRL-C does not wait for the step to finish
            raise KeyboardInterrupt
        aborted = True
        interpreter.abort()

    previous = signal.signal(signal.SIGINT, on_sigint)
    out = sys.stdout
    try:
        for event in interpreter.execute(main.name, args.loops):
            if isinstance(event, Error):
                errors += 1
            if args.json:
                out.write(json.dumps(event.to_json()) + "\n")
                continue
            for line in event_lines(event):
                out.write(line + "\n")
            if isinstance(event, Pause):
                out.write("(headless: PROCEED)\n")
        where = sim.where()
        end = End(where=where.to_json(), variables=dict(interpreter.variables))
        if args.json:
            out.write(json.dumps(end.to_json()) + "\n")
        else:
            out.write("\n".join(["", "WHERE", *where_lines(where)]) + "\n")
            if interpreter.variables:
                values = "  ".join(f"{k}={_value(v)}" for k, v in interpreter.variables.items())
                out.write(f"VARIABLES  {values}\n")
        out.flush()
    finally:
        signal.signal(signal.SIGINT, previous)
    if aborted:
        return 130
    return FAILURE if errors else OK


def _value(value: float) -> str:
    return str(int(value)) if float(value).is_integer() else f"{value:g}"
