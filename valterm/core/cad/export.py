"""Generate (main menu G, ``valterm export``): the robot and the cell as GLB, OBJ or STL.

Each polyhedron becomes a closed triangle mesh named by its own name (an imported part's
IGES label or mesh name, ``PART n`` otherwise; robot links by the model's link names), made
unique within the file with ``-2``, ``-3``...

* GLB follows glTF: metres, Y up (world X, Y, Z -> glTF X, Z, -Y, ``valterm.core.cad.axes``;
  import turns it back), the names on both node
  and mesh; the robot's links hang under a ``robot`` node and the parts under a ``cell`` node.
* OBJ keeps world millimetres, Z up, and says so in its first comment line; it has no
  hierarchy, so the names carry it (``o robot/BASE``, ``o cell/CHASSIS``); read it back with
  ``trimesh.load(path, split_objects=True)``.
* STL keeps world millimetres, Z up: one mesh of every body, no names (the format has none).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from valterm.core.cad.axes import Z_UP_TO_Y_UP  # the one convention, import's too
from valterm.core.cad.errors import CadExportError
from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.cell.workcell import WorkCell
from valterm.core.files.atomic import write_bytes_atomic

if TYPE_CHECKING:  # trimesh is imported where it is used: it is slow to import
    import trimesh

EXPORT_EXTENSIONS = (".glb", ".obj", ".stl")
# what each format's numbers are, for the user (the CLI prints it)
EXPORT_UNITS = {".glb": "metres, Y up (glTF)", ".obj": "millimetres, Z up", ".stl": "millimetres, Z up"}
OBJ_HEADER = "# valterm export: world millimetres, Z up (the VAL-II SIMULATOR's world frame)\n"


def polyhedron_triangles(poly: Polyhedron) -> np.ndarray:
    """(T, 3) vertex indices: every face fanned into triangles, wound outward."""
    normals = poly.face_normals()
    tris: list[np.ndarray] = []
    for face, normal in zip(poly.topology.faces, normals):
        fan = np.stack([np.full(len(face) - 2, face[0]), face[1:-1], face[2:]], 1)
        a, b, c = (poly.vertices[fan[:, i]] for i in range(3))
        wrong = np.einsum("ij,j->i", np.cross(b - a, c - a), normal) < 0
        fan[wrong] = fan[wrong][:, [0, 2, 1]]
        tris.append(fan)
    return np.concatenate(tris)


def polyhedron_mesh(poly: Polyhedron, matrix: np.ndarray | None = None) -> trimesh.Trimesh:
    """A trimesh.Trimesh of ``poly`` (vertices times ``matrix`` if given; import kept lazy)."""
    import trimesh

    vertices = poly.vertices.copy() if matrix is None else poly.vertices @ np.asarray(matrix).T
    return trimesh.Trimesh(vertices=vertices, faces=polyhedron_triangles(poly), process=False)


def export_scene(cell: WorkCell, robot_polyhedra: list[Polyhedron], path: str | Path) -> Path:
    """Write the robot and the cell to ``path`` (.glb, .obj or .stl) atomically; returns the path."""
    import trimesh

    path = Path(path)
    ext = path.suffix.lower()
    if ext not in EXPORT_EXTENSIONS:
        raise CadExportError(f"cannot export {ext or 'a file without extension'}: use .glb, .obj or .stl")
    matrix = Z_UP_TO_Y_UP / 1000.0 if ext == ".glb" else None
    scene = trimesh.Scene()
    used: set[str] = set()

    def unique(name: str) -> str:
        out, i = name, 2
        while out in used:
            out, i = f"{name}-{i}", i + 1
        used.add(out)
        return out

    for group, polys, default in (("robot", robot_polyhedra, "LINK"), ("cell", cell.objects, "PART")):
        if not polys:
            continue
        scene.graph.update(frame_to=group, frame_from=scene.graph.base_frame)
        for i, poly in enumerate(polys, 1):
            label = " ".join((poly.name or f"{default} {i}").split()).replace("/", "-")
            name = unique(label if ext == ".glb" else f"{group}/{label}")
            scene.add_geometry(polyhedron_mesh(poly, matrix), node_name=name, geom_name=name, parent_node_name=group)
    if not scene.geometry:
        raise CadExportError("nothing to export: no robot and no parts")
    data = scene.export(file_type=ext[1:])
    if ext == ".obj":
        data = OBJ_HEADER + (data.decode() if isinstance(data, bytes) else data)
    path.parent.mkdir(parents=True, exist_ok=True)
    write_bytes_atomic(path, data if isinstance(data, bytes) else data.encode())
    return path

