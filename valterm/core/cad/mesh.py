"""Polygon-mesh import (start-up choice U, the modern stand-in for UGII part files).

Any file trimesh reads (STL, OBJ, PLY, OFF, GLB/GLTF) becomes one part per mesh instance
in its scene (per ``o`` object in an OBJ), each with its scene-graph transform applied.
STL, OBJ, PLY and OFF carry no units: their numbers are taken as millimetres unless told
otherwise. A glTF/GLB is in metres by its specification (``METRE_EXTENSIONS``); the numbers
returned here are the file's own, the caller scales them.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from valterm.core.cad.errors import CadImportError

if TYPE_CHECKING:        # the IGES reader loads when a file is read (issue 25: start time)
    from valterm.core.cad.iges import Part

MESH_EXTENSIONS = (".stl", ".obj", ".ply", ".off", ".glb", ".gltf")
METRE_EXTENSIONS = (".glb", ".gltf")


def read_mesh_parts(path: str | Path) -> list[Part]:
    """The parts of a mesh file; raises ``CadImportError`` with the reason on bad input."""
    import trimesh

    from valterm.core.cad.iges import Part

    path = Path(path)
    ext = path.suffix.lower()
    if ext not in MESH_EXTENSIONS:
        raise CadImportError(path, None,
                             f"unknown mesh file type {ext or '(none)'}; use one of {', '.join(MESH_EXTENSIONS)}")
    if not path.is_file():
        raise CadImportError(path, None, "no such file")
    if path.stat().st_size == 0:
        raise CadImportError(path, None, "the file is empty")
    try:
        # an OBJ's `o` objects are its parts
        scene = (trimesh.load_scene(str(path), split_objects=True) if ext == ".obj"
                 else trimesh.load_scene(str(path)))
    except Exception as exc:  # trimesh raises many kinds on junk input; all mean "unreadable"
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise CadImportError(path, None, f"not a readable {ext[1:].upper()} mesh ({reason})") from None
    parts: list[Part] = []
    for node in scene.graph.nodes_geometry:
        transform, geom_name = scene.graph[node]
        geom = scene.geometry.get(geom_name)
        vertices = getattr(geom, "vertices", None)
        if vertices is None or len(vertices) == 0:
            continue
        v = np.asarray(vertices, dtype=float)
        v = v @ np.asarray(transform)[:3, :3].T + np.asarray(transform)[:3, 3]
        if not np.all(np.isfinite(v)):
            raise CadImportError(path, None, f"mesh {node!r} has non-finite vertex coordinates")
        # a single-mesh file (STL, PLY, OFF) is named after the file by trimesh: keep its stem
        parts.append(Part(path.stem if str(node) == path.name else str(node), v, []))
    if not parts:
        raise CadImportError(path, None, f"no mesh geometry in the file (is it a {ext[1:].upper()} mesh?)")
    return parts
