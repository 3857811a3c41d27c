"""``valterm cell show FILE.SET [--json]``: what a setup file holds, in world millimetres.

FILE is a path, or a name in the workspace (``PROCESS`` or ``PROCESS.SET``). A malformed
or missing file exits 1 with ``valterm: FILE:LINE: reason`` on stderr; warnings (inward
winding...) go to stderr too.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from valterm.commands import FAILURE, USAGE, fail, say
from valterm.core.cell.workcell import WorkCell
from valterm.core.files.errors import FileFormatError
from valterm.core.files.setup import read_setup
from valterm.core.workspace import Workspace, WorkspaceError


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    parser = subparsers.add_parser("cell", help="inspect work-cell setup files (.SET)")
    actions = parser.add_subparsers(dest="cell_command", metavar="ACTION")
    show = actions.add_parser("show", help="list a setup file's objects and their world vertices (mm)")
    show.add_argument("file", metavar="FILE.SET", help="a path, or a setup name in the workspace")
    show.add_argument("--json", action="store_true", help="print JSON instead of a table")
    show.set_defaults(func=show_cell)
    parser.set_defaults(func=lambda args: _usage(parser))


def _usage(parser: argparse.ArgumentParser) -> int:
    parser.print_usage(sys.stderr)
    return fail("cell: say what to do, e.g. `valterm cell show PROCESS.SET`", USAGE)


def find_setup(argument: str, workspace_root: str | None) -> Path:
    """An existing path as given, else the name in the workspace."""
    given = Path(argument).expanduser()
    if given.is_file():
        return given
    looks_like_path = any(sep in argument for sep in ("/", "\\")) or given.suffix.upper() not in ("", ".SET")
    if looks_like_path:
        raise FileNotFoundError(f"{argument}: no such setup file")
    return Workspace.open(workspace_root).path(argument, "SET")


def show_cell(args: argparse.Namespace) -> int:
    try:
        path = find_setup(args.file, getattr(args, "workspace", None))
        cell = read_setup(path)
    except (FileFormatError, WorkspaceError, OSError) as error:
        return fail(error, FAILURE)
    for warning in cell.warnings:
        say(f"warning: {warning}")
    if args.json:
        print(json.dumps(cell_json(cell), indent=1))
    else:
        print(cell_text(cell), end="")
    return 0


def cell_json(cell: WorkCell) -> dict[str, object]:
    return {
        "name": cell.name,
        "units": cell.units,
        "system": cell.system,
        "objects": [
            {"number": number, "vertices": [[round(float(c), 6) + 0.0 for c in v] for v in polyhedron.vertices]}
            for number, polyhedron in enumerate(cell.objects, start=1)
        ],
        "warnings": list(cell.warnings),
    }


def cell_text(cell: WorkCell) -> str:
    count = len(cell.objects)
    frame = "world (W)" if cell.system == "W" else "screen (S)"
    lines = [f"{cell.name}: {count} object{'s' if count != 1 else ''}, units {cell.units}, {frame}; world vertices in mm"]
    for number, polyhedron in enumerate(cell.objects, start=1):
        lines.append(f"object {number}: {len(polyhedron.vertices)} vertices")
        for index, vertex in enumerate(polyhedron.vertices, start=1):
            x, y, z = (float(c) + 0.0 for c in vertex)
            lines.append(f"  {index:>3} {x:10.2f} {y:10.2f} {z:10.2f}")
    return "\n".join(lines) + "\n"
