"""Setup files, NAME.SET (§7.1, App. C §4, Figs. 7-1 and C-22).

::

    14                 number of objects
    MM                 units: MM or IN
    W                  frame: W (WCS) or S (SCS)
    1,8                first and last vertex: N even, >= 8
    440.00 -50.00 -320.00     the reference point (first corner), absolute
    0.00 0.00 0.00            N vertex lines relative to the reference point
    ...

Numbers are separated by commas and/or spaces; blank lines are ignored. Vertices 1..N/2
are the front polygon, N/2+1..N the back one. The WorkCell always holds world millimetres;
it remembers the file's units and frame so writing it back gives the same kind of file.

The format has no place for a part's name, so names (an IGES entity label, a mesh's
geometry name) ride in a comment line before the object's ``1,N`` line: ``; NAME CHASSIS``.
Lines starting with ``;`` are comments (as in a .DAT program); the 1985 layout is otherwise
unchanged. Numbers are written at the precision the format shows (``440.00``: 0.01 mm,
0.0001 in), never as float noise (``2.77e-05``, ``17.141799999999996``).
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np

from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.cell.workcell import WorkCell
from valterm.core.files._text import (
    check_line_lengths,
    decode_text,
    numbered_lines,
    parse_count,
    parse_number,
    read_bytes,
    split_fields,
)
from valterm.core.files.atomic import write_text_atomic
from valterm.core.files.errors import FileFormatError, FileWriteError
from valterm.core.files.limits import MAX_PARTS, MAX_VERTICES
from valterm.core.numbers import numpy_errors

MM_PER_INCH = 25.4
SCS_HEIGHT = 26.0  # H of SPEC §1: Y_s = Z_w + H, in millimetres

UNITS = ("MM", "IN")
SYSTEMS = ("W", "S")
DECIMALS = {"MM": 2, "IN": 4}  # 0.01 mm as Fig. 7-1 prints; the same order of precision in inches
COMMENT = ";"
NAME_TAG = "NAME"


# ---------------------------------------------------------------------------
# Frames and units
# ---------------------------------------------------------------------------

def file_to_world(points: np.ndarray, units: str, system: str) -> np.ndarray:
    """Absolute file coordinates (units, frame) to world millimetres."""
    p = np.asarray(points, dtype=float) * (MM_PER_INCH if units == "IN" else 1.0)
    if system == "S":
        # X_s = Y_w, Y_s = Z_w + H, Z_s = X_w
        p = np.stack([p[:, 2], p[:, 0], p[:, 1] - SCS_HEIGHT], axis=1)
    return p


def world_to_file(points: np.ndarray, units: str, system: str) -> np.ndarray:
    """World millimetres to absolute file coordinates in the given units and frame."""
    p = np.asarray(points, dtype=float)
    if system == "S":
        p = np.stack([p[:, 1], p[:, 2] + SCS_HEIGHT, p[:, 0]], axis=1)
    return p / (MM_PER_INCH if units == "IN" else 1.0)


# ---------------------------------------------------------------------------
# Reading
# ---------------------------------------------------------------------------

class _Lines:
    """The data lines of a file (not blank, not comments) with their numbers, where the file
    ended, and the part names given by ``; NAME ...`` comments, by the data line they precede."""

    def __init__(self, text: str) -> None:
        numbered = numbered_lines(text)
        self._lines: list[tuple[int, str]] = []
        self.names: dict[int, str] = {}
        pending: str | None = None
        for n, line in numbered:
            stripped = line.strip()
            if stripped.startswith(COMMENT):
                words = stripped[1:].split(None, 1)
                if len(words) == 2 and words[0].upper() == NAME_TAG:
                    pending = words[1].strip()
            elif stripped:
                if pending is not None:
                    self.names[n] = pending
                    pending = None
                self._lines.append((n, line))
        self._index = 0
        self.last_line = max((n for n, _ in numbered), default=0)

    def next(self) -> tuple[int, str] | None:
        if self._index >= len(self._lines):
            return None
        found = self._lines[self._index]
        self._index += 1
        return found

    def rest(self) -> Iterator[tuple[int, str]]:
        while (found := self.next()) is not None:
            yield found


def read_setup(path: str | Path, *, checked: bool = True) -> WorkCell:
    """Read a setup file into a WorkCell of world millimetres (FileFormatError if malformed)."""
    return read_setup_bytes(path, checked=checked)[0]


def read_setup_bytes(path: str | Path, *, checked: bool = True) -> tuple[WorkCell, bytes]:
    """``read_setup``'s cell and the bytes it was parsed from (a session's stamp of the file)."""
    path = Path(path)
    data = read_bytes(path, "setup")
    return parse_setup(decode_text(data, path, "setup"), path, checked=checked), data


def parse_setup(text: str, name: str | Path, *, checked: bool = True) -> WorkCell:
    """Parse setup-file text; ``name`` (the file name) locates errors and warnings.
    ``checked=False`` skips the geometry warnings (``_check_geometry``): for the bundled
    robot model, of which only the vertices are used (issue 25: half a session's start)."""
    lines = _Lines(text)
    where = Path(name)
    if not text.strip():
        raise FileFormatError(where, 0, "the setup file is empty (line 1 should be the number of objects)")

    def need(what: str) -> tuple[int, list[str]]:
        found = lines.next()
        if found is None:
            raise FileFormatError(where, lines.last_line + 1 if lines.last_line else 0,
                                  f"the file ends where {what} should be")
        number, line = found
        return number, split_fields(line)

    check_line_lengths(text, where, "setup")
    number, fields = need("the number of objects (line 1)")
    if len(fields) != 1:
        raise FileFormatError(where, number, f"line 1 must be the number of objects, not {_shown(fields)!r}")
    count = parse_count(fields[0], where, number, "the number of objects", MAX_PARTS)

    number, fields = need("the units (MM or IN)")
    units = fields[0].upper() if len(fields) == 1 else ""
    if units not in UNITS:
        raise FileFormatError(where, number, f"units must be MM or IN, not {_shown(fields)!r}")

    number, fields = need("the frame (W or S)")
    system = fields[0].upper() if len(fields) == 1 else ""
    if system not in SYSTEMS:
        raise FileFormatError(where, number, f"the frame must be W (world) or S (screen), not {_shown(fields)!r}")

    cell = WorkCell(units=units, system=system, name=where.name)
    header_lines: list[int] = []
    for part in range(1, count + 1):
        header_line, fields = need(f"object {part} of {count} ('1,N')")
        vertex_count = _object_size(fields, where, header_line, part)
        ref_line, fields = need(f"the reference point of object {part}")
        reference = _point(fields, where, ref_line, f"object {part} reference point")
        relative = []
        for index in range(1, vertex_count + 1):
            line_number, fields = need(f"vertex {index} of {vertex_count} of object {part}")
            relative.append(_point(fields, where, line_number, f"object {part} vertex {index}"))
        try:
            with numpy_errors():
                vertices = file_to_world(np.asarray(relative) + np.asarray(reference), units, system)
                polyhedron = Polyhedron(vertices, name=lines.names.get(header_line, f"PART {part}"))
        except (FloatingPointError, ValueError) as error:
            raise FileFormatError(where, header_line, f"object {part}: unusable vertices ({error})") from None
        cell.objects.append(polyhedron)
        header_lines.append(header_line)

    extra = lines.next()
    if extra is not None:
        raise FileFormatError(
            where, extra[0], f"more data after the last object (line 1 says {count} object{'s' if count != 1 else ''})"
        )
    for part, (header_line, warnings) in enumerate(zip(header_lines, _all_warnings(cell.objects) if checked else (),
                                                       strict=False), 1):
        cell.warnings.extend(f"{where.name}:{header_line}: object {part}: {warning}" for warning in warnings)
    return cell


def _object_size(fields: list[str], where: Path, line: int, part: int) -> int:
    """N of the object's ``1,N`` line, checked."""
    shown = _shown(fields, ",")
    if len(fields) != 2 or not all(f.isascii() and f.isdigit() for f in fields):
        if len(fields) == 3:
            reason = (f"object {part}: expected '1,N' (first and last vertex), found a point {shown!r}; "
                      "is the vertex count wrong?")
        else:
            reason = f"object {part}: expected '1,N' (first and last vertex), not {shown!r}"
        raise FileFormatError(where, line, reason)
    first = parse_count(fields[0], where, line, f"object {part}: the first vertex", MAX_VERTICES)
    last = parse_count(fields[1], where, line, f"object {part}: N", MAX_VERTICES)
    if first != 1:
        raise FileFormatError(where, line, f"object {part}: the first vertex must be 1, not {first}")
    if last % 2:
        raise FileFormatError(where, line,
                              f"object {part}: N = {last} is odd; the two polygons need the same number of vertices")
    if last < 8:
        raise FileFormatError(where, line,
                              f"object {part}: N = {last} is too few; each polygon needs at least 4 vertices (N >= 8)")
    return last


def _shown(fields: list[str], separator: str = " ") -> str:
    """Fields as a message quotes them: at most 40 characters."""
    text = separator.join(fields)
    return text if len(text) <= 40 else text[:40] + "..."


def _point(fields: list[str], where: Path, line: int, what: str) -> list[float]:
    """X, Y, Z of a point's line, as floats: the object's points become one array together
    (an array a point was a few hundred numpy calls a session's start, issue 25)."""
    if len(fields) != 3:
        raise FileFormatError(where, line,
                              f"{what}: expected 3 numbers (X, Y, Z), found {len(fields)}: {_shown(fields)!r}")
    return [parse_number(f, where, line, what) for f in fields]


def _check_geometry(polyhedron: Polyhedron, part: int) -> list[str]:
    """Cheap sanity checks; problems are warnings (the object is still drawn), never errors."""
    warnings: list[str] = []
    try:
        with numpy_errors():
            _geometry_warnings(polyhedron, warnings)
    except (FloatingPointError, ValueError, np.linalg.LinAlgError):
        pass  # numbers too odd to check: a check must never stop a file from loading
    return warnings


def _all_warnings(polyhedra: list[Polyhedron]) -> list[list[str]]:
    """``_check_geometry``'s warnings of each polyhedron, the polyhedra of one size checked
    at once: a few numpy calls a file instead of a few a part (most of the app's session at
    its start, issue 25). Numbers too odd for the batch are checked one by one."""
    found: list[list[str]] = [[] for _ in polyhedra]
    sizes: dict[int, list[int]] = {}
    for index, polyhedron in enumerate(polyhedra):
        sizes.setdefault(polyhedron.k, []).append(index)
    for members in sizes.values():
        group = [polyhedra[i] for i in members]
        try:
            with numpy_errors():
                warnings, flipped = _group_warnings(group)
        except (FloatingPointError, ValueError, np.linalg.LinAlgError):
            warnings = [_check_geometry(polyhedron, 0) for polyhedron in group]
        else:
            for polyhedron, turned in zip(group, flipped, strict=True):
                if turned:
                    polyhedron.winding_flipped = True
        for index, said in zip(members, warnings, strict=True):
            found[index] = said
    return found


def _group_warnings(group: list[Polyhedron]) -> tuple[list[list[str]], list[bool]]:
    """``_geometry_warnings`` of polyhedra of one size k at once: their warnings and which
    wind inward (the same numbers, face by face, as one at a time)."""
    k = group[0].k
    v = np.stack([polyhedron.vertices for polyhedron in group])  # (n, 2k, 3)
    front = v[:, :k]
    normal = np.cross(front, np.roll(front, -1, axis=1)).sum(axis=1)
    outward = ((normal * (front.mean(axis=1) - v.mean(axis=1))).sum(axis=1) >= 0).tolist()
    size = np.ptp(v, axis=1).max(axis=1)
    smallest = np.linalg.svd(v - v.mean(axis=1, keepdims=True), compute_uv=False)[:, -1]
    faces = group[0].topology.faces
    ends = v[:, np.stack(faces[:2])].reshape(-1, k, 3)
    sides = v[:, np.stack(faces[2:])].reshape(-1, 4, 3)
    worst = np.maximum(_off_planes(ends).reshape(len(group), 2).max(axis=1),
                       _off_planes(sides).reshape(len(group), k).max(axis=1))
    convex = _convex(np.concatenate([front, v[:, k:]])).reshape(2, len(group))
    warnings: list[list[str]] = []
    for i, out in enumerate(outward):
        said = [] if out else ["vertices wind inward; drawn with outward normals"]
        warnings.append(said)
        if size[i] <= 1e-9:
            said.append("all vertices coincide")
            continue
        if smallest[i] <= 1e-6 * size[i]:
            said.append("flat: the vertices enclose no volume")
            continue
        if worst[i] > 1e-3 * size[i] + 0.01:
            said.append(f"a face is not planar (off by {worst[i]:.2f} mm)")
        said.extend(f"the {label} polygon is not convex"
                    for label, ok in zip(("front", "back"), convex[:, i], strict=True) if not ok)
    return warnings, [not out for out in outward]


def _geometry_warnings(polyhedron: Polyhedron, warnings: list[str]) -> None:
    if not polyhedron.file_winding_outward():
        polyhedron.winding_flipped = True
        warnings.append("vertices wind inward; drawn with outward normals")
    v = polyhedron.vertices
    size = float(np.ptp(v, axis=0).max())
    if size <= 1e-9:
        warnings.append("all vertices coincide")
        return
    tolerance = 1e-3 * size + 0.01
    centred = v - v.mean(axis=0)
    if np.linalg.svd(centred, compute_uv=False)[-1] <= 1e-6 * size:
        warnings.append("flat: the vertices enclose no volume")
        return
    # the faces in two stacks, the end polygons (k corners) and the sides (4): a few numpy
    # calls a polyhedron instead of a few a face (this was most of a session's start, issue 25)
    faces = polyhedron.topology.faces
    worst = float(max(_off_planes(v[np.stack(faces[:2])]).max(), _off_planes(v[np.stack(faces[2:])]).max()))
    if worst > tolerance:
        warnings.append(f"a face is not planar (off by {worst:.2f} mm)")
    convex = _convex(np.stack([v[: polyhedron.k], v[polyhedron.k :]]))
    for label, ok in zip(("front", "back"), convex, strict=True):
        if not ok:
            warnings.append(f"the {label} polygon is not convex")


def _newell(pts: np.ndarray) -> np.ndarray:
    """The Newell normals of polygons (..., corners, 3)."""
    nxt = np.roll(pts, -1, axis=-2)
    return np.asarray(np.cross(pts, nxt).sum(axis=-2))


def _off_planes(faces: np.ndarray) -> np.ndarray:
    """The farthest each of ``faces`` (n, corners, 3) has a corner from its plane (through the
    face's mean, along its Newell normal; 0 for a face without a normal)."""
    normals = _newell(faces)
    lengths = np.sqrt((normals * normals).sum(axis=-1))
    kept = lengths != 0.0
    worst = np.zeros(len(faces))
    if kept.any():
        faces, units = faces[kept], normals[kept] / lengths[kept, None]
        off = np.einsum("fcx,fx->fc", faces - faces.mean(axis=1, keepdims=True), units)
        worst[kept] = np.abs(off).max(axis=1)
    return worst


def _convex(polygons: np.ndarray) -> np.ndarray:
    """Whether each of ``polygons`` (n, corners, 3) turns one way only (a polygon without a
    normal counts as convex)."""
    normals = _newell(polygons)
    edges = np.roll(polygons, -1, axis=1) - polygons
    turns = np.einsum("pcx,px->pc", np.cross(edges, np.roll(edges, -1, axis=1)), normals)
    scale = np.abs(turns).max(axis=1)
    scale[scale == 0.0] = 1.0
    flat = (normals * normals).sum(axis=-1) == 0.0  # no normal: as the face-at-a-time norm test
    return np.asarray(flat | (turns >= -1e-9 * scale[:, None]).all(axis=1))


# ---------------------------------------------------------------------------
# Writing
# ---------------------------------------------------------------------------

def format_setup(cell: WorkCell) -> str:
    """The setup-file text of ``cell`` in its own units and frame (reference = first vertex).

    Absolute points are rounded first, so reference + relative reads back exactly the
    rounded point (no error piles up between the two lines)."""
    units = cell.units.upper() if cell.units.upper() in UNITS else "MM"
    system = cell.system.upper() if cell.system.upper() in SYSTEMS else "W"
    decimals = DECIMALS[units]
    lines = [str(len(cell.objects)), units, system]
    for number, polyhedron in enumerate(cell.objects, 1):
        points = np.round(world_to_file(polyhedron.vertices, units, system), decimals)
        reference = points[0]
        name = " ".join(polyhedron.name.split())
        if name and name.upper() != f"PART {number}":
            lines.append(f"{COMMENT} {NAME_TAG} {name}")
        lines.append(f"1,{len(points)}")
        lines.append(_format_point(reference, decimals))
        lines.extend(_format_point(p - reference, decimals) for p in points)
    return "\n".join(lines) + "\n"


def _format_point(point: np.ndarray, decimals: int) -> str:
    # round again: the difference of two rounded numbers carries float noise (0.1 + 0.2)
    return " ".join(f"{round(float(value), decimals) + 0.0:>10.{decimals}f}" for value in point)


def write_setup(path: str | Path, cell: WorkCell, expected: str | None = None) -> None:
    """Write ``cell`` atomically (FileWriteError for a cell no setup file can hold; FileChanged
    when ``expected``, the stamp it was read with, no longer matches the file)."""
    if len(cell.objects) > MAX_PARTS:
        raise FileWriteError(path, f"{len(cell.objects)} objects are too many for a setup file (at most {MAX_PARTS})")
    largest = max((len(p.vertices) for p in cell.objects), default=0)
    if largest > MAX_VERTICES:
        raise FileWriteError(path,
                             f"an object of {largest} vertices is too large for a setup file (at most {MAX_VERTICES})")
    write_text_atomic(path, format_setup(cell), expected=expected)
