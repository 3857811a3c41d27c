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
  face. Added here (issue 13): the fine check also asks whether either centre lies strictly
  inside the other polyhedron (``_contained``), so that case collides, as fcl says too.

Every step works on whole arrays: the coarse test of all pairs is one numpy expression and the
fine test of all near pairs (both directions) is one batch; only the loop over the (few)
polyhedron sizes that build the index layout is Python, and it is cached.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Callable, Literal, Sequence

import numpy as np

from valterm.core.cell.polyhedron import Polyhedron, topology

Kind = Literal["clear", "near", "collides"]
CLEAR, NEAR, COLLIDES = 0, 1, 2
KINDS: tuple[Kind, Kind, Kind] = ("clear", "near", "collides")

EPS = 1e-6        # mm: how far past a plane a segment end must be to count as crossing it
AREA_TOL = 1e-7   # relative: triangle-area sum may exceed the polygon area by this much
STEP_MM = 25.4    # straight-line increment at SPEED 100 (SPEC §3)
SEPARATED = 1.0   # mm: a face plane this far clear of every vertex of the other separates a pair


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
    face_next: np.ndarray  # (N, Fmax, M) the next vertex round each face


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
    return Layout(tuple(ks), starts, counts, edge_idx, face_idx, np.roll(face_idx, -1, axis=2))


@dataclass
class Scene:
    """Per-step geometry of a list of polyhedra: concatenated vertices, centres, radii, boxes."""

    layout: Layout
    vertices: np.ndarray   # (V, 3)
    centres: np.ndarray    # (N, 3)
    radii: np.ndarray      # (N,)
    mid: np.ndarray        # (N, 3) middle of the extreme box
    half: np.ndarray       # (N, 3) half its size
    # face planes (unit normal (N, F, 3), offset (N, F), twice the area (N, F)) when kept
    # up to date by the owner (``valterm.core.collision.frames``); else computed per pair
    planes: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
    stale: np.ndarray | None = None   # (N,) bool: planes of these polyhedra moved, not kept
    # called before the kept planes are read: the owner brings them up to date only when a
    # fine check needs them (most steps need none)
    refresh: Callable[[], None] | None = None
    # per pair (a[i], b[i]): True where the owner can show cheaply that the two are more than
    # SEPARATED mm apart (the fine test then answers clear without its own arrays); else False
    apart: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None

    @classmethod
    def of(cls, polys: Sequence[Polyhedron]) -> "Scene":
        lay = layout(tuple(len(p.vertices) // 2 for p in polys))
        if not polys:
            z = np.zeros((0, 3))
            return cls(lay, z, z, np.zeros(0), z, z)
        v = np.concatenate([p.vertices for p in polys])
        return cls(lay, v, *figures(v, lay.starts, lay.counts))

    @property
    def lo(self) -> np.ndarray:
        lo: np.ndarray = self.mid - self.half
        return lo

    @property
    def hi(self) -> np.ndarray:
        hi: np.ndarray = self.mid + self.half
        return hi


def figures(v: np.ndarray, starts: np.ndarray, counts: np.ndarray
            ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Centres, circumscribed radii, box middles and box half-sizes of polyhedra whose vertices
    are stacked in ``v``, each starting at ``starts`` with ``counts`` vertices."""
    centres = np.add.reduceat(v, starts, axis=0) / counts[:, None]
    d = v - np.repeat(centres, counts, axis=0)
    radii = np.sqrt(np.maximum.reduceat(np.einsum("ij,ij->i", d, d), starts))
    lo = np.minimum.reduceat(v, starts, axis=0)
    hi = np.maximum.reduceat(v, starts, axis=0)
    return centres, radii, (lo + hi) * 0.5, (hi - lo) * 0.5


# cross products as one matmul: (a outer b) flattened to 9, times the Levi-Civita symbol
_LEVI = np.zeros((9, 3))
for _i, _j, _k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
    _LEVI[3 * _j + _k, _i] = 1.0
    _LEVI[3 * _k + _j, _i] = -1.0


@lru_cache(maxsize=16)
def _levi_summed(m: int) -> np.ndarray:
    """Levi-Civita stacked m times: the matmul also sums the m cross products (Newell)."""
    tiled: np.ndarray = np.tile(_LEVI, (m, 1))
    return tiled


def _outer(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    outer: np.ndarray = (a[..., :, None] * b[..., None, :]).reshape(*a.shape[:-1], 9)
    return outer


def largest_of_xyz(d: np.ndarray) -> np.ndarray:
    """Per row of (n, 3), the largest coordinate: two ufuncs (a numpy reduction along an
    axis of three is many times slower for the few hundred rows of a step)."""
    out: np.ndarray = np.maximum(d[:, 0], d[:, 1])
    np.maximum(out, d[:, 2], out=out)
    return out


# -- the two checks ----------------------------------------------------------------------------

def face_planes(vertices: np.ndarray, face_idx: np.ndarray, face_next: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Unit normal, offset and twice the area of every face (Newell), for (P, F, M) face indices."""
    poly = vertices[face_idx]
    nxt = vertices[face_next]
    pn, f, m = poly.shape[0], poly.shape[1], poly.shape[2]
    # Newell's vector area, sum of v_i x v_i+1: twice the area times the unit normal
    area2 = _outer(poly, nxt).reshape(pn, f, 9 * m) @ _levi_summed(m)           # (P, F, 3)
    size = np.sqrt(np.einsum("nfk,nfk->nf", area2, area2))                    # 2 * area
    unit = area2 / np.where(size > 0, size, 1.0)[..., None]
    off = np.einsum("nfk,nfk->nf", poly[:, :, 0], unit)
    return unit, off, size


def _kept_planes(scene: Scene, dst: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The face planes of ``dst`` from the scene's kept ones, the moved polyhedra's computed now."""
    assert scene.planes is not None
    if scene.refresh is not None:
        scene.refresh()
    unit, off, size = (x.take(dst, axis=0) for x in scene.planes)
    if scene.stale is not None:
        rows = np.flatnonzero(scene.stale.take(dst))
        if len(rows):
            which, back = np.unique(dst.take(rows), return_inverse=True)
            lay = scene.layout
            u, o, z = face_planes(scene.vertices, lay.face_idx.take(which, axis=0),
                                  lay.face_next.take(which, axis=0))
            unit[rows], off[rows], size[rows] = u[back], o[back], z[back]
    return unit, off, size


def fine(scene: Scene, a: np.ndarray, b: np.ndarray, shortcut: bool = True) -> np.ndarray:
    """Boolean per pair (a[i], b[i]): does an edge of one cross a face polygon of the other,
    or does one lie wholly inside the other (its centre inside)?

    ``shortcut``: when a face plane separates every pair (``_separated``), answer clear at
    once (the same answer, fewer numpy calls; off only to test that it is the same), and
    likewise the pairs the scene's owner finds ``apart`` first."""
    n = len(a)
    if n == 0:
        return np.zeros(0, dtype=bool)
    if shortcut and scene.apart is not None:
        todo = np.flatnonzero(~scene.apart(a, b))
        if len(todo) < n:
            hit = np.zeros(n, dtype=bool)
            if len(todo):
                hit[todo] = _edges_cross_faces(scene, a.take(todo), b.take(todo), shortcut)
            return hit
    return _edges_cross_faces(scene, a, b, shortcut)


def _edges_cross_faces(scene: Scene, a: np.ndarray, b: np.ndarray, shortcut: bool) -> np.ndarray:
    """``fine`` itself: the edge-face test of Fig. 2-14 and the containment test."""
    n = len(a)
    lay, v = scene.layout, scene.vertices
    src = np.concatenate([a, b])    # whose edges
    dst = np.concatenate([b, a])    # whose faces
    seg = v[lay.edge_idx.take(src, axis=0)]                 # (2n, E, 2, 3)
    faces = lay.face_idx.take(dst, axis=0)                  # (2n, F, M)
    if scene.planes is None:
        unit, off, size = face_planes(v, faces, lay.face_next.take(dst, axis=0))
    else:
        unit, off, size = _kept_planes(scene, dst)
    pn, e, f, m = faces.shape[0], seg.shape[1], faces.shape[1], faces.shape[2]
    # signed distances of both ends of every edge from every face plane: one batched matmul
    s = (seg.reshape(pn, 2 * e, 3) @ unit.transpose(0, 2, 1)).reshape(pn, e, 2, f) - off[:, None, None, :]
    s0, s1 = s[:, :, 0], s[:, :, 1]
    # each face oriented away from its own polyhedron's centre (the file's winding is free)
    outward = -np.sign(np.einsum("nfk,nk->nf", unit, scene.centres.take(dst, axis=0)) - off)
    crossing = (np.minimum(s0, s1) < -EPS) & (np.maximum(s0, s1) > EPS)
    if shortcut:
        sep = _separated(s, outward, n)
        if sep.all():
            return np.zeros(n, dtype=bool)
        if sep.any():                   # those pairs are clear: only the others' crossings
            crossing &= ~np.concatenate([sep, sep])[:, None, None]
    contained = _contained(scene.centres, src, unit, off, size, outward)
    hit: np.ndarray = contained[:n] | contained[n:]
    cand = np.flatnonzero(crossing)                  # flat (pair, edge, face) candidates
    if len(cand) == 0:
        return hit
    pair, rest = np.divmod(cand, e * f)
    edge = pair * e + rest // f
    face = pair * f + rest % f
    # where on the segment the plane is met, then the triangle-area sum of Fig. 2-14 B
    a0 = s0.take(cand)
    ends = seg.reshape(pn * e, 2, 3).take(edge, axis=0)
    x = ends[:, :1] + (a0 / (a0 - s1.take(cand)))[:, None, None] * (ends[:, 1:] - ends[:, :1])
    corners = faces.reshape(pn * f, m).take(face, axis=0)
    following = lay.face_next.take(dst, axis=0).reshape(pn * f, m).take(face, axis=0)
    tri = _outer(v[corners] - x, v[following] - x) @ _LEVI                     # (c, M, 3)
    tri_sum = np.sqrt(np.einsum("cmk,cmk->cm", tri, tri)).sum(axis=1)
    inside = tri_sum <= size.take(face) * (1.0 + AREA_TOL)
    hit[pair[inside] % n] = True
    return hit


def _separated(s: np.ndarray, outward: np.ndarray, n: int) -> np.ndarray:
    """Per pair: does a face plane of one have every vertex of the other more than ``SEPARATED``
    mm on its outer side? Then nothing of the other can reach that face's polyhedron: no
    edge crosses a face polygon, no centre is inside, and the fine test answers clear.

    ``s``: signed distances (2n, E, 2, F) of both ends of every edge from every face plane
    (the ends cover every vertex). The margin is far above what the area test's tolerance
    lets a crossing point lie outside its polygon, so this shortcut never changes an answer.
    """
    out = s * outward[:, None, None, :]
    beyond = (out.min(axis=(1, 2)) > SEPARATED).any(axis=1)      # (2n,): a face plane separates
    sep: np.ndarray = beyond[:n] | beyond[n:]
    return sep


def _contained(centres: np.ndarray, src: np.ndarray, unit: np.ndarray, off: np.ndarray,
               size: np.ndarray, outward: np.ndarray) -> np.ndarray:
    """Per (src, dst): is src's centre strictly inside the convex dst (all its face planes)?

    The containment test the 1985 edge-face check lacks: a polyhedron wholly inside another
    crosses no face, but its centre lies inside the other. ``outward``: each face's sign
    pointing away from dst's own centre, so the file's winding does not matter.
    """
    d_src = np.einsum("nfk,nk->nf", unit, centres.take(src, axis=0)) - off
    inner = d_src * outward < -EPS
    result = np.asarray(np.where(size > 0, inner, True).all(axis=1), dtype=bool)
    return result


def check_pairs(scene: Scene, moving: np.ndarray, stationary: np.ndarray, grow: float,
                fine_only: np.ndarray | None = None, gaps: np.ndarray | None = None) -> np.ndarray:
    """Kind codes (CLEAR/NEAR/COLLIDES) per pair, the coarse test gating the fine one.

    ``fine_only`` marks pairs where only the coarse test is run (never COLLIDES).
    ``gaps``: filled with how far apart each pair's two boxes are (the swept check's figure).
    """
    moving = np.asarray(moving, dtype=np.intp)
    stationary = np.asarray(stationary, dtype=np.intp)
    mid_s, half_s = scene.mid.take(stationary, axis=0), scene.half.take(stationary, axis=0)
    gap = np.abs(scene.centres.take(moving, axis=0) - mid_s)
    gap -= half_s
    # the coarse test: the moving centre inside the stationary box grown by radius + margin
    near = largest_of_xyz(gap) <= scene.radii.take(moving) + grow
    codes = near.astype(np.int8)
    if fine_only is not None:
        near &= ~fine_only
    # an edge can only cross a face where the two extreme boxes overlap: the fine test runs
    # on near pairs whose boxes meet (an exact shortcut, not a change to the 1985 answer)
    if gaps is not None:            # every pair's boxes: their gaps are asked for
        gaps[:] = box_gaps(scene.mid.take(moving, axis=0), scene.half.take(moving, axis=0), mid_s, half_s)
        at = (near & (gaps <= EPS)).nonzero()[0]     # flatnonzero's, without its Python wrappers
    else:                           # the near pairs' only: most poses have none
        at = near.nonzero()[0]
        if len(at):
            near_moving = moving.take(at)
            at = at[box_gaps(scene.mid.take(near_moving, axis=0), scene.half.take(near_moving, axis=0),
                             mid_s[at], half_s[at]) <= EPS]
    if len(at):
        codes[at[fine(scene, moving.take(at), stationary.take(at))]] = COLLIDES
    return codes


def box_gaps(mid_a: np.ndarray, half_a: np.ndarray, mid_b: np.ndarray, half_b: np.ndarray) -> np.ndarray:
    """How far apart boxes a[i] and b[i] are (given as middles and half sizes, (n, 3)): their
    largest gap on an axis, below 0 where they overlap."""
    apart = np.abs(mid_a - mid_b)
    apart -= half_a + half_b
    return largest_of_xyz(apart)


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
