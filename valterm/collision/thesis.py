"""The 1985 collision check of §2.7, vectorised: a coarse box test, then the fine edge-face test.

Coarse (Figs. 2-12, 2-13): the extreme box of each *stationary* polyhedron is grown by the
circumscribed-sphere radius of the *moving* one (the yellow box) plus a speed-dependent error
margin (the lavender box); if the moving polyhedron's centre is inside, the pair is "near"
(the yellow message) and the fine check runs.

Fine (Figs. 2-14 A, B): every edge segment of one polyhedron against the plane of every face
polygon of the other, and vice versa. A segment that properly crosses a plane gives one
intersection point; lines from that point to the polygon's vertices make triangles, and if
the sum of their areas is no larger than the polygon's area the point is inside: collision.

Conventions chosen here (documented because the thesis leaves them open):

* ``margin(speed)`` is the straight-line step length at that speed, 25.4 mm * speed / 100
  (SPEED clamped to 10..100, as §6.6.1 does): the faster the robot, the farther apart the
  steps, the larger the lavender box, so a collision is announced at least a step ahead.
* Touching is not colliding: a segment must cross a plane by more than ``EPS`` mm on both
  sides. A part resting on a table, or an edge lying in a face's plane (the "parallel"
  possibility of Fig. 2-14), is clear; a real crossing always has other, non-parallel edges.
* The area test accepts a point on the polygon's boundary (relative tolerance ``AREA_TOL``).
* Blind spot of the 1985 method: a polyhedron wholly inside another has no edge crossing any
  face, so the fine check says "clear" (the pair is still "near"). The exact checker
  (``valterm.collision.exact``) reports that case; the agreement tests detect it explicitly.

Every step works on whole arrays: the coarse test of all pairs is one numpy expression and the
fine test of all near pairs (both directions) is one batch; only the loop over the (few)
polyhedron sizes that build the index layout is Python, and it is cached.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Literal, Sequence

import numpy as np

from valterm.cell.polyhedron import Polyhedron, topology

Kind = Literal["clear", "near", "collides"]
CLEAR, NEAR, COLLIDES = 0, 1, 2
KINDS: tuple[Kind, Kind, Kind] = ("clear", "near", "collides")

EPS = 1e-6        # mm: how far past a plane a segment end must be to count as crossing it
AREA_TOL = 1e-7   # relative: triangle-area sum may exceed the polygon area by this much
STEP_MM = 25.4    # straight-line increment at SPEED 100 (SPEC §3)


def margin(speed: float) -> float:
    """The speed-dependent error margin (mm) of §2.7 / §6.6.1: one straight-line step."""
    return STEP_MM * min(max(float(speed), 10.0), 100.0) / 100.0


# -- layout: index arrays into the concatenated vertices of a list of polyhedra ---------------

@dataclass(frozen=True)
class Layout:
    """Padded edge and face index arrays for polyhedra of the given k's, vertices concatenated.

    Padding is degenerate on purpose so no masks are needed: a padded edge is one vertex
    twice (it crosses nothing), a padded face vertex repeats the face's last vertex (a
    zero-area triangle), a padded face is one vertex repeated (zero normal, crosses nothing).
    """

    ks: tuple[int, ...]
    starts: np.ndarray     # (N,) first vertex of each polyhedron in the concatenation
    counts: np.ndarray     # (N,) 2k
    edge_idx: np.ndarray   # (N, Emax, 2)
    face_idx: np.ndarray   # (N, Fmax, M)


@lru_cache(maxsize=64)
def layout(ks: tuple[int, ...]) -> Layout:
    counts = np.array([2 * k for k in ks], dtype=np.intp)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.intp)
    kmax = max(ks) if ks else 4
    e_max, f_max, m = 3 * kmax, kmax + 2, max(kmax, 4)
    edge_idx = np.zeros((len(ks), e_max, 2), dtype=np.intp)
    face_idx = np.zeros((len(ks), f_max, m), dtype=np.intp)
    for i, (k, s) in enumerate(zip(ks, starts)):
        top = topology(k)
        edge_idx[i] = s
        edge_idx[i, : len(top.edges)] = top.edges + s
        face_idx[i] = s
        for j, face in enumerate(top.faces):
            face_idx[i, j] = face[-1] + s
            face_idx[i, j, : len(face)] = face + s
    return Layout(tuple(ks), starts, counts, edge_idx, face_idx)


@dataclass
class Scene:
    """Per-step geometry of a list of polyhedra: concatenated vertices, centres, radii, boxes."""

    layout: Layout
    vertices: np.ndarray   # (V, 3)
    centres: np.ndarray    # (N, 3)
    radii: np.ndarray      # (N,)
    lo: np.ndarray         # (N, 3) extreme box
    hi: np.ndarray         # (N, 3)

    @classmethod
    def of(cls, polys: Sequence[Polyhedron]) -> "Scene":
        lay = layout(tuple(len(p.vertices) // 2 for p in polys))
        v = np.concatenate([p.vertices for p in polys]) if polys else np.zeros((0, 3))
        if not polys:
            z = np.zeros((0, 3))
            return cls(lay, v, z, np.zeros(0), z, z)
        centres = np.add.reduceat(v, lay.starts, axis=0) / lay.counts[:, None]
        d = v - np.repeat(centres, lay.counts, axis=0)
        radii = np.sqrt(np.maximum.reduceat(np.einsum("ij,ij->i", d, d), lay.starts))
        lo = np.minimum.reduceat(v, lay.starts, axis=0)
        hi = np.maximum.reduceat(v, lay.starts, axis=0)
        return cls(lay, v, centres, radii, lo, hi)


# -- the two checks ----------------------------------------------------------------------------

def coarse(scene: Scene, moving: np.ndarray, stationary: np.ndarray, grow: float | np.ndarray) -> np.ndarray:
    """Boolean per pair: is the moving centre inside the stationary box grown by radius + margin?"""
    g = (scene.radii[moving] + grow)[:, None]
    c = scene.centres[moving]
    return np.all((c >= scene.lo[stationary] - g) & (c <= scene.hi[stationary] + g), axis=1)


def fine(scene: Scene, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Boolean per pair (a[i], b[i]): does an edge of one cross a face polygon of the other?"""
    n = len(a)
    if n == 0:
        return np.zeros(0, dtype=bool)
    lay, v = scene.layout, scene.vertices
    src = np.concatenate([a, b])    # whose edges
    dst = np.concatenate([b, a])    # whose faces
    seg = v[lay.edge_idx[src]]                       # (2n, E, 2, 3)
    poly = v[lay.face_idx[dst]]                      # (2n, F, M, 3)
    # Newell-style vector area about the first vertex: twice the area times the unit normal
    rel = poly - poly[:, :, :1]
    area2 = np.cross(rel, np.roll(rel, -1, axis=2)).sum(axis=2)     # (2n, F, 3)
    size = np.linalg.norm(area2, axis=-1)                           # (2n, F) = 2 * area
    unit = area2 / np.where(size > 0, size, 1.0)[..., None]
    off = np.einsum("nfk,nfk->nf", poly[:, :, 0], unit)
    s0 = np.einsum("nek,nfk->nef", seg[:, :, 0], unit) - off[:, None, :]
    s1 = np.einsum("nek,nfk->nef", seg[:, :, 1], unit) - off[:, None, :]
    crossing = ((s0 > EPS) & (s1 < -EPS)) | ((s0 < -EPS) & (s1 > EPS))
    hit = np.zeros(n, dtype=bool)
    ni, ei, fi = np.nonzero(crossing)
    if len(ni) == 0:
        return hit
    # where on the segment the plane is met, then the triangle-area sum of Fig. 2-14 B
    t = s0[ni, ei, fi] / (s0[ni, ei, fi] - s1[ni, ei, fi])
    p0 = seg[ni, ei, 0]
    x = p0 + t[:, None] * (seg[ni, ei, 1] - p0)
    r = poly[ni, fi] - x[:, None, :]                                 # (c, M, 3)
    tri = np.linalg.norm(np.cross(r, np.roll(r, -1, axis=1)), axis=-1).sum(axis=1)
    inside = tri <= size[ni, fi] * (1.0 + AREA_TOL)
    hit[ni[inside] % n] = True
    return hit


def check_pairs(scene: Scene, moving: np.ndarray, stationary: np.ndarray, grow: float,
                fine_only: np.ndarray | None = None) -> np.ndarray:
    """Kind codes (CLEAR/NEAR/COLLIDES) per pair, the coarse test gating the fine one.

    ``fine_only`` marks pairs where only the coarse test is run (never COLLIDES).
    """
    moving = np.asarray(moving, dtype=np.intp)
    stationary = np.asarray(stationary, dtype=np.intp)
    codes = coarse(scene, moving, stationary, grow).astype(np.int8)
    check = codes == NEAR
    if fine_only is not None:
        check &= ~fine_only
    idx = np.nonzero(check)[0]
    if len(idx):
        codes[idx[fine(scene, moving[idx], stationary[idx])]] = COLLIDES
    return codes


def check_pair(moving: Polyhedron, stationary: Polyhedron, margin: float) -> Kind:
    """The 1985 check of one pair: "clear", "near" (coarse only) or "collides"."""
    scene = Scene.of([moving, stationary])
    return KINDS[int(check_pairs(scene, np.array([0]), np.array([1]), margin)[0])]


def segment_hits_polyhedron(p0: np.ndarray, p1: np.ndarray, poly: Polyhedron, *,
                            solid: bool = False) -> bool:
    """Whether the segment p0-p1 crosses a face polygon of ``poly`` (the fine check's test).

    With ``solid`` an endpoint strictly inside the convex polyhedron also counts (a short
    segment wholly inside crosses no face; the LED sensor between the fingers needs this).
    """
    p0 = np.asarray(p0, dtype=float)
    p1 = np.asarray(p1, dtype=float)
    scene = Scene.of([poly])
    lay = scene.layout
    poly_pts = scene.vertices[lay.face_idx[0]][None]          # (1, F, M, 3)
    rel = poly_pts - poly_pts[:, :, :1]
    area2 = np.cross(rel, np.roll(rel, -1, axis=2)).sum(axis=2)[0]
    size = np.linalg.norm(area2, axis=-1)
    unit = area2 / np.where(size > 0, size, 1.0)[:, None]
    first = poly_pts[0, :, 0]
    off = np.einsum("fk,fk->f", first, unit)
    s0 = unit @ p0 - off
    s1 = unit @ p1 - off
    if solid:
        outward = np.einsum("fk,fk->f", unit, first - scene.centres[0])
        sign = np.where(outward >= 0, 1.0, -1.0)[size > 0]
        for s in (s0, s1):
            if np.all(s[size > 0] * sign < -EPS):
                return True
    crossing = ((s0 > EPS) & (s1 < -EPS)) | ((s0 < -EPS) & (s1 > EPS))
    fi = np.nonzero(crossing)[0]
    if len(fi) == 0:
        return False
    t = s0[fi] / (s0[fi] - s1[fi])
    x = p0 + t[:, None] * (p1 - p0)
    r = poly_pts[0, fi] - x[:, None, :]
    tri = np.linalg.norm(np.cross(r, np.roll(r, -1, axis=1)), axis=-1).sum(axis=1)
    return bool(np.any(tri <= size[fi] * (1.0 + AREA_TOL)))
