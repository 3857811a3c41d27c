"""Generate (main menu G): the robot and the cell written as OBJ or GLB for other programs.

Each polyhedron becomes a closed triangle mesh named ``robot/<name>`` or ``cell/PART<n>``;
in a GLB the robot's links hang under a ``robot`` node and the parts under a ``cell`` node.
OBJ has no hierarchy, so the names carry it (one ``o`` object each); read it back with
``trimesh.load(path, split_objects=True)``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.cell.workcell import WorkCell
from valterm.core.files.atomic import write_bytes_atomic

EXPORT_EXTENSIONS = (".obj", ".glb")


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


def polyhedron_mesh(poly: Polyhedron):  # -> trimesh.Trimesh (import kept lazy)
    import trimesh

    return trimesh.Trimesh(vertices=poly.vertices.copy(), faces=polyhedron_triangles(poly), process=False)


def export_scene(cell: WorkCell, robot_polyhedra: list[Polyhedron], path: str | Path) -> Path:
    """Write the robot and the cell to ``path`` (.obj or .glb); returns the path written."""
    import trimesh

    path = Path(path)
    ext = path.suffix.lower()
    if ext not in EXPORT_EXTENSIONS:
        raise ValueError(f"cannot export {ext or 'a file without extension'}: use .obj or .glb")
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
            label = (poly.name or f"{default}{i}").replace("/", "-").replace(" ", "_")
            name = unique(f"{group}/{label}")
            scene.add_geometry(polyhedron_mesh(poly), node_name=name, geom_name=name, parent_node_name=group)
    if not scene.geometry:
        raise ValueError("nothing to export: no robot and no parts")
    path.parent.mkdir(parents=True, exist_ok=True)
    data = scene.export(file_type=ext[1:])
    # the one safe write path: a random exclusive temporary, never through a link
    write_bytes_atomic(path, data if isinstance(data, bytes) else data.encode())
    return path
