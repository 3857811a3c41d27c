"""``valterm export-program NAME [NAME ...] --out FILE.v2``: workspace programs as a V+ file.

Each program NAME.DAT of the workspace (or a .DAT path) is written as a ``.PROGRAM name()``
... ``.END`` block, its steps as they are (labels kept), in the order given, so V+ tools
and ``valterm check``/``run`` read them back. FILE is a path as any command takes one (a
bare name is in the current folder); the file is written atomically (nothing half-written). ``--with-calls``
adds the programs the named ones CALL (found in the workspace), once each. ``--loc X.LOC``
(may repeat) writes those locations and precision points into a ``.LOCATIONS`` section (in
V+'s X Y Z yaw pitch roll), ``--with-variables`` the workspace's variables (CHECK.DAT) into
``.REALS``, as the controller's STORE keeps them beside the programs.

Where V+ programs live: the workspace's own programs are NAME.DAT files whose names are
1-9 letters or digits (the thesis's DATFILER.DAT lists them). V+ programs keep their
dotted names (``pick.place``) in their ``.v2``/``.pg`` file: that file is the unit of
storage for V+ programs (``check`` and ``run`` read all of its programs; a CALL between
them works), and it is not split into NAME.DAT files.

Exit 0 written; 1 a program cannot be read or the file cannot be written; 2 usage.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from valterm.core.files.vplus import VplusData
    from valterm.core.workspace import Workspace


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    parser = subparsers.add_parser(
        "export-program", help="write workspace programs (NAME.DAT) as a V+ file (.v2/.pg, .PROGRAM blocks)")
    parser.add_argument("names", nargs="+", metavar="NAME", help="a program of the workspace, or a .DAT path")
    parser.add_argument("--out", required=True, metavar="FILE.v2", help="the V+ file to write (.v2 or .pg)")
    parser.add_argument("--with-calls", action="store_true", help="add the programs they CALL")
    parser.add_argument("--loc", action="append", metavar="X.LOC",
                        help="write these locations as a .LOCATIONS section (may repeat)")
    parser.add_argument("--with-variables", action="store_true",
                        help="write the workspace's variables (CHECK.DAT) as a .REALS section")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from valterm.core.errors import ValtermError
    from valterm.core.files.atomic import write_text_atomic
    from valterm.core.files.vplus import EXTENSIONS, VplusProgram, format_vplus
    from valterm.core.workspace import Workspace

    out = Path(args.out).expanduser()
    if out.suffix.upper() not in EXTENSIONS:
        print(f"--out {args.out}: a V+ file ends in .v2 or .pg", file=sys.stderr)
        return 2
    try:
        workspace = Workspace.open(getattr(args, "workspace", None))
        programs = _collect(args.names, workspace, args.with_calls)
        blocks = [VplusProgram(program, list(program.parameters)) for program in programs]
        write_text_atomic(out, format_vplus(blocks, _data(args, workspace)))
    except (ValtermError, OSError) as error:
        print(error, file=sys.stderr)
        return 1
    print(f"{out}: {len(blocks)} program(s) written ({', '.join(p.name for p in programs)})")
    return 0


def _data(args: argparse.Namespace, workspace: Workspace) -> VplusData:
    """The data sections asked for: --loc files' locations and points, --with-variables."""
    from valterm.core.files.locations import read_location_file
    from valterm.core.files.vplus import VplusData

    data = VplusData()
    for name in args.loc or []:
        path = Path(name).expanduser()
        if not path.is_file():
            path = workspace.path(Path(name).stem, "LOC")
        locations, points = read_location_file(path)
        data.locations.update(locations)
        data.precision.update(points)
    if args.with_variables:
        data.reals.update(workspace.read_variables())
    return data


def _collect(names: list[str], workspace: object, with_calls: bool) -> list:  # type: ignore[type-arg]
    """The programs named, then (with_calls) those they CALL, each once, in that order."""
    from valterm.core.files.programs import read_program
    from valterm.core.val.compiler import analyse

    found: dict[str, object] = {}
    queue = list(names)
    while queue:
        name = queue.pop(0)
        path = Path(name).expanduser()
        program = read_program(path) if path.is_file() else workspace.read_program(name)  # type: ignore[attr-defined]
        if program.name in found:
            continue
        found[program.name] = program
        if with_calls:
            queue.extend(called for _index, called in analyse(program).calls if called not in found)
    return list(found.values())
