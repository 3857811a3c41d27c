"""STEP import (ISO 10303-21: AP203/AP214/AP242), the CAD systems' first export for solids.

A STEP file holds exact solids (B-rep), not triangles: OpenCASCADE, through the optional
``cascadio`` binding (``pip install 'valterm[step]'``), tessellates them and trimesh reads the
result as a scene, one node per solid, named as the file names its product. The scene comes
in metres with the file's own Z up, whatever length unit the file was written in (OpenCASCADE
applies the file's unit); the unit the file declares (its first ``LENGTH_UNIT``) is read here
as well, so the setup file keeps inches when the file is in inches and ``--units`` can say the
numbers are something else.

Without the extra the import says which extra to install, in one line.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from valterm.core.cad.errors import CadImportError, read_cad_bytes
from valterm.core.cad.mesh import LARGE_BYTES, Progress, _check_count, _quiet_trimesh, _reason

if TYPE_CHECKING:        # the IGES reader loads when a file is read (issue 25: start time)
    from valterm.core.cad.iges import Part

STEP_EXTENSIONS = (".step", ".stp")
EXTRA_HINT = "pip install 'valterm[step]'"

# millimetres per unit of a STEP length unit: SI_UNIT(prefix, .METRE.) or a named conversion
_SI_PREFIX_MM = {"$": 1000.0, ".MILLI.": 1.0, ".CENTI.": 10.0, ".DECI.": 100.0, ".KILO.": 1_000_000.0,
                 ".MICRO.": 0.001}
_CONVERSION_MM = {"INCH": 25.4, "FOOT": 304.8, "MILLIMETRE": 1.0, "METRE": 1000.0}
_LENGTH_UNIT = re.compile(rb"\(\s*([^;]*?LENGTH_UNIT\s*\(\s*\)[^;]*?)\)\s*;", re.S)
_SI_UNIT = re.compile(rb"SI_UNIT\s*\(\s*(\$|\.[A-Z]+\.)\s*,\s*\.METRE\.\s*\)")
_CONVERSION = re.compile(rb"CONVERSION_BASED_UNIT\s*\(\s*'([^']*)'")


def require_cascadio(path: str | Path) -> None:
    """CadImportError naming the extra when the OpenCASCADE binding is not installed."""
    try:
        import cascadio  # noqa: F401  (trimesh loads STEP through it)
    except ImportError:
        raise CadImportError(path, None, f"reading STEP files needs the optional OpenCASCADE binding "
                                         f"cascadio: {EXTRA_HINT}") from None


def step_mm_per_unit(path: str | Path, data: bytes | None = None) -> float:
    """Millimetres per length unit the file declares (its first ``LENGTH_UNIT``; mm if none)."""
    if data is None:
        data = read_cad_bytes(path)
    found = _LENGTH_UNIT.search(data.upper())
    if found is None:
        return 1.0
    unit = found.group(1)
    named = _CONVERSION.search(unit)
    if named is not None:
        return _CONVERSION_MM.get(named.group(1).decode(errors="replace").strip(), 1.0)
    si = _SI_UNIT.search(unit)
    return _SI_PREFIX_MM.get(si.group(1).decode(), 1.0) if si is not None else 1.0


def read_step_parts(path: str | Path, progress: Progress | None = None) -> tuple[list[Part], float]:
    """The solids of a STEP file as parts in millimetres, and the millimetres per file unit."""
    path = Path(path)
    data = read_cad_bytes(path)
    if not data.lstrip().startswith(b"ISO-10303-21"):
        raise CadImportError(path, 1, "not a STEP file (it does not begin with ISO-10303-21;)")
    require_cascadio(path)
    mm_per_unit = step_mm_per_unit(path, data)
    large = len(data) >= LARGE_BYTES
    del data
    import trimesh

    if progress is not None and large:
        progress(f"{path.name}: OpenCASCADE is tessellating the solids")
    try:
        with _quiet_trimesh():
            scene = trimesh.load_scene(str(path))
    except Exception as exc:  # the binding raises many kinds on junk input; all mean "unreadable"
        raise CadImportError(path, None, f"not a readable STEP file ({_reason(exc)})") from None
    _check_count(path, sum(len(getattr(g, "faces", ())) for g in scene.geometry.values()), progress)
    scale = 1000.0 if scene.units in (None, "m", "meter", "meters") else _scale_to_mm(path, str(scene.units))
    parts: list[Part] = []
    for node in scene.graph.nodes_geometry:
        transform, geom_name = scene.graph[node]
        vertices = getattr(scene.geometry.get(geom_name), "vertices", None)
        if vertices is None or len(vertices) == 0:
            continue
        matrix = np.asarray(transform, dtype=float)
        v = (np.asarray(vertices, dtype=float) @ matrix[:3, :3].T + matrix[:3, 3]) * scale
        if not np.all(np.isfinite(v)):
            raise CadImportError(path, None, f"solid {str(node)[:40]!r} has non-finite coordinates")
        parts.append(_part(str(node), v))
    if not parts:
        raise CadImportError(path, None, "no solid in the file (OpenCASCADE found nothing to tessellate)")
    return parts, mm_per_unit


def _scale_to_mm(path: Path, units: str) -> float:
    """Millimetres per unit of a scene trimesh says is in ``units`` (OpenCASCADE gives metres)."""
    import trimesh

    try:
        return float(trimesh.units.unit_conversion(units, "mm"))
    except (ValueError, KeyError):
        raise CadImportError(path, None, f"the file's units {units!r} are not known") from None


def _part(name: str, points: np.ndarray) -> Part:
    from valterm.core.cad.iges import Part

    return Part(name, points, [])
