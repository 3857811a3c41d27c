"""``valterm render``: the model view's picture without the app (tests, docs, posters, SSH).

``valterm [--workspace W] render [--setup NAME] [--joints J1..J6 | --loc FILE --at NAME]
[--view iso|side|top|front | --azimuth A --elevation E] [--size WxH]
[--trace PROGRAM.DAT --loc FILE] [--svg FILE] [--ascii] [--json]``

The robot stands at READY unless ``--joints`` or ``--at`` place it; ``--trace`` runs the
program headless first (DELAY not waited, CHECK.DAT not written) and draws the clamp's
path, the robot left where the program ended. The text fits ``--size`` exactly; ``--json``
prints ``{"view": {"azimuth": A, "elevation": E}, "size": [W, H], "lines": [...]}``;
``--svg FILE`` also writes the wireframe as vector lines.

Exit 0: drawn; 1: the robot cannot be placed or the program fails; 2: bad arguments or
input files. Errors go to stderr as ``valterm: ...``.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from typing import Any

from valterm.commands.robots import add_robot_option, robot_from
from valterm.core.errors import RefusedValue, ValtermError

DEFAULT_SIZE = (80, 24)


class RenderFailed(Exception):
    """A reason to stop with exit status 1 (the input was fine, the picture cannot be had)."""


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    parser = subparsers.add_parser("render", help="draw the robot and the cell as text (or SVG)")
    # dest names of their own: the top-level --setup / --ascii mean the app's
    parser.add_argument("--setup", dest="render_setup", metavar="NAME", help="the setup file (default PROCESS)")
    place = parser.add_mutually_exclusive_group()
    place.add_argument("--joints", nargs=6, type=float, metavar="J", help="the six joint angles (degrees)")
    place.add_argument("--at", metavar="NAME", help="a location of the --loc file(s)")
    parser.add_argument("--loc", metavar="FILE", action="append", help="a location file (may repeat)")
    parser.add_argument("--view", metavar="NAME", help="iso (default), side, top or front")
    parser.add_argument("--azimuth", type=float, metavar="A", help="degrees from +X towards +Y")
    parser.add_argument("--elevation", type=float, metavar="E", help="degrees above the XY plane")
    parser.add_argument("--size", metavar="WxH", default="80x24", help="characters (default 80x24)")
    parser.add_argument("--trace", metavar="PROGRAM.DAT", help="run a program and draw the clamp's path")
    parser.add_argument("--svg", metavar="FILE", help="also write the picture as SVG")
    parser.add_argument("--ascii", dest="render_ascii", action="store_true", help="ASCII, not braille")
    parser.add_argument("--json", action="store_true", help="JSON: the view and the lines")
    add_robot_option(parser)
    parser.set_defaults(func=run)


def _fail(message: str, status: int) -> int:
    print(f"valterm: {message}", file=sys.stderr)
    return status


def parse_size(text: str) -> tuple[int, int]:
    match = re.fullmatch(r"\s*(\d{1,4})\s*[xX]\s*(\d{1,4})\s*", text or "")
    if not match:
        raise RefusedValue(f"--size {text!r}: give WIDTHxHEIGHT, e.g. 80x24")
    w, h = int(match.group(1)), int(match.group(2))
    if not (8 <= w <= 1000 and 4 <= h <= 500):
        raise RefusedValue(f"--size {text}: from 8x4 to 1000x500 characters")
    return w, h


def _angles(args: argparse.Namespace) -> tuple[float, float]:
    from valterm.core.render.views import DEFAULT_VIEW, preset_angles

    if args.view is not None and (args.azimuth is not None or args.elevation is not None):
        raise RefusedValue("give --view or --azimuth/--elevation, not both")
    if args.azimuth is not None or args.elevation is not None:
        default_az, default_el = preset_angles(DEFAULT_VIEW)
        return (default_az if args.azimuth is None else args.azimuth,
                default_el if args.elevation is None else args.elevation)
    return preset_angles(args.view or DEFAULT_VIEW)


def run(args: argparse.Namespace) -> int:
    from valterm.core.files.errors import error_message
    from valterm.core.render.views import view_axes

    try:
        size = parse_size(args.size)
        azimuth, elevation = _angles(args)
        view_axes(azimuth, elevation)  # checks the angles
        if args.at is not None and not args.loc:
            raise RefusedValue("--at NAME needs --loc FILE")
        session = _session(args)
    except (ValtermError, OSError) as error:
        return _fail(error_message(error), 2)
    try:
        trace = _place(session, args)
        picture = draw(session.simulator, azimuth, elevation, size, trace=trace,
                       ascii=args.render_ascii or bool(getattr(args, "ascii", False)))
        if args.svg:
            from valterm.core.files.atomic import write_text_atomic

            write_text_atomic(args.svg, picture["svg"])
    except RenderFailed as error:
        return _fail(str(error), 1)
    except OSError as error:
        return _fail(error_message(error), 2)
    out = sys.stdout
    if args.json:
        out.write(json.dumps({"view": {"azimuth": azimuth, "elevation": elevation},
                              "size": list(size), "lines": picture["lines"]}) + "\n")
    else:
        out.write("\n".join(picture["lines"]) + "\n")
    return 0


def _session(args: argparse.Namespace) -> Any:
    """The session on the setup, with the location files read."""
    from valterm.core.session import DEFAULT_SETUP, Session

    setup = args.render_setup or getattr(args, "setup", None) or DEFAULT_SETUP  # also `valterm --setup X render`
    session = Session(workspace_root=getattr(args, "workspace", None), setup=setup, robot=robot_from(args))
    for name in args.loc or ():
        session.load_locations(_stem(name, "LOC"))
    if args.trace and not session.workspace.exists(_stem(args.trace, "DAT"), "DAT"):
        raise RefusedValue(f"{args.trace}: no such program in the workspace {session.workspace.root}")
    if args.joints is not None:
        from valterm.core.motion import check_joint_goal

        check_joint_goal(list(args.joints), session.simulator.arm)
    return session


def _stem(name: str, ext: str) -> str:
    """A file name as the workspace takes it: NAME or NAME.EXT."""
    stem = name.strip()
    return stem[: -len(ext) - 1] if stem.upper().endswith(f".{ext}") else stem


def _place(session: Any, args: argparse.Namespace) -> Any:
    """Run the trace program and/or put the robot where asked; the trace (or None)."""
    from valterm.core.events import Error, PoseEvent
    from valterm.core.render.overlays import Trace, clamp_point

    sim = session.simulator
    trace = None
    try:
        if args.trace:
            from valterm.core.val.interpreter import Interpreter

            trace = Trace([clamp_point(sim)])
            # no keep_variables: a picture must not write CHECK.DAT
            interpreter = Interpreter(sim, session.workspace.read_program)
            for event in interpreter.execute(_stem(args.trace, "DAT").upper(), 1):
                if isinstance(event, PoseEvent):
                    trace.add(clamp_point(sim))
                elif isinstance(event, Error):
                    raise RenderFailed(f"{event.program or args.trace}, step {event.step}: {event.message}")
        if args.joints is not None:
            sim.stand_at([float(j) for j in args.joints])
        elif args.at is not None:
            sim.autoconfig = True  # a picture of the location, in whichever configuration reaches it
            for _ in sim.move(args.at.upper()):
                pass
    except ValtermError as error:
        raise RenderFailed(str(error)) from error
    return trace


def draw(sim: Any, azimuth: float, elevation: float, size: tuple[int, int], *, trace: Any = None,
         ascii: bool = False) -> dict[str, Any]:
    """The picture as text lines (exactly ``size``) and SVG."""
    from valterm.core.render.overlays import Overlays, cell_points, picture_scene
    from valterm.core.render.raster import rasterize
    from valterm.core.render.svg import scene_svg
    from valterm.core.render.views import make_view

    view = make_view(cell_points(sim, trace), azimuth, elevation)
    scene = picture_scene(sim, Overlays(trace=trace, axes=True, depth=view))
    width, height = size
    frame = rasterize(scene, view, width, height, back_faces=False, axes=True, ascii=ascii)
    return {"lines": frame.lines(), "frame": frame, "svg": scene_svg(scene, view, width, height)}
