"""``valterm import FILE --out NAME.SET``: a CAD file to a setup file, with no questions (§7.1).

FILE is an IGES file (.igs/.iges) or a polygon mesh (.stl/.obj/.ply/.off/.glb/.gltf): a path,
or a file in the workspace. The setup file is written into the workspace under NAME.SET.
The options answer the thesis's questions: --parts (the number of workpieces), --units
(MM/IN: what the file's numbers are), --system (W/S: the axes they are given in).
Bad input exits 2 with ``FILE:LINE: reason`` on stderr.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from valterm.core.cad.convert import import_cad, summary
from valterm.core.cad.errors import CadImportError
from valterm.core.files.errors import error_message


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "import", help="turn an IGES or mesh file into a work-cell setup file (.SET)",
        description="Read an IGES or polygon-mesh file, envelop each part in an extruded convex "
                    "polyhedron, place the parts at the origin and write NAME.SET in the workspace.")
    parser.add_argument("file", metavar="FILE", help="IGES (.igs .iges) or mesh (.stl .obj .ply .off .glb .gltf)")
    parser.add_argument("--out", required=True, metavar="NAME.SET", help="setup file name (1-9 of A-Z 0-9)")
    parser.add_argument("--units", type=str.upper, choices=("MM", "IN"),
                        help="the file's numbers are in these units (default: the file's own; meshes MM)")
    parser.add_argument("--system", type=str.upper, choices=("W", "S"), default="W",
                        help="the file's coordinates are world (W, default) or screen (S) axes")
    parser.add_argument("--parts", type=int, metavar="N",
                        help="number of workpieces: 1 merges everything, N splits into N separate bodies")
    parser.add_argument("--force", action="store_true", help="replace NAME.SET if it exists")
    parser.set_defaults(func=run_import)


def _source(argument: str, workspace_root: str | None) -> Path:
    given = Path(argument).expanduser()
    if given.is_file() or any(sep in argument for sep in ("/", "\\")):
        return given
    from valterm.core.workspace import Workspace
    root = Workspace.open(workspace_root).root
    found = next((p for p in root.iterdir() if p.name.upper() == argument.upper()), None)
    return found or given


def run_import(args: argparse.Namespace) -> int:
    from valterm.core.files.setup import write_setup
    from valterm.core.workspace import Workspace, WorkspaceError

    root = getattr(args, "workspace", None)
    try:
        workspace = Workspace.open(root)
        out = workspace.path(args.out, "SET")
        source = _source(args.file, root)
        if not source.is_file():
            raise CadImportError(source, None, "no such file")
        if out.exists() and not args.force:
            print(f"valterm import: {out.name} exists in the workspace; use --force to replace it", file=sys.stderr)
            return 2
        cell = import_cad(source, units=args.units, system=args.system, name=out.stem, parts=args.parts)
        write_setup(out, cell)
    except (CadImportError, WorkspaceError) as error:
        print(error, file=sys.stderr)
        return 2
    except OSError as error:
        print(f"valterm import: {error_message(error)}", file=sys.stderr)
        return 2
    for warning in cell.warnings:
        print(f"warning: {warning}", file=sys.stderr)
    print(f"{out.name} written ({out})")
    print(summary(cell))
    return 0
