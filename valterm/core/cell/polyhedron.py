"""The extruded convex polyhedron of §2.1 / §7.1: the one solid of the simulator.

A polyhedron is a front polygon of k vertices and a back polygon of k vertices joined
vertex to vertex (N = 2k vertices, k >= 4 in a setup file). Faces: the front polygon,
the back polygon and k side quads. Everything is stored as numpy arrays so placing,
culling and collision work on whole arrays at once.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np


@dataclass(frozen=True)
class Topology:
    """Faces and edges of an extruded polyhedron with k vertices per polygon (shared by size)."""

    k: int
    faces: tuple[np.ndarray, ...]       # vertex indices per face: front, back, k side quads
    edges: np.ndarray                   # (3k, 2) vertex index pairs, each edge once
    face_edges: tuple[np.ndarray, ...]  # per face, its edges as (m, 2) pairs (polygon-by-polygon drawing)


_TOPOLOGIES: dict[int, Topology] = {}


def topology(k: int) -> Topology:
    """Faces and edges for k vertices per polygon, built once per k."""
    found = _TOPOLOGIES.get(k)
    if found is not None:
        return found
    front = np.arange(k)
    back = np.arange(k, 2 * k)
    nxt = (front + 1) % k
    sides = [np.array([i, nxt[i], k + nxt[i], k + i]) for i in range(k)]
    faces = (front, back[::-1].copy(), *sides)
    edges = np.concatenate(
        [np.stack([front, nxt], 1), np.stack([back, k + nxt], 1), np.stack([front, back], 1)]
    )
    face_edges = tuple(np.stack([f, np.roll(f, -1)], 1) for f in faces)
    found = Topology(k, faces, edges, face_edges)
    _TOPOLOGIES[k] = found
    return found


@dataclass
class Polyhedron:
    """An extruded convex polyhedron: ``vertices`` (2k, 3) in millimetres.

    ``reference`` is the reference point of the setup file (the first corner); vertices are
    absolute. ``winding_flipped`` records that the file's vertex order disagreed with the
    outward normals (accepted, reported as a warning, drawn right).
    """

    vertices: np.ndarray
    name: str = ""
    winding_flipped: bool = False
    # how many times a polyhedron's vertices have been replaced (moved): a cache of placed
    # polyhedra (the collision scene's) knows none has moved while this stays the same (a new
    # polyhedron is a new object, told by its identity)
    placements: ClassVar[int] = 0

    def __setattr__(self, name: str, value: object) -> None:
        if name == "vertices" and "vertices" in self.__dict__:
            Polyhedron.placements += 1
        object.__setattr__(self, name, value)

    def __post_init__(self) -> None:
        v = np.asarray(self.vertices, dtype=float)
        if v.ndim != 2 or v.shape[1] != 3 or len(v) < 6 or len(v) % 2:
            raise ValueError(f"a polyhedron needs an even number (>= 6) of 3-D vertices, got shape {v.shape}")
        object.__setattr__(self, "vertices", v)     # still being made: not a move

    # -- structure ---------------------------------------------------------
    @property
    def k(self) -> int:
        return len(self.vertices) // 2

    @property
    def topology(self) -> Topology:
        return topology(self.k)

    @property
    def reference(self) -> np.ndarray:
        first: np.ndarray = self.vertices[0]  # numpy types a row of an array as Any
        return first

    @property
    def edges(self) -> np.ndarray:
        """(3k, 2, 3) edge segments."""
        segments: np.ndarray = self.vertices[self.topology.edges]
        return segments

    # -- geometry ----------------------------------------------------------
    @property
    def centre(self) -> np.ndarray:
        mean: np.ndarray = self.vertices.mean(axis=0)  # numpy types a mean as Any
        return mean

    @property
    def radius(self) -> float:
        """Radius of the circumscribed sphere about the centre (coarse collision check)."""
        return float(np.linalg.norm(self.vertices - self.centre, axis=1).max())

    @property
    def extreme_box(self) -> tuple[np.ndarray, np.ndarray]:
        return self.vertices.min(axis=0), self.vertices.max(axis=0)

    def face_normals(self) -> np.ndarray:
        """Outward unit normals, one per face (front, back, sides), from Newell's method.

        Faces are oriented outward by comparing with the centre, so a file whose winding
        disagrees is still drawn right.
        """
        normals = []
        centre = self.centre
        for face in self.topology.faces:
            pts = self.vertices[face]
            nxt = np.roll(pts, -1, axis=0)
            n = np.array([
                np.sum((pts[:, 1] - nxt[:, 1]) * (pts[:, 2] + nxt[:, 2])),
                np.sum((pts[:, 2] - nxt[:, 2]) * (pts[:, 0] + nxt[:, 0])),
                np.sum((pts[:, 0] - nxt[:, 0]) * (pts[:, 1] + nxt[:, 1])),
            ])
            length = np.linalg.norm(n)
            n = n / length if length > 0 else n
            if np.dot(n, pts.mean(axis=0) - centre) < 0:
                n = -n
            normals.append(n)
        return np.array(normals)

    def file_winding_outward(self) -> bool:
        """Whether the front polygon as listed winds counter-clockwise seen from outside."""
        pts = self.vertices[: self.k]
        nxt = np.roll(pts, -1, axis=0)
        n = np.cross(pts, nxt).sum(axis=0)
        return bool(np.dot(n, pts.mean(axis=0) - self.centre) >= 0)

    # -- moving ------------------------------------------------------------
    def transformed(self, rotation: np.ndarray, translation: np.ndarray) -> Polyhedron:
        """A copy moved by ``v -> rotation @ v + translation``."""
        return Polyhedron(self.vertices @ np.asarray(rotation).T + translation, self.name, self.winding_flipped)

    def translated(self, offset: np.ndarray) -> Polyhedron:
        return Polyhedron(self.vertices + offset, self.name, self.winding_flipped)

    @classmethod
    def from_polygons(cls, front: np.ndarray, back: np.ndarray, name: str = "") -> Polyhedron:
        front = np.asarray(front, dtype=float)
        back = np.asarray(back, dtype=float)
        if front.shape != back.shape:
            raise ValueError("front and back polygons need the same number of vertices")
        return cls(np.concatenate([front, back]), name)

    @classmethod
    def box(cls, lo: np.ndarray, hi: np.ndarray, name: str = "") -> Polyhedron:
        """An axis-aligned box: front polygon at z = lo, back at z = hi."""
        (x0, y0, z0), (x1, y1, z1) = lo, hi
        front = [[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0]]
        back = [[x, y, z1] for x, y, _ in front]
        return cls.from_polygons(np.array(front), np.array(back), name)


def stack_edges(polyhedra: list[Polyhedron]) -> tuple[np.ndarray, np.ndarray]:
    """All edges of many polyhedra as one (E, 2, 3) array and the owner index of each edge."""
    if not polyhedra:
        return np.zeros((0, 2, 3)), np.zeros(0, dtype=int)
    edges = [p.edges for p in polyhedra]
    owners = np.concatenate([np.full(len(e), i) for i, e in enumerate(edges)])
    return np.concatenate(edges), owners
