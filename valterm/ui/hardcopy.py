"""H_HARDCOPY: the screen as an SVG and a plain-text printout of the cell and the pose."""

from __future__ import annotations

import os
import time
from pathlib import Path
from typing import TYPE_CHECKING

from valterm.core.files.atomic import write_text_atomic
from valterm.core.render.raster import rasterize
from valterm.core.text.transcript import where_lines
from valterm.ui.widgets.readouts import format_part

if TYPE_CHECKING:  # annotations only
    from valterm.ui.app import ValtermApp

PRINT_WIDTH = 100
PRINT_HEIGHT = 40


def next_name(root: Path, stem: str = "HCOPY") -> str:
    """HCOPY1, HCOPY2, ... : the first number with neither .SVG nor .TXT taken (≤ 9 chars).

    A name is taken by any directory entry, a dangling link included (never written through)."""
    for number in range(1, 10_000):
        name = f"{stem}{number}"
        if not os.path.lexists(root / f"{name}.SVG") and not os.path.lexists(root / f"{name}.TXT"):
            return name
    raise OSError("no free HCOPY name left in the workspace")


def printout(app: ValtermApp) -> str:
    """The text printout: the setup, the clamp readout, every part, the model in ASCII."""
    session = app.active_session
    simulator = session.simulator
    lines = [
        "VAL-II SIMULATOR HARDCOPY",
        time.strftime("%d-%b-%Y %H:%M:%S").upper(),
        f"SETUP FILE {session.setup_name}.SET, {len(simulator.cell.objects)} PARTS",
        "",
        *where_lines(simulator.where(1)),
        "",
    ]
    for number, part in enumerate(simulator.cell.objects, start=1):
        lines += format_part(number, [float(v) for v in part.reference])
    scene = app.scene()
    assert scene is not None, "a hardcopy without a cell"  # H is a key of MAIN MENU, shown with a set-up
    frame = rasterize(scene, app.view_transform, PRINT_WIDTH, PRINT_HEIGHT,
                      back_faces=app.back_faces, axes=app.axes, ascii=True)
    lines += ["", *(line.rstrip() for line in frame.lines())]
    return "\n".join(lines) + "\n"


def write_hardcopy(app: ValtermApp) -> tuple[Path, Path]:
    """Write HCOPYn.SVG (the screen) and HCOPYn.TXT (the printout) into the workspace,
    each through the one safe write path (atomic, never through a link)."""
    workspace = app.active_session.workspace
    name = next_name(workspace.root)
    svg_path = workspace.path(name, "SVG")
    text_path = workspace.path(name, "TXT")
    write_text_atomic(text_path, printout(app))
    write_text_atomic(svg_path, app.export_screenshot())
    return svg_path, text_path
