"""``import_cad``: a CAD file -> a WorkCell ready to be written as a setup file (§7.1).

The thesis's IGES path asked for the setup-file name, the number of workpieces, their units
(MM/IN) and the coordinate system (W/S), then "placed the parts at the origin of the user
specified coordinate axes". Here:

* the file's numbers are read in its own units unless ``units`` says they are ``MM``, ``IN``
  or ``M``: an IGES file by its header's units flag; a STEP file by its length unit (read
  through the optional OpenCASCADE binding, ``valterm.core.cad.step``); a glTF/GLB in metres with Y up (its
  specification says so; turned to the world's Z up as export turns it back); STL/OBJ/PLY/OFF
  carry no units and are taken as millimetres. A part implausibly small (under 2 mm: a file
  in metres read as millimetres) or large (over 20 m) is kept, with a warning that names
  the units to give instead;
* the numbers are coordinates in the chosen system: ``W`` world as is (a glTF's Y up turned to
  Z up), ``S`` screen axes (X_s = Y_w, Y_s = Z_w + 26, Z_s = X_w), so a model drawn Y-up
  stands upright (a glTF's numbers taken as written);
* all parts move together (their arrangement kept) onto a free spot of a table in front of
  the robot, clear of it and of the objects ``around`` them (``valterm.core.cad.placement``);
  or, when ``place_at`` is given, so the minimum corner of their joint box sits there (in the
  chosen system), as the thesis did;
* each part becomes its extruded convex envelope (``valterm.core.cad.hull``), named as the
  file names it (IGES entity label, STEP product, mesh geometry name).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from valterm.core.cad.axes import world_to_gltf
from valterm.core.cad.errors import CadImportError, DegeneratePart, check_cad_file
from valterm.core.cad.hull import MIN_DEPTH_MM, extruded_hull
from valterm.core.cad.mesh import MESH_EXTENSIONS, METRE_EXTENSIONS, Y_UP_EXTENSIONS, read_mesh_parts
from valterm.core.cad.placement import place_on_table
from valterm.core.cad.step import STEP_EXTENSIONS, read_step_parts, step_mm_per_unit
from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.cell.workcell import WorkCell

if TYPE_CHECKING:
    from valterm.core.cad.iges import Part

IGES_EXTENSIONS = (".igs", ".iges")
SCS_HEIGHT = 26.0
UNITS_MM = {"MM": 1.0, "IN": 25.4, "M": 1000.0}


def scs_to_world(p: np.ndarray) -> np.ndarray:
    """SCS -> WCS for (..., 3) points: X_w = Z_s, Y_w = X_s, Z_w = Y_s - 26."""
    p = np.asarray(p, dtype=float)
    return np.stack([p[..., 2], p[..., 0], p[..., 1] - SCS_HEIGHT], -1)


def setup_name(path: str | Path) -> str:
    """A workspace-legal name (1-9 of A-Z, 0-9) from a file name."""
    name = re.sub(r"[^A-Z0-9]", "", Path(path).stem.upper())[:9]
    return name or "CAD"


def read_parts(path: str | Path, parts: int | None = None,
               progress: Callable[[str], None] | None = None) -> tuple[list[Part], float, str, list[str]]:
    """Parts (points in mm by the file's units), mm per file unit, the file's units and warnings.

    The units are MM, IN or M: what the file says (IGES header; glTF/GLB metres) or MM."""
    from valterm.core.cad.iges import Part, read_iges  # the readers load when a file is read

    path = Path(path)
    ext = path.suffix.lower()
    check_cad_file(path)  # a FIFO would block a reader for ever, /dev/zero fill the memory
    if ext in IGES_EXTENSIONS:
        model = read_iges(path)
        return model.parts(parts), model.mm_per_unit, file_units(model.mm_per_unit), model.warnings
    if ext in MESH_EXTENSIONS + STEP_EXTENSIONS:
        if ext in STEP_EXTENSIONS:  # in mm already, by the file's own unit
            found, mm_per_unit = read_step_parts(path, progress)
        else:
            found, mm_per_unit = read_mesh_parts(path, progress), 1.0
        if parts is not None and parts != len(found):
            if parts != 1:
                raise CadImportError(path, None, f"asked for {parts} workpieces; the file holds {len(found)} meshes")
            found = [Part(setup_name(path), np.concatenate([p.points for p in found]), [])]
        if ext in METRE_EXTENSIONS:
            return [Part(p.name, p.points * 1000.0, p.entities) for p in found], 1000.0, "M", []
        return found, mm_per_unit, file_units(mm_per_unit), []
    known = ", ".join(IGES_EXTENSIONS + STEP_EXTENSIONS + MESH_EXTENSIONS)
    raise CadImportError(path, None, f"unknown CAD file type {ext or '(none)'}; use one of {known}")


# a part smaller than this (mm) or larger is taken for a file read in the wrong units
PLAUSIBLE_MM = (2.0, 20_000.0)


def unit_warnings(found: Sequence[Part], rescale: float, units: str) -> list[str]:
    """One warning when the parts, read as ``units``, are implausibly small or large for a
    robot's work cell, naming the units that would give them a plausible size."""
    if not found:
        return []
    points = np.concatenate([p.points for p in found]) * rescale
    size = float(np.ptp(points, axis=0).max()) if len(points) else 0.0
    low, high = PLAUSIBLE_MM
    if size <= 0 or low <= size <= high:
        return []
    mm_per_given = UNITS_MM.get(units, 1.0)
    sizes = {u: size / mm_per_given * mm for u, mm in UNITS_MM.items() if u != units}
    fixes = sorted((u for u, s in sizes.items() if low <= s <= high), key=lambda u: abs(np.log(sizes[u] / 300.0)))
    fix = (f"if its numbers are {_UNIT_WORDS[fixes[0]]}, import it again with units {fixes[0]} "
           f"(valterm import --units {fixes[0]}; the app asks the units)") if fixes else "check the file's units"
    said = "small" if size < low else "large"
    return [f"the parts are {size:.4g} mm across, implausibly {said} for a work cell read as "
            f"{_UNIT_WORDS.get(units, units)}: {fix}"]


_UNIT_WORDS = {"MM": "millimetres", "IN": "inches", "M": "metres"}


def file_units(mm_per_unit: float) -> str:
    """MM, IN or M for a file's millimetres per unit (other units read as their millimetres)."""
    return {25.4: "IN", 1000.0: "M"}.get(mm_per_unit, "MM")


def native_units(path: str | Path) -> str:
    """The units a CAD file's numbers are in by its own account (MM, IN or M), for a prompt."""
    path = Path(path)
    ext = path.suffix.lower()
    if ext in IGES_EXTENSIONS:
        from valterm.core.cad.iges import read_iges

        return file_units(read_iges(path).mm_per_unit)
    if ext in STEP_EXTENSIONS:
        return file_units(step_mm_per_unit(path))
    return "M" if ext in METRE_EXTENSIONS else "MM"


def import_cad(path: str | Path, units: str | None = None, system: str = "W", name: str | None = None,
               place_at: Sequence[float] | None = None, parts: int | None = None,
               min_depth: float = MIN_DEPTH_MM, around: Sequence[Polyhedron] = (),
               progress: Callable[[str], None] | None = None) -> WorkCell:
    """Read an IGES, STEP or mesh file into a WorkCell of extruded convex polyhedra (world mm).

    ``around``: the objects already in the setup the parts join (they land clear of them).
    ``progress``: told what is being done while a large mesh is read.
    Raises ``CadImportError`` (``file:line: reason``) for anything it cannot use.
    """
    path = Path(path)
    system = system.upper()
    if system not in ("W", "S"):
        raise CadImportError(path, None, f"coordinate system {system!r} is not W or S")
    if units is not None and units.upper() not in UNITS_MM:
        raise CadImportError(path, None, f"units {units!r} are not MM, IN or M")
    if parts is not None and parts < 1:
        raise CadImportError(path, None, f"number of workpieces {parts} must be at least 1")
    found, mm_per_unit, units_of_file, warnings = read_parts(path, parts, progress)
    warnings = list(warnings)
    rescale = UNITS_MM[units.upper()] / mm_per_unit if units is not None else 1.0
    warnings.extend(unit_warnings(found, rescale, (units or units_of_file).upper()))

    objects = []
    for part in found:
        pts = part.points * rescale
        if system == "S":
            # S says the file's own numbers are screen axes: a glTF's are taken as written
            pts = scs_to_world(world_to_gltf(pts) if path.suffix.lower() in Y_UP_EXTENSIONS else pts)
        try:
            poly, notes = extruded_hull(pts, part.name, min_depth)
        except DegeneratePart as exc:
            if parts is not None or len(found) == 1:
                raise CadImportError(path, None, f"part {part.name}: {exc}") from None
            warnings.append(f"part {part.name} left out: {exc}")
            continue
        objects.append(poly)
        warnings.extend(notes)
    if not objects:
        raise CadImportError(path, None, "no part with a usable outline")

    if place_at is None:
        objects, notes = place_on_table(objects, around)
        warnings.extend(notes)
    else:
        lo = np.min([p.vertices.min(axis=0) for p in objects], axis=0)
        target = np.asarray(place_at, dtype=float)
        target = scs_to_world(target) if system == "S" else target
        objects = [p.translated(target - lo) for p in objects]
    # a setup file holds MM or IN; metres are written as millimetres
    written = (units or units_of_file).upper()
    return WorkCell(objects=objects, units="IN" if written == "IN" else "MM", system=system,
                    name=name or setup_name(path), warnings=warnings)


def add_parts(setup: WorkCell, parts: WorkCell) -> WorkCell:
    """The setup with ``parts`` appended after its own objects (which keep their numbers);
    the setup's units and frame stay those of its file."""
    return WorkCell(objects=list(setup.objects) + list(parts.objects), units=setup.units, system=setup.system,
                    name=setup.name, warnings=list(parts.warnings))


def summary(cell: WorkCell) -> str:
    """One line per part: vertices and size in millimetres, then the joint size."""
    lines = []
    for i, p in enumerate(cell.objects, 1):
        lo, hi = p.extreme_box
        size = " x ".join(f"{v:.2f}" for v in hi - lo)
        lines.append(f"part {i} {p.name}: {len(p.vertices)} vertices, {size} mm")
    lo = np.min([p.vertices.min(axis=0) for p in cell.objects], axis=0)
    hi = np.max([p.vertices.max(axis=0) for p in cell.objects], axis=0)
    lines.append(f"{len(cell.objects)} part(s), {' x '.join(f'{v:.2f}' for v in hi - lo)} mm overall, "
                 f"units {cell.units}, system {cell.system}")
    return "\n".join(lines)
