"""``valterm import FILE --out NAME.SET | --into NAME.SET``: a CAD file to a setup file (§7.1).

FILE is an IGES file (.igs/.iges), a STEP file (.step/.stp: through the optional OpenCASCADE
binding, ``pip install 'valterm[step]'``; each solid a part named as in the file) or a polygon mesh (.stl/.obj/.ply/.off/.glb/.gltf): a path,
or a file in the workspace. ``--out`` writes a new setup file NAME.SET into the workspace
(an existing one only with --force); ``--into`` appends the parts to an existing setup file,
keeping its objects, their numbers, its units and frame (with --out as well, the combined
setup goes to --out instead). The parts land on a free spot of a table in front of the robot.
The options answer the thesis's questions: --parts (the number of workpieces), --units
(MM/IN/M: what the file's numbers are; default the file's own: the IGES header, the STEP
length unit, metres for
glTF/GLB, millimetres for other meshes), --system (W/S: the axes they are given in).
Bad input exits 2 with ``FILE:LINE: reason`` on stderr; nothing is half-written.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from valterm.commands import FAILURE, USAGE, fail
from valterm.core.cad.errors import CadImportError
from valterm.core.errors import ValtermError
from valterm.core.files.errors import error_message


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    parser = subparsers.add_parser(
        "import", help="turn an IGES, STEP or mesh file into a work-cell setup file (.SET), or add it to one",
        description="Read an IGES, STEP or polygon-mesh file, envelop each part in an extruded convex "
                    "polyhedron, place the parts on a free spot of a table in front of the robot and "
                    "write NAME.SET in the workspace (--out), or append them to an existing one (--into).")
    parser.add_argument("file", metavar="FILE", help="IGES (.igs .iges), STEP (.step .stp; pip install 'valterm[step]') "
                             "or mesh (.stl .obj .ply .off .glb .gltf)")
    parser.add_argument("--out", metavar="NAME.SET", help="the setup file to write (1-9 of A-Z 0-9)")
    parser.add_argument("--into", metavar="NAME.SET", help="an existing setup file the parts are added to")
    parser.add_argument("--units", type=str.upper, choices=("MM", "IN", "M"),
                        help="the file's numbers are in these units (default: the file's own: the IGES "
                             "header, the STEP length unit, M for glTF/GLB, MM for STL/OBJ/PLY/OFF)")
    parser.add_argument("--system", type=str.upper, choices=("W", "S"), default="W",
                        help="the file's coordinates are world (W, default) or screen (S) axes")
    parser.add_argument("--parts", type=int, metavar="N",
                        help="number of workpieces: 1 merges everything, N splits into N separate bodies")
    parser.add_argument("--force", action="store_true", help="replace the --out file if it exists")
    parser.set_defaults(func=run_import, parser=parser)


def _source(argument: str, workspace_root: str | None) -> Path:
    given = Path(argument).expanduser()
    if given.is_file() or any(sep in argument for sep in ("/", "\\")):
        return given
    from valterm.core.workspace import Workspace
    root = Workspace.open(workspace_root).root
    found = next((p for p in root.iterdir() if p.name.upper() == argument.upper()), None)
    return found or given


def _set_name(argument: str) -> str:
    """NAME of NAME.SET or NAME (the workspace checks the name itself)."""
    stem, dot, ext = argument.rpartition(".")
    return stem if dot and ext.upper() == "SET" else argument


def _progress(text: str) -> None:
    """A large mesh: what the import is doing, on stderr (stdout keeps the summary)."""
    print(f"import: {text} ...", file=sys.stderr, flush=True)


def run_import(args: argparse.Namespace) -> int:
    from valterm.core.cad.convert import add_parts, import_cad, summary  # not at every start (issue 25)
    from valterm.core.files.setup import write_setup
    from valterm.core.workspace import Workspace

    if not args.out and not args.into:
        return fail("import: give --out NAME.SET (a new setup) or --into NAME.SET (add to a setup)", USAGE)
    root = getattr(args, "workspace", None)
    try:
        workspace = Workspace.open(root)
        # --into: the setup as read; written back only if no other session saved it meanwhile
        stamp = workspace.stamp(_set_name(args.into), "SET") if args.into else None
        setup = workspace.read_setup(_set_name(args.into)) if args.into else None
        out = workspace.path(_set_name(args.out or args.into), "SET")
        source = _source(args.file, root)
        if not source.exists() or source.is_dir():  # a FIFO or a device: its reader says so
            raise CadImportError(source, None, "no such file")
        if args.out and out.exists() and not args.force:
            return fail(f"import: {out.name} exists in the workspace; use --force to replace it", FAILURE)
        cell = import_cad(source, units=args.units, system=args.system, name=out.stem, parts=args.parts,
                          around=setup.objects if setup is not None else (), progress=_progress)
        if setup is not None:
            cell = add_parts(setup, cell)
        same = args.into and out == workspace.path(_set_name(args.into), "SET")
        write_setup(out, cell, stamp if same else None)
    except (ValtermError, OSError) as error:
        return fail(error_message(error), FAILURE)
    for warning in cell.warnings:
        print(f"warning: {warning}", file=sys.stderr)
    added = f", {len(cell.objects) - len(setup.objects)} part(s) added" if setup is not None else ""
    print(f"{out.name} written ({out}){added}")
    print(summary(cell))
    return 0
