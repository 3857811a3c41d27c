"""Polygon-mesh import (start-up choice U, the modern stand-in for UGII part files).

Any file trimesh reads (OBJ, PLY, OFF, GLB/GLTF) becomes one part per mesh instance in its
scene (per ``o`` object in an OBJ), each with its scene-graph transform applied. STL is read
here with numpy (binary or ASCII): a 2-million-triangle STL is a 100 MB array, not the
gigabytes a general mesh loader builds. STL, OBJ, PLY and OFF carry no units: their numbers
are taken as millimetres unless told otherwise. A glTF/GLB is in metres with Y up by its
specification: its points are turned to the world's Z up here (``valterm.core.cad.axes``,
the convention export uses) and the caller scales the metres.

A file of more than ``MAX_TRIANGLES`` triangles is refused with the limit named. No
decimation: each part becomes the convex envelope of all its vertices, so every vertex is
kept (a simplified mesh would let the envelope cut into the real part); the envelope is
computed from the vertices alone, so a large mesh costs only its reading. ``progress`` is
told what is being done on a large file (the CLI and the app show it).

Every malformed file is a ``CadImportError`` naming the file (and the line where there is
one); trimesh's own log output is silenced while it reads.
"""

from __future__ import annotations

import logging
import re
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from valterm.core.cad.axes import gltf_to_world
from valterm.core.cad.errors import CadImportError, read_cad_bytes

if TYPE_CHECKING:        # the IGES reader loads when a file is read (issue 25: start time)
    from valterm.core.cad.iges import Part

MESH_EXTENSIONS = (".stl", ".obj", ".ply", ".off", ".glb", ".gltf")
METRE_EXTENSIONS = (".glb", ".gltf")
Y_UP_EXTENSIONS = (".glb", ".gltf")

MAX_TRIANGLES = 5_000_000  # 250 MB of binary STL; the import stays under 1 GB of memory
LARGE_TRIANGLES = 200_000  # from here on the import says what it is doing
LARGE_BYTES = 10_000_000

Progress = Callable[[str], None]

_STL_RECORD = np.dtype([("normal", "<f4", (3,)), ("vertices", "<f4", (3, 3)), ("attribute", "<u2")])
_STL_HEADER = 84
_STL_VERTEX = re.compile(rb"^[ \t]*vertex\b([^\n]*)", re.MULTILINE)
# an OBJ vertex line with fewer than three numbers (trimesh would fail on it without saying where)
_OBJ_SHORT_VERTEX = re.compile(rb"^v[ \t]+[^ \t\r\n]+(?:[ \t]+[^ \t\r\n]+)?[ \t]*\r?$", re.MULTILINE)


def read_mesh_parts(path: str | Path, progress: Progress | None = None) -> list[Part]:
    """The parts of a mesh file; raises ``CadImportError`` with the reason on bad input."""
    from valterm.core.cad.iges import Part

    path = Path(path)
    ext = path.suffix.lower()
    if ext not in MESH_EXTENSIONS:
        raise CadImportError(path, None,
                             f"unknown mesh file type {ext or '(none)'}; use one of {', '.join(MESH_EXTENSIONS)}")
    data = read_cad_bytes(path)
    if not data:
        raise CadImportError(path, None, "the file is empty")
    if progress is not None and len(data) >= LARGE_BYTES:
        progress(f"{path.name}: reading {len(data) / 1e6:.0f} MB")
    if ext == ".stl":
        points = read_stl(path, data, progress)
        return [Part(path.stem, points, [])]
    if ext == ".obj":
        _check_obj(path, data)
    elif ext == ".gltf":
        _check_gltf(path, data)
    del data
    return _read_with_trimesh(path, ext, progress)


def _read_with_trimesh(path: Path, ext: str, progress: Progress | None) -> list[Part]:
    import trimesh

    from valterm.core.cad.iges import Part

    try:
        with _quiet_trimesh():
            # an OBJ's `o` objects are its parts
            scene = (trimesh.load_scene(str(path), split_objects=True) if ext == ".obj"
                     else trimesh.load_scene(str(path)))
    except Exception as exc:  # trimesh raises many kinds on junk input; all mean "unreadable"
        raise CadImportError(path, None, f"not a readable {ext[1:].upper()} mesh ({_reason(exc)})") from None
    triangles = sum(len(getattr(g, "faces", ())) for g in scene.geometry.values())
    _check_count(path, triangles, progress)
    parts: list[Part] = []
    for node in scene.graph.nodes_geometry:
        transform, geom_name = scene.graph[node]
        geom = scene.geometry.get(geom_name)
        vertices = getattr(geom, "vertices", None)
        if vertices is None or len(vertices) == 0:
            continue
        v = np.asarray(vertices, dtype=float)
        if v.ndim != 2 or v.shape[1] != 3:
            raise CadImportError(path, None, f"mesh {str(node)[:40]!r} has vertices of {v.shape[-1]} coordinates, "
                                             "not x y z")
        v = v @ np.asarray(transform)[:3, :3].T + np.asarray(transform)[:3, 3]
        if not np.all(np.isfinite(v)):
            raise CadImportError(path, None, f"mesh {str(node)[:40]!r} has non-finite vertex coordinates")
        if ext in Y_UP_EXTENSIONS:
            v = gltf_to_world(v)  # glTF is Y up; the world Z up (export turns it the other way)
        # a single-mesh file (PLY, OFF) is named after the file by trimesh: keep its stem
        parts.append(Part(path.stem if str(node) == path.name else str(node), v, []))
    if not parts:
        raise CadImportError(path, None, f"no mesh geometry in the file (is it a {ext[1:].upper()} mesh?)")
    return parts


def _check_count(path: Path, triangles: int, progress: Progress | None) -> None:
    if triangles > MAX_TRIANGLES:
        raise CadImportError(path, None, f"{triangles:,} triangles: more than the import limit of "
                                         f"{MAX_TRIANGLES:,}; simplify the mesh in the CAD program first")
    if progress is not None and triangles >= LARGE_TRIANGLES:
        progress(f"{path.name}: {triangles:,} triangles read; enveloping the parts")


# -- STL ---------------------------------------------------------------------------------
def read_stl(path: Path, data: bytes, progress: Progress | None = None) -> np.ndarray:
    """The (3T, 3) vertices of a binary or ASCII STL (CadImportError, located, if malformed)."""
    if len(data) >= _STL_HEADER:
        count = int(np.frombuffer(data, "<u4", 1, 80)[0])
        expected = _STL_HEADER + count * _STL_RECORD.itemsize
        if len(data) == expected or (len(data) > expected and not _looks_ascii(data)):
            _check_count(path, count, progress)
            if count == 0:
                raise CadImportError(path, None, "a binary STL of no triangles")
            records = np.frombuffer(data, _STL_RECORD, count, _STL_HEADER)
            return _finite(path, distinct(records["vertices"].reshape(-1, 3)))
    if _looks_ascii(data):
        return _read_ascii_stl(path, data, progress)
    if len(data) < _STL_HEADER:
        raise CadImportError(path, None, f"not a readable STL mesh: {len(data)} bytes, too short for a binary "
                                         "STL (84 bytes of header) and no ASCII STL (no 'solid')")
    count = int(np.frombuffer(data, "<u4", 1, 80)[0])
    held = (len(data) - _STL_HEADER) // _STL_RECORD.itemsize
    raise CadImportError(path, None, f"not a readable STL mesh: a binary STL cut short, its header says {count:,} "
                                     f"triangles, "
                                     f"the file holds {held:,} ({len(data):,} bytes)")


def distinct(points: np.ndarray) -> np.ndarray:
    """The distinct rows of (n, 3) float32 or float64 ``points``, as float64: an STL repeats each
    vertex for every triangle that has it (about six times). Rows are grouped by a hash of their
    bits (one numeric sort), and a row whose bits differ from its group's first is kept as well,
    so nothing is lost to a hash collision."""
    points = np.ascontiguousarray(points) + points.dtype.type(0)  # -0.0 is 0.0
    bits = points.view(np.uint32 if points.dtype.itemsize == 4 else np.uint64)  # a view: no copy
    key = np.zeros(len(bits), np.uint64)
    for column, odd in zip(bits.T, (0x9E3779B97F4A7C15, 0xC2B2AE3D27D4EB4F, 0x165667B19E3779F9)):
        key ^= column  # then a multiply-xorshift mix of each coordinate's bits
        key *= np.uint64(odd)
        key ^= key >> np.uint64(31)
    order = np.argsort(key)
    sorted_key = key[order]
    starts = np.ones(len(key), dtype=bool)
    starts[1:] = sorted_key[1:] != sorted_key[:-1]
    # each row's group representative: the first row of its run of equal keys
    first = order[np.maximum.accumulate(np.where(starts, np.arange(len(key)), 0))]
    differs = np.zeros(len(key), dtype=bool)
    for column in bits.T:  # one coordinate at a time: no (n, 3) copies of a large mesh
        differs |= column[order] != column[first]
    collided = order[differs]
    if len(collided):  # rare: sorted row by row, the few rows a collision grouped wrongly
        collided = collided[np.unique(bits[collided], axis=0, return_index=True)[1]]
    out: np.ndarray = points[np.concatenate([order[starts], collided])].astype(float)
    return out


def _looks_ascii(data: bytes) -> bool:
    return data.lstrip()[:5].lower() == b"solid" and b"\0" not in data[:1024]


def _read_ascii_stl(path: Path, data: bytes, progress: Progress | None) -> np.ndarray:
    _check_count(path, data.count(b"vertex") // 3, progress)  # before any list is made of them
    found = _STL_VERTEX.findall(data)
    if not found:
        raise CadImportError(path, None, "an ASCII STL with no 'vertex' lines: no mesh geometry")
    fields = b" ".join(found).split()
    if len(fields) != 3 * len(found):
        raise CadImportError(path, _bad_vertex_line(data), "a vertex needs three numbers: x y z")
    try:
        points = np.array(fields, dtype=float).reshape(-1, 3)
    except ValueError:
        raise CadImportError(path, _bad_vertex_line(data, numbers=True),
                             "a vertex coordinate is not a number") from None
    if len(points) % 3:
        raise CadImportError(path, None, f"{len(points)} vertices: not three a facet (the file is cut short?)")
    return _finite(path, distinct(points))


def _bad_vertex_line(data: bytes, numbers: bool = False) -> int | None:
    """The line of the first vertex without three numbers (an error path: a loop is fine)."""
    for match in _STL_VERTEX.finditer(data):
        values = match.group(1).split()
        bad = len(values) != 3
        if numbers and not bad:
            try:
                [float(v) for v in values]
            except ValueError:
                bad = True
        if bad:
            return data.count(b"\n", 0, match.start()) + 1
    return None


def _finite(path: Path, points: np.ndarray) -> np.ndarray:
    if not np.all(np.isfinite(points)):
        raise CadImportError(path, None, "the mesh has non-finite vertex coordinates (NaN or infinity)")
    return points


# -- OBJ and glTF checks trimesh does not locate ---------------------------------------------
def _check_obj(path: Path, data: bytes) -> None:
    short = _OBJ_SHORT_VERTEX.search(data)
    if short is not None:
        line = data.count(b"\n", 0, short.start()) + 1
        raise CadImportError(path, line, f"a vertex needs three numbers (x y z), not "
                                         f"{short.group(0).decode(errors='replace').strip()[:40]!r}")
    faces = data.count(b"\nf ") + data.count(b"\nf\t") + data.startswith((b"f ", b"f\t"))
    if faces > MAX_TRIANGLES:
        raise CadImportError(path, None, f"{faces:,} faces: more than the import limit of "
                                         f"{MAX_TRIANGLES:,} triangles; simplify the mesh in the CAD program first")


MAX_JSON_DEPTH = 64  # a glTF's JSON nests 5 or 6 deep; 2000 deep was Python's RecursionError
_JSON_STRING = re.compile(rb'"[^"\\]*(?:\\.[^"\\]*)*"')  # its brackets are no nesting
_JSON_BRACKET = re.compile(rb"[][{}]")


def json_too_deep(data: bytes, limit: int = MAX_JSON_DEPTH) -> bool:
    """Whether JSON text nests arrays and objects more than ``limit`` deep (looked at before a
    parser recurses into it)."""
    depth = 0
    for bracket in _JSON_BRACKET.findall(_JSON_STRING.sub(b'""', data)):
        depth += 1 if bracket in b"[{" else -1
        if depth > limit:
            return True
    return False


def _check_gltf(path: Path, data: bytes) -> None:
    """A .gltf names its buffers: say which one is missing or remote instead of a bare name."""
    import json

    if json_too_deep(data):
        raise CadImportError(path, None, f"not a glTF file (its JSON is nested more than {MAX_JSON_DEPTH} deep)")
    try:
        document = json.loads(data)
    except (ValueError, UnicodeDecodeError) as error:
        raise CadImportError(path, getattr(error, "lineno", None),
                             "not a glTF file (its JSON cannot be read)") from None
    if not isinstance(document, dict):
        raise CadImportError(path, None, "not a glTF file (no JSON object)")
    for key in ("buffers", "images"):
        for entry in document.get(key) or []:
            uri = entry.get("uri", "") if isinstance(entry, dict) else ""
            if not isinstance(uri, str) or not uri or uri.startswith("data:"):
                continue
            if re.match(r"[a-z][a-z0-9+.-]*://", uri, re.I):
                raise CadImportError(path, None, f"its data is on the web ({uri[:60]}); only local files are "
                                                 "read: save it as a .glb or put the file beside the .gltf")
            if key == "buffers" and not (path.parent / uri).is_file():
                raise CadImportError(path, None, f"its data file {uri[:60]} is not beside it "
                                                 "(copy it into the same folder, or use the .glb)")
    required = [e for e in document.get("extensionsRequired") or [] if isinstance(e, str)]
    if required:
        raise CadImportError(path, None, f"it needs the glTF extension {', '.join(required)[:80]}, which valterm "
                                         "cannot read: export it again without it (no compression)")


# -- trimesh's messages -------------------------------------------------------------------------
@contextmanager
def _quiet_trimesh() -> Iterator[None]:
    """trimesh logs its own tracebacks for broken files; valterm says the one line instead."""
    logger = logging.getLogger("trimesh")
    level, propagate = logger.level, logger.propagate
    logger.setLevel(logging.CRITICAL + 1)
    logger.propagate = False
    try:
        yield
    finally:
        logger.setLevel(level)
        logger.propagate = propagate


def _reason(exc: BaseException) -> str:
    """A library's reason as a user reads it: its first line, without the library's own advice
    to pass a Python argument (``force='mesh'``, ``allow_remote=True``)."""
    text = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
    if "`" in text or "=" in text or text.startswith("No module named"):
        return "the file is damaged or uses a feature valterm cannot read"
    return text[:120]
