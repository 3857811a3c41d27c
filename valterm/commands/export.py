"""``valterm export NAME.SET --out FILE.glb|.obj|.stl``: the cell and the robot for other programs.

The command-line twin of the main menu's G (GENERATE). The robot stands at READY, at the
joint angles of ``--pose J1,..,J6`` (degrees), or at location NAME of a location file
(``--loc FILE --at NAME``; the first of the user's configurations that reaches it, RIGHTY
ABOVE NOFLIP first, as the simulator starts). ``--no-robot`` writes the cell alone.
GLB is in metres with Y up as glTF requires; OBJ and STL keep the world's millimetres, Z up
(the command says which). FILE is a path: a relative one is relative to the current folder,
as for any command (main menu G in the app writes into the workspace).
Exit status 0 written, 1 failed (no such setup file or location, out of reach, cannot
write), 2 usage (a malformed --pose, an unknown format); the reason goes to stderr and
nothing is half-written.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from valterm.core.errors import RefusedValue


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    parser = subparsers.add_parser(
        "export", help="write a setup file's cell and the robot as GLB (metres, Y up), OBJ or STL (mm, Z up)",
        description="Export the objects of NAME.SET and the robot (at READY, a pose or a location) "
                    "as polygon meshes for other programs: GLB in metres with Y up as glTF requires, "
                    "OBJ and STL in millimetres with Z up.")
    parser.add_argument("setup", metavar="NAME.SET", help="the setup file in the workspace")
    parser.add_argument("--out", required=True, metavar="FILE", help="FILE.glb, FILE.obj or FILE.stl")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--pose", metavar="J1,..,J6",
                       help="the robot's joint angles in degrees (default READY); --pose=-10,... when J1 < 0")
    where.add_argument("--loc", metavar="FILE", help="a location file (NAME.LOC) of the workspace; with --at")
    parser.add_argument("--at", metavar="NAME", help="the location of --loc the robot's tool stands at")
    where.add_argument("--no-robot", action="store_true", help="the cell alone")
    parser.set_defaults(func=run_export, parser=parser)


def _stem(argument: str, ext: str) -> str:
    stem, dot, given = argument.rpartition(".")
    return stem if dot and given.upper() == ext else argument


def _pose(text: str) -> list[float]:
    fields = [f for f in text.replace(" ", ",").split(",") if f]
    try:
        joints = [float(f) for f in fields]
    except ValueError:
        joints = []
    if len(joints) != 6 or not all(abs(j) < 1e6 for j in joints):
        raise RefusedValue(f"--pose needs six joint angles in degrees, J1,..,J6; not {text!r}")
    return joints


def _joints_at(location: object) -> tuple[list[float], str]:
    """JT1..JT6 reaching ``location`` in the first configuration that can, and its words."""
    from valterm.core.kinematics import Config, IKError, ik_oat

    reason = ""
    for arm in (1, -1):
        for elbow in (1, -1):
            for wrist in (1, -1):
                config = Config(arm, elbow, wrist)
                try:
                    return ik_oat(location.xyz, location.oat, config), str(config)  # type: ignore[attr-defined]
                except IKError as error:
                    reason = reason or str(error)
    raise RefusedValue(f"the robot cannot reach it in any configuration ({reason})")


def _out_path(argument: str) -> Path:
    """--out as the shell means it: relative to the current folder."""
    return Path(argument).expanduser().absolute()


def run_export(args: argparse.Namespace) -> int:
    from valterm.core.cad.export import EXPORT_EXTENSIONS, EXPORT_UNITS, export_scene
    from valterm.core.errors import ValtermError
    from valterm.core.simulator import default_model
    from valterm.core.workspace import Workspace

    if args.at and not args.loc or args.loc and not args.at:
        args.parser.error("--loc FILE and --at NAME go together")
    if Path(args.out).suffix.lower() not in EXPORT_EXTENSIONS:
        args.parser.error(f"--out {args.out}: use FILE.glb, FILE.obj or FILE.stl")
    try:
        pose = _pose(args.pose) if args.pose else None
    except RefusedValue as error:
        args.parser.error(str(error))
    try:
        workspace = Workspace.open(getattr(args, "workspace", None))
        cell = workspace.read_setup(_stem(args.setup, "SET"))
        model = default_model()
        joints: Sequence[float] = model.geometry.ready
        said = "READY"
        if pose is not None:
            joints, said = pose, f"pose {args.pose}"
        elif args.loc:
            points = workspace.read_locations(_stem(args.loc, "LOC"))
            name = args.at.upper()
            if name not in points:
                raise RefusedValue(f"{_stem(args.loc, 'LOC').upper()}.LOC has no location {name}")
            joints, config = _joints_at(points[name])
            said = f"location {name} ({config})"
        robot = [] if args.no_robot else model.place(joints)
        out = export_scene(cell, robot, _out_path(args.out))
    except ValtermError as error:
        print(f"valterm export: {error}", file=sys.stderr)
        return 1
    except OSError as error:
        print(f"valterm export: {error.strerror or error}: {error.filename or ''}", file=sys.stderr)
        return 1
    robot_said = "no robot" if args.no_robot else f"the robot at {said}"
    print(f"{out} written: {len(cell.objects)} part(s) and {robot_said}; "
          f"units {EXPORT_UNITS[out.suffix.lower()]}")
    return 0
