"""Points of a part -> the extruded convex polyhedron that envelops it (§2.1, §7.1).

The thesis represents every object by a front polygon swept along a normal axis. Given a
part's 3-D points we pick the sweep axis that gives the tightest prism (world X/Y/Z first,
then the principal axes), take the 2-D convex hull of the points projected along it and
extrude it over the part's depth. The prism contains every point, so collision checks on
the envelope never miss the real part.
"""

from __future__ import annotations

import numpy as np

from valterm.core.cad.errors import DegeneratePart
from valterm.core.cell.polyhedron import Polyhedron

MAX_HULL_VERTICES = 32   # more than enough for a 1985-style envelope; keeps drawing cheap
MIN_DEPTH_MM = 1.0       # depth given to flat parts (a sheet, a sketch in one plane)
_REL_TOL = 1e-9


def _cross2(o: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    cross: np.ndarray = ((a[..., 0] - o[..., 0]) * (b[..., 1] - o[..., 1])
                         - (a[..., 1] - o[..., 1]) * (b[..., 0] - o[..., 0]))
    return cross


def _prefilter(pts: np.ndarray) -> np.ndarray:
    """Drop points strictly inside the polygon of 16 extreme points (Akl-Toussaint), vectorised."""
    if len(pts) < 64:
        return pts
    ang = np.linspace(0.0, 2 * np.pi, 16, endpoint=False)
    dirs = np.stack([np.cos(ang), np.sin(ang)], 1)
    x, y = np.ascontiguousarray(pts[:, 0]), np.ascontiguousarray(pts[:, 1])
    # one direction at a time: contiguous passes, no (n, 16) matrix (a mesh may have millions of points)
    idx = np.array([int(np.argmax(x * c + y * s)) for c, s in dirs])
    idx = idx[np.concatenate([[True], np.diff(idx) != 0])]
    if len(idx) > 1 and idx[0] == idx[-1]:
        idx = idx[:-1]
    poly = pts[idx]
    if len(poly) < 3:
        return pts
    nxt = np.roll(poly, -1, axis=0)
    # cross > 0 for every edge -> strictly inside the (counter-clockwise) extreme polygon
    inside = np.ones(len(pts), dtype=bool)
    for (ox, oy), (ax, ay) in zip(poly, nxt):
        inside &= (ax - ox) * (y - oy) - (ay - oy) * (x - ox) > 0
    outside: np.ndarray = pts[~inside]
    return outside


def convex_hull_2d(points: np.ndarray) -> np.ndarray:
    """Counter-clockwise convex hull of (n, 2) points, no repeats (quickhull, vectorised per edge)."""
    pts = _prefilter(np.asarray(points, dtype=float))
    # after the prefilter; as complex numbers: a plain numeric sort (x, then y), not row-by-row
    unique = np.unique(pts[:, 0] + 1j * pts[:, 1])
    pts = np.stack([unique.real, unique.imag], 1)
    if len(pts) < 3:
        return pts
    scale = float(np.ptp(pts, axis=0).max()) or 1.0
    eps = _REL_TOL * scale * scale
    a = int(np.lexsort((pts[:, 1], pts[:, 0]))[0])     # lowest x (then y): on the hull
    b = int(np.lexsort((-pts[:, 1], -pts[:, 0]))[0])   # highest x: on the hull
    idx = np.arange(len(pts))

    def side(i: int, j: int, cand: np.ndarray) -> np.ndarray:
        """Candidates strictly right of i->j (outside, for a counter-clockwise hull)."""
        c = _cross2(pts[i], pts[j], pts[cand])
        return cand[c < -eps]

    # hull vertices between i and j (exclusive), found by splitting at the farthest point
    def between(i: int, j: int, cand: np.ndarray) -> list[int]:
        # iterative in-order walk: (i, j, cand) -> [between(i, far), far, between(far, j)]
        result: list[int] = []
        work: list[int | tuple[int, int, np.ndarray]] = [(i, j, cand)]
        while work:
            item = work.pop()
            if isinstance(item, int):
                result.append(item)
                continue
            p, q, c = item
            if len(c) == 0:
                continue
            far = int(c[np.argmin(_cross2(pts[p], pts[q], pts[c]))])
            left, right = side(p, far, c), side(far, q, c)
            work.extend([(far, q, right), far, (p, far, left)])
        return result

    lower = between(a, b, side(a, b, idx))   # below a->b, walking from a to b
    upper = between(b, a, side(b, a, idx))
    return pts[[a, *lower, b, *upper]]


def polygon_area(poly: np.ndarray) -> float:
    if len(poly) < 3:
        return 0.0
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def circumscribe(hull: np.ndarray, n: int = MAX_HULL_VERTICES) -> np.ndarray:
    """A convex n-gon (or fewer vertices) containing ``hull``: support lines in n directions.

    The directions include the two axes, so the extents along them stay exact.
    """
    ang = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    dirs = np.stack([np.cos(ang), np.sin(ang)], 1)
    h = (hull @ dirs.T).max(axis=0)
    d2 = np.roll(dirs, -1, axis=0)
    h2 = np.roll(h, -1)
    det = dirs[:, 0] * d2[:, 1] - dirs[:, 1] * d2[:, 0]
    x = (h * d2[:, 1] - h2 * dirs[:, 1]) / det
    y = (dirs[:, 0] * h2 - d2[:, 0] * h) / det
    poly = np.stack([x, y], 1)
    # consecutive support lines through one hull vertex meet there: merge repeats
    scale = float(np.ptp(hull, axis=0).max()) or 1.0
    keep = np.linalg.norm(poly - np.roll(poly, 1, axis=0), axis=1) > 1e-9 * scale
    return convex_hull_2d(poly[keep] if keep.sum() >= 3 else poly)


def _basis(axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Right-handed (u, v) with u x v = axis."""
    helper = np.eye(3)[int(np.argmin(np.abs(axis)))]
    u = np.cross(helper, axis)
    u /= np.linalg.norm(u)
    v = np.cross(axis, u)
    return u, v


_WORLD = np.eye(3)
_WORLD_BASES = {0: (np.array([0.0, 1, 0]), np.array([0.0, 0, 1])),
                1: (np.array([0.0, 0, 1]), np.array([1.0, 0, 0])),
                2: (np.array([1.0, 0, 0]), np.array([0.0, 1, 0]))}


def extruded_hull(points: np.ndarray, name: str = "", min_depth: float = MIN_DEPTH_MM) -> tuple[Polyhedron, list[str]]:
    """The tightest extruded convex polyhedron enveloping ``points`` (mm) and any warnings.

    Raises ``DegeneratePart`` when the points enclose no area at all.
    """
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    pts = pts[np.all(np.isfinite(pts), axis=1)]
    if len(pts) == 0:
        raise DegeneratePart("it has no geometry that can be drawn")
    scale = float(np.ptp(pts, axis=0).max())
    if scale <= 0:
        raise DegeneratePart("all its points coincide: it has no size")

    centred = pts - pts.mean(axis=0)
    _, vecs = np.linalg.eigh(centred.T @ centred)
    candidates: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = [( _WORLD[i], *_WORLD_BASES[i]) for i in range(3)]
    for j in range(3):
        a = vecs[:, j] / np.linalg.norm(vecs[:, j])
        candidates.append((a, *_basis(a)))

    best = None
    for index, (axis, u, v) in enumerate(candidates):
        hull = convex_hull_2d(np.stack([pts @ u, pts @ v], 1))
        area = polygon_area(hull)
        if len(hull) < 3 or area <= 1e-9 * scale * scale:
            continue
        d = pts @ axis
        depth = float(d.max() - d.min())
        volume = area * max(depth, min_depth)
        # world axes win unless a principal axis is 1 % tighter: axis-aligned parts stay aligned
        if best is None or volume < best[0] * (1 - 1e-2):
            best = (volume, index, axis, u, v, hull, float(d.min()), float(d.max()))
    if best is None:
        raise DegeneratePart("all its points lie on one line: there is no outline to extrude")
    _, _, axis, u, v, hull, lo, hi = best

    warnings: list[str] = []
    if len(hull) > MAX_HULL_VERTICES:
        n0 = len(hull)
        hull = circumscribe(hull)
        warnings.append(f"{name or 'part'}: outline of {n0} vertices simplified to {len(hull)} (enclosing polygon)")
    if hi - lo < min_depth:
        mid = 0.5 * (lo + hi)
        lo, hi = mid - min_depth / 2, mid + min_depth / 2
        warnings.append(f"{name or 'part'}: flat (no thickness); given a depth of {min_depth:g} mm")
    if len(hull) == 3:
        # a setup-file polygon needs >= 4 vertices: split the longest edge
        edges = np.linalg.norm(np.roll(hull, -1, axis=0) - hull, axis=1)
        i = int(np.argmax(edges))
        hull = np.insert(hull, i + 1, 0.5 * (hull[i] + hull[(i + 1) % 3]), axis=0)

    flat = hull[:, :1] * u + hull[:, 1:2] * v
    # front polygon at the low end, listed counter-clockwise seen from outside (from -axis)
    front = flat[::-1] + lo * axis
    back = flat[::-1] + hi * axis
    return Polyhedron.from_polygons(front, back, name), warnings
