"""The model view's rasterizer: wireframe polyhedra -> braille (or ASCII) character cells.

Pure numpy, no textual or rich, so `valterm bench` and the tests run it headless.

Pipeline (§2.1-§2.3 of the thesis, Fig. 2-5):
world mm --(SCS mapping, ORIENT view transform)--> view mm --(fit to canvas)--> dots
(2 x 4 per cell) --> one U+2800 braille code per cell, one colour index per cell.

With hidden-surface removal on (``back_faces=False``) the polyhedra are drawn polygon by
polygon and a face whose transformed normal has Z_s < 0 is skipped (an edge shared by two
front faces is drawn twice, as in 1985); with back faces on every edge is drawn once
(segment by segment).
"""

from __future__ import annotations

import codecs
import math
from dataclasses import dataclass, field
from functools import cached_property, lru_cache
from typing import Iterable, Sequence

import numpy as np

from valterm.core.cell.polyhedron import Polyhedron, topology
from valterm.core.render.legend import (
    AXES_COLOUR,
    LED_COLOUR,
    LINK_COLOUR_BASE,
    N_OBJECT_COLOURS,
    OBJECT_COLOUR_BASE,
)

# -- frames (SPEC §1) ------------------------------------------------------------------
SCS_H = 26.0
# X_s = Y_w, Y_s = Z_w + H, Z_s = X_w (a cyclic permutation: right-handed).
WORLD_TO_SCS = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
SCS_OFFSET = np.array([0.0, SCS_H, 0.0])

# The robot at READY reaches ~990 mm up; the cell spans about +-1000 mm; tables sit ~-610.
DEFAULT_BOUNDS: tuple[np.ndarray, np.ndarray] = (
    np.array([-1000.0, -1000.0, -700.0]),
    np.array([1000.0, 1000.0, 1100.0]),
)


def link_colour(link: int) -> int:
    """Colour index of robot link ``link`` (0 = base)."""
    return LINK_COLOUR_BASE + link % 8


def object_colour(number: int) -> int:
    """Colour index of work-cell object ``number`` (1..n)."""
    return OBJECT_COLOUR_BASE + (number - 1) % N_OBJECT_COLOURS


AXIS_LENGTH = 400.0  # mm, the WCS frame drawn by AXES

# Braille dot bits by (row, col) inside a cell.
BRAILLE_WEIGHTS = np.array([[1, 8], [2, 16], [4, 32], [64, 128]], dtype=np.uint8)
BRAILLE_BASE = 0x2800


def axis_rotation(axis: str, degrees: float) -> np.ndarray:
    """Right-handed rotation about ``axis`` ('x', 'y' or 'z')."""
    a = math.radians(degrees)
    c, s = math.cos(a), math.sin(a)
    if axis in ("x", "X"):
        return np.array([[1.0, 0, 0], [0, c, -s], [0, s, c]])
    if axis in ("y", "Y"):
        return np.array([[c, 0, s], [0, 1.0, 0], [-s, 0, c]])
    if axis in ("z", "Z"):
        return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])
    raise ValueError(f"axis must be x, y or z, not {axis!r}")


# -- the view transform (Keyboard ORIENT) ----------------------------------------------
@dataclass
class ViewTransform:
    """World -> view millimetres: ``q = scale * R (S p + h - pivot) + pan``.

    S, h are the SCS mapping; R rotates about the screen axes through ``pivot`` (an SCS
    point, the centre of the fitted bounds); ``pan`` shifts in screen mm. The canvas shows
    ``half_extent`` (view mm, at scale 1) about the origin. World data is never touched.
    """

    rotation: np.ndarray = field(default_factory=lambda: np.eye(3))
    scale: float = 1.0
    pan: np.ndarray = field(default_factory=lambda: np.zeros(2))
    pivot: np.ndarray | None = None  # None: fit to home_bounds
    half_extent: np.ndarray | None = None
    home_bounds: tuple[np.ndarray, np.ndarray] = DEFAULT_BOUNDS

    def __post_init__(self) -> None:
        self.rotation = np.asarray(self.rotation, dtype=float)
        self.pan = np.asarray(self.pan, dtype=float)
        if self.pivot is None or self.half_extent is None:
            scale, pan = self.scale, self.pan
            self.fit(self.home_bounds)
            self.scale, self.pan = scale, pan

    # -- composing ------------------------------------------------------------
    def rotate_by(self, axis: str, degrees: float) -> "ViewTransform":
        """Turn the picture about a screen axis (x right, y up, z at the viewer)."""
        self.rotation = axis_rotation(axis, degrees) @ self.rotation
        return self

    def scale_by(self, factor: float) -> "ViewTransform":
        if not factor > 0:
            raise ValueError("the scale factor must be positive")
        self.scale *= factor
        return self

    def pan_by(self, dx: float, dy: float) -> "ViewTransform":
        """Shift the picture by (dx, dy) screen mm (right, up)."""
        self.pan = self.pan + np.array([dx, dy], dtype=float)
        return self

    def reset(self) -> "ViewTransform":
        """Back to the default view: the SCS mapping, fitted to the home bounds."""
        self.rotation = np.eye(3)
        return self.fit(self.home_bounds)

    def fit(self, bounds: tuple[Sequence[float] | np.ndarray, Sequence[float] | np.ndarray],
            margin: float = 0.04) -> "ViewTransform":
        """Centre and size the view on a world box (lo, hi) as seen with the current rotation."""
        lo, hi = (np.asarray(b, dtype=float) for b in bounds)
        self.home_bounds = (lo.copy(), hi.copy())
        corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
        scs = corners @ WORLD_TO_SCS.T + SCS_OFFSET
        self.pivot = (scs.min(axis=0) + scs.max(axis=0)) / 2
        seen = (scs - self.pivot) @ self.rotation.T
        self.half_extent = np.maximum(np.abs(seen[:, :2]).max(axis=0), 1.0) * (1 + margin)
        self.scale = 1.0
        self.pan = np.zeros(2)
        return self

    # -- using ----------------------------------------------------------------
    def affine(self) -> tuple[np.ndarray, np.ndarray]:
        """(A, b) with view = A @ world + b."""
        assert self.pivot is not None  # set by __post_init__
        a = self.scale * (self.rotation @ WORLD_TO_SCS)
        b = self.scale * (self.rotation @ (SCS_OFFSET - self.pivot))
        b[:2] += self.pan
        return a, b

    def depth_axis(self) -> np.ndarray:
        """World direction that points at the viewer (Z_s after the view rotation)."""
        axis: np.ndarray = (self.rotation @ WORLD_TO_SCS)[2]
        return axis

    def key(self) -> bytes:
        """A value that changes whenever the picture would (for redraw decisions)."""
        a, b = self.affine()
        assert self.half_extent is not None
        return a.tobytes() + b.tobytes() + self.half_extent.tobytes()

    def copy(self) -> "ViewTransform":
        assert self.pivot is not None and self.half_extent is not None
        return ViewTransform(
            self.rotation.copy(), self.scale, self.pan.copy(), self.pivot.copy(),
            self.half_extent.copy(), self.home_bounds,
        )


# -- the scene ---------------------------------------------------------------------------
@dataclass(frozen=True)
class _Index:
    """Global index arrays for a sequence of polyhedron sizes (cached: the same robot and cell
    give the same sizes every frame)."""

    vertex_item: np.ndarray  # (V,)
    edges: np.ndarray  # (E, 2) each edge once
    edge_item: np.ndarray  # (E,)
    faces: np.ndarray  # (F, m) vertex indices, short faces padded with their last vertex
    face_item: np.ndarray  # (F,)
    face_edges: np.ndarray  # (FE, 2) polygon-by-polygon edges
    face_edge_face: np.ndarray  # (FE,)


@lru_cache(maxsize=64)
def _index(ks: tuple[int, ...]) -> _Index:
    vertex_item, edges, edge_item, faces, face_item, face_edges, face_edge_face = [], [], [], [], [], [], []
    width = max([max(k, 4) for k in ks], default=4)
    offset = 0
    n_faces = 0
    for item, k in enumerate(ks):
        top = topology(k)
        padded, polygon_edges, polygon_edge_face = _polygons(k, width)
        vertex_item.append(np.full(2 * k, item))
        edges.append(top.edges + offset)
        edge_item.append(np.full(len(top.edges), item))
        faces.append(padded + offset)
        face_edges.append(polygon_edges + offset)
        face_edge_face.append(polygon_edge_face + n_faces)
        face_item.append(np.full(len(top.faces), item))
        n_faces += len(top.faces)
        offset += 2 * k

    def cat(parts: list[np.ndarray], shape: tuple[int, ...]) -> np.ndarray:
        return np.concatenate(parts).astype(np.intp) if parts else np.zeros(shape, dtype=np.intp)

    return _Index(
        cat(vertex_item, (0,)), cat(edges, (0, 2)), cat(edge_item, (0,)), cat(faces, (0, width)),
        cat(face_item, (0,)), cat(face_edges, (0, 2)), cat(face_edge_face, (0,)),
    )


@lru_cache(maxsize=64)
def _polygons(k: int, width: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One polyhedron of ``k`` vertices a polygon, numbered from 0: its faces padded to
    ``width`` with their last vertex (zero-length edges: harmless for Newell's normal), its
    polygon-by-polygon edges and the face of each. Once per size, not a few numpy calls a
    face at every new scene (issue 25: the start's first picture)."""
    top = topology(k)
    padded = np.stack([np.concatenate([face, np.full(width - len(face), face[-1])]) for face in top.faces])
    edge_face = np.concatenate([np.full(len(fe), f) for f, fe in enumerate(top.face_edges)])
    return padded, np.concatenate(top.face_edges), edge_face


@dataclass(frozen=True, eq=False)
class Scene:
    """What the model view draws: polyhedra with a colour index each, plus loose segments.

    Build with :meth:`Scene.build`. Drawing order is priority: where two items share a
    character cell, the later item's colour wins (put the robot after the cell, a carried
    part after the robot). Loose lines (the LED sensor, extra frames) always draw.
    """

    vertices: np.ndarray  # (V, 3) world mm, all polyhedra concatenated
    colours: np.ndarray  # (n_polyhedra,) colour index per polyhedron
    index: _Index
    lines: np.ndarray  # (L, 2, 3) world mm
    line_colours: np.ndarray  # (L,)
    # what does not move (the cell's parts), drawn before everything here: rasterised once
    # per view and size and kept (see ``rasterize``); build it once and pass the same object
    background: "Scene | None" = None

    @classmethod
    def build(
        cls,
        items: Iterable[tuple[Polyhedron, int]],
        lines: np.ndarray | Sequence[Sequence[Sequence[float]]] | None = None,
        line_colours: Sequence[int] | int = LED_COLOUR,
        background: "Scene | None" = None,
    ) -> "Scene":
        """``items``: (polyhedron, colour index) pairs in drawing order; ``lines``: (L, 2, 3);
        ``background``: a static scene drawn first (its own lines and background ignored)."""
        items = list(items)
        polys = [p for p, _ in items]
        vertices = np.concatenate([p.vertices for p in polys]) if polys else np.zeros((0, 3))
        colours = np.array([c for _, c in items], dtype=np.uint8)
        seg = np.zeros((0, 2, 3)) if lines is None else np.asarray(lines, dtype=float).reshape(-1, 2, 3)
        lc = np.broadcast_to(np.asarray(line_colours, dtype=np.uint8), (len(seg),)).copy()
        return cls(vertices, colours, _index(tuple(p.k for p in polys)), seg, lc, background)

    @property
    def n_polyhedra(self) -> int:
        return len(self.colours)

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        back = self.background.vertices if self.background is not None else np.zeros((0, 3))
        pts = np.concatenate([back, self.vertices, self.lines.reshape(-1, 3)])
        if len(pts) == 0:
            return DEFAULT_BOUNDS
        return pts.min(axis=0), pts.max(axis=0)

    @cached_property
    def _normals(self) -> np.ndarray:
        return self.face_normals()

    def face_normals(self) -> np.ndarray:
        """(F, 3) outward unit normals of every face, Newell's method on all faces at once."""
        idx = self.index
        if len(idx.faces) == 0:
            return np.zeros((0, 3))
        pts = self.vertices[idx.faces]  # (F, m, 3)
        nxt = np.roll(pts, -1, axis=1)
        d = pts - nxt
        s = pts + nxt
        n = np.stack([
            (d[..., 1] * s[..., 2]).sum(1),
            (d[..., 2] * s[..., 0]).sum(1),
            (d[..., 0] * s[..., 1]).sum(1),
        ], axis=1)
        n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
        # outward: the face's point must lie on the far side from its polyhedron's centre
        counts = np.bincount(idx.vertex_item, minlength=self.n_polyhedra)[:, None]
        centres = np.stack([np.bincount(idx.vertex_item, self.vertices[:, a], self.n_polyhedra) for a in range(3)], 1) / counts
        outward = np.einsum("ij,ij->i", n, pts.mean(axis=1) - centres[idx.face_item])
        n[outward < 0] *= -1
        return n

    def visible_faces(self, view: ViewTransform) -> np.ndarray:
        """(F,) bool: front faces (transformed normal Z_s >= 0; edge-on faces count as front)."""
        visible: np.ndarray = self._normals @ view.depth_axis() >= -1e-9   # normals kept per scene
        return visible

    def segments(self, view: ViewTransform, back_faces: bool) -> tuple[np.ndarray, np.ndarray]:
        """World segments to draw, (S, 2, 3), and the priority (item number + 1) of each.

        Loose lines get priorities after the polyhedra."""
        pairs, prio = self.drawn_pairs(view, back_faces, axes=False)
        return self.drawn_points(axes=False)[pairs], prio

    def palette_indices(self) -> np.ndarray:
        """Colour index by priority (index 0 = empty)."""
        return np.concatenate([[0], self.colours, self.line_colours]).astype(np.uint8)

    @cached_property
    def _palette_with_axes(self) -> np.ndarray:
        return np.concatenate([self.palette_indices(), [AXES_COLOUR]]).astype(np.uint8)

    def drawn_points(self, axes: bool) -> np.ndarray:
        """Every point a segment of ``drawn_pairs`` names: the vertices, then the loose lines'
        ends, then (``axes``) the WCS axes' ends (kept: a scene's points do not change)."""
        return self._drawn_points[int(axes)]

    @cached_property
    def _drawn_points(self) -> tuple[np.ndarray, np.ndarray]:
        points = np.concatenate([self.vertices, self.lines.reshape(-1, 3)])
        return points, np.concatenate([points, _AXES_POINTS])

    @cached_property
    def _every_paint(self) -> tuple[np.ndarray, np.ndarray]:
        """The colour of every edge (back faces on), without and with the WCS axes."""
        palette = self._palette_with_axes
        return palette.take(self._every_pair[0][1]), palette.take(self._every_pair[1][1])

    @cached_property
    def _every_end_at(self) -> tuple[np.ndarray, np.ndarray]:
        """``_end_at`` of every edge (back faces on), without and with the WCS axes."""
        return _end_at(self._every_pair[0][0]), _end_at(self._every_pair[1][0])

    def drawn_pairs(self, view: ViewTransform, back_faces: bool, axes: bool) -> tuple[np.ndarray, np.ndarray]:
        """The segments to draw as index pairs into ``drawn_points`` (S, 2), and the priority
        of each: ``segments`` without fetching the points (so each is projected once)."""
        if back_faces:
            return self._every_pair[int(axes)]  # every edge: the same for every view
        idx = self.index
        keep = self.visible_faces(view)[idx.face_edge_face]
        lines, line_prio = self._line_pairs[int(axes)]
        return (np.concatenate([idx.face_edges[keep], lines]),
                np.concatenate([idx.face_item[idx.face_edge_face[keep]] + 1, line_prio]))

    @cached_property
    def _line_pairs(self) -> tuple[tuple[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]:
        """The loose lines (after the vertices) as pairs and their priorities (after the
        polyhedra), without and with the WCS axes."""
        n_lines = len(self.lines)
        pairs = len(self.vertices) + np.arange(2 * (n_lines + 3)).reshape(-1, 2)
        prio = self.n_polyhedra + 1 + np.minimum(np.arange(n_lines + 3), n_lines)
        return (pairs[:n_lines], prio[:n_lines]), (pairs, prio)

    @cached_property
    def _every_pair(self) -> tuple[tuple[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]:
        idx = self.index
        return tuple(  # type: ignore[return-value]
            (np.concatenate([idx.edges, lines]), np.concatenate([idx.edge_item + 1, prio]))
            for lines, prio in self._line_pairs)


def frame_lines(origin: Sequence[float] | np.ndarray, rotation: np.ndarray | None = None, length: float = AXIS_LENGTH) -> np.ndarray:
    """(3, 2, 3) segments of a coordinate frame (x, y, z axes), e.g. a part's frame in
    MANIPULATION mode, to pass as Scene lines."""
    o = np.asarray(origin, dtype=float)
    r = np.eye(3) if rotation is None else np.asarray(rotation, dtype=float)
    return np.stack([np.stack([o, o + length * r[:, i]]) for i in range(3)])


# -- the frame ---------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class Frame:
    """A rasterized picture: ``chars`` (H, W) code points, ``colours`` (H, W) colour indices.

    ``text_units``: the frame's text as UTF-16 units, H rows of W + 1 ending in a newline,
    with ``chars`` a view of its first W columns (``rasterize`` draws the characters there,
    so ``text`` is one decode); None: ``text`` makes it from ``chars``."""

    chars: np.ndarray
    colours: np.ndarray
    text_units: np.ndarray | None = field(default=None, repr=False)

    @property
    def width(self) -> int:
        return int(self.chars.shape[1])

    @property
    def height(self) -> int:
        return int(self.chars.shape[0])

    def row_text(self, y: int) -> str:
        units = self.text_units
        if units is not None:
            w = self.width
            return str(codecs.utf_16_le_decode(units[y * (w + 1): y * (w + 1) + w].data)[0])
        return str(self.chars[y].astype("<u4").tobytes().decode("utf-32-le"))

    def lines(self) -> list[str]:
        return self.text().split("\n") if self.height else []

    def text(self) -> str:
        """The rows joined by newlines: one decode of the whole grid with a newline column
        (not a decode and a join per row)."""
        units = self.text_units
        if units is not None:     # drawn as text already (rows of w + 1): less the last newline
            text: str = codecs.utf_16_le_decode(units[:-1].data)[0]
            return text
        h, w = self.chars.shape
        if h == 0:
            return ""
        # braille and ASCII lie below the surrogates: two bytes a character decode in half the time
        narrow = w == 0 or int(_MAX(self.chars, axis=None)) < 0xD800
        flat = np.empty(h * (w + 1), dtype="<u2" if narrow else "<u4")
        grid = flat.reshape(h, w + 1)
        grid[:, :w] = self.chars
        grid[:, w] = ord("\n")
        # decoded straight from the grid's memory (no bytes copy), less the last newline
        return str((codecs.utf_16_le_decode if narrow else codecs.utf_32_le_decode)(flat[:-1].data)[0])

    def changed_spans(self, previous: "Frame | None") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Rows that differ from ``previous`` and, per row, the changed span [x0, x1)."""
        if previous is None or previous.chars.shape != self.chars.shape:
            rows = np.arange(self.height)
            return rows, np.zeros(self.height, dtype=int), np.full(self.height, self.width)
        if self.width == 0:  # a hidden view (0 columns): nothing can differ (argmax needs a column)
            empty = np.zeros(0, dtype=int)
            return empty, empty, empty
        changed = (self.chars != previous.chars) | (self.colours != previous.colours)
        rows = np.flatnonzero(changed.any(axis=1))
        sub = changed[rows]
        x0 = sub.argmax(axis=1)
        x1 = self.width - sub[:, ::-1].argmax(axis=1)
        return rows, x0, x1


def empty_frame(width: int, height: int) -> Frame:
    return Frame(np.full((height, width), 0x20, dtype=np.uint32), np.zeros((height, width), dtype=np.uint8))


# -- ASCII fallback ----------------------------------------------------------------------
@lru_cache(maxsize=1)
def _ascii_table() -> np.ndarray:
    """Braille pattern (0..255) -> the ASCII character closest to its dots' direction.

    Built once, when ASCII is first drawn (256 patterns; not at import: the app's start
    draws braille): the principal axis of the lit dots picks - / | \\, a blob
    gives + or #, a lone dot ' or .
    """
    table = np.full(256, ord(" "), dtype=np.uint32)
    for code in range(1, 256):
        rows, cols = np.nonzero(np.bitwise_and(code, BRAILLE_WEIGHTS))
        n = len(rows)
        if n == 1:
            ch = "'" if rows[0] <= 1 else "."
        elif n >= 6:
            ch = "#"
        else:
            x, y = cols - cols.mean(), rows - rows.mean()  # dots are square: no rescaling
            vx, vy, cxy = (x * x).mean(), (y * y).mean(), (x * y).mean()
            spread = math.hypot(vx - vy, 2 * cxy)
            major, minor = (vx + vy + spread) / 2, (vx + vy - spread) / 2
            angle = math.degrees(0.5 * math.atan2(2 * cxy, vx - vy))  # y grows downwards
            if minor > 0.5 * major:
                ch = "+"
            elif abs(angle) < 25:
                ch = "_" if rows.min() == 3 else "-"
            elif abs(angle) > 65:
                ch = "|"
            else:
                ch = "\\" if angle > 0 else "/"
        table[code] = ord(ch)
    return table


# -- rasterizing -------------------------------------------------------------------------
def _clip(a: np.ndarray, b: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Liang-Barsky on all segments at once against [0, hi]; returns clipped a, b and kept.
    A segment with an end not a finite number has no place on the canvas: not kept (the
    sampling would turn NaN into an index far outside its tables)."""
    d = b - a
    t0 = np.zeros(len(a))
    t1 = np.ones(len(a))
    keep = np.isfinite(a).all(axis=1) & np.isfinite(b).all(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        for axis in (0, 1):
            for p, q in ((-d[:, axis], a[:, axis]), (d[:, axis], hi[axis] - a[:, axis])):
                parallel = p == 0
                keep &= ~(parallel & (q < 0))
                r = q / p
                t0 = np.where(p < 0, np.maximum(t0, r), t0)
                t1 = np.where(p > 0, np.minimum(t1, r), t1)
        keep &= t0 <= t1
        return a + t0[:, None] * d, a + t1[:, None] * d, keep


class _Canvas:
    """What every frame of one view state on one w x h canvas uses, made once and kept (a
    motion's frames share it; a frame finds it with one lookup, ``_canvas``): ``_to_dots``'
    maps, the world -> dot projection (``_projection``) with its offset repeated (x, y, x, y
    ...) for the flattened products of the points, the dot rows' bits (``_row_bits``) and
    the samples' t table (``_fractions``)."""

    __slots__ = ("fractions", "maps", "offsets", "past_row", "project", "row_bits")
    maps: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]
    project: np.ndarray
    offsets: np.ndarray
    row_bits: np.ndarray
    fractions: np.ndarray
    past_row: np.ndarray

    def __init__(self, view: ViewTransform, w: int, h: int, dot_aspect: float) -> None:
        self.maps = _make_dot_maps(view, 2 * w, 4 * h, dot_aspect)
        self.project, offset = _projection(self.maps)
        self.offsets = np.tile(offset, 1024)
        self.row_bits = _row_bits(w, h)
        self.fractions, self.past_row = _fractions(max(2 * w, 4 * h))

    def offsets_for(self, n_points: int) -> np.ndarray:
        """The offset repeated for the flattened products of ``n_points`` points (made longer
        for a scene with more points than any before)."""
        if len(self.offsets) < 2 * n_points:
            self.offsets = np.tile(self.offsets[:2], n_points)
        return self.offsets[:2 * n_points]


_CANVASES: dict[tuple[bytes, float, int, int, float], _Canvas] = {}


def _canvas(view: ViewTransform, w: int, h: int, dot_aspect: float) -> _Canvas:
    """The kept ``_Canvas`` of this view state and w x h canvas (a few: the app, a hardcopy,
    a bench)."""
    assert view.pivot is not None and view.half_extent is not None
    key = (view.rotation.tobytes() + view.pan.tobytes() + view.pivot.tobytes() + view.half_extent.tobytes(),
           view.scale, w, h, dot_aspect)
    found = _CANVASES.get(key)
    if found is None:
        if len(_CANVASES) >= 8:
            _CANVASES.pop(next(iter(_CANVASES)))
        found = _CANVASES[key] = _Canvas(view, w, h, dot_aspect)
    return found


def _to_dots(view: ViewTransform, wd: int, hd: int, dot_aspect: float
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The view's affine map and the view-mm -> dot map (to_dots, centre) for a canvas of
    wd x hd dots (2 x 4 a cell), kept with its ``_canvas``."""
    return _canvas(view, wd // 2, hd // 4, dot_aspect).maps


def _projection(maps: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """World -> continuous dot coordinates as one (3, 2) product and an offset."""
    a_mat, b_vec, to_dots, centre = maps
    return a_mat[:2].T @ to_dots.T, b_vec[:2] @ to_dots.T + centre


def _make_dot_maps(view: ViewTransform, wd: int, hd: int, dot_aspect: float
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    a_mat, b_vec = view.affine()
    half = view.half_extent
    assert half is not None
    ppm = min(wd / (2 * half[0]), hd * dot_aspect / (2 * half[1]))
    to_dots = np.array([[ppm, 0.0], [0.0, -ppm / dot_aspect]])
    return a_mat, b_vec, to_dots, np.array([wd / 2, hd / 2])


def _samples(segs: np.ndarray, prio: np.ndarray, maps: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
             w: int, h: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The dots that world segments (S, 2, 3) light: per sample its cell (flat index), its
    bit in the packed bit map (``_row_bits``) and the priority of its segment, in drawing order."""
    if len(segs) == 0:
        return _dot_samples(np.zeros((0, 2, 2)), prio, w, h)
    project, offset = _projection(maps)   # world -> view mm -> dots, every endpoint in one product
    return _dot_samples((segs.reshape(-1, 3) @ project + offset).reshape(-1, 2, 2), prio, w, h)


def _dot_samples(pts: np.ndarray, prio: np.ndarray, w: int, h: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``_samples`` of segments already in continuous dot coordinates (S, 2, 2)."""
    per = np.empty((5, len(pts)))
    per[1:] = pts.reshape(-1, 4).T
    return _end_samples(per, prio, w, h, _row_bits(w, h), *_fractions(max(2 * w, 4 * h)))


def _end_samples(per: np.ndarray, prio: np.ndarray, w: int, h: int, row_bits: np.ndarray,
                 fractions: np.ndarray, past_row: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``_dot_samples`` of the segments' ends in rows 1-4 of ``per`` (first x, first y, last
    x, last y; row 0 free, every row overwritten): every pass below runs on contiguous rows
    (a reduction or an op along an axis of 2 costs several times more). The third result is
    ``prio`` (a value per segment) per sample. The tables: ``_row_bits(w, h)`` and
    ``_fractions`` of at least the canvas's longest side in dots."""
    wd, hd = 2 * w, 4 * h
    if not per.shape[1]:
        return _NO_SAMPLES
    # rows: the steps, start (2), direction (2). The ufuncs' own reductions, the arrays' own
    # methods, arguments by place and numpy operands (no keyword parsing, no conversion of
    # a Python number): every call's own cost counts at this size, as every line's does
    ends = per[1:]
    x0, y0, x1, y1 = _MAX(ends, 1).tolist()
    clipped = not (_MIN(ends, None) >= 0.0 and max(x0, x1) <= wd - 1e-6 and max(y0, y1) <= hd - 1e-6)
    if clipped:
        a, b, keep = _clip(per[1:3].T, per[3:].T, np.array([wd - 1e-6, hd - 1e-6]))
        per = per[:, keep]
        if not per.shape[1]:
            return _NO_SAMPLES
        per[1:3] = a[keep].T
        per[3:] = (b[keep] - a[keep]).T
        prio = prio[keep]
        ends, direction = per[1:], per[3:]
    else:                                 # all inside (the usual frame): nothing to clip
        direction = per[3:]
        direction -= per[1:3]
    # samples per edge from its length in dots: consecutive samples <= 1 dot apart, at
    # t = k / max(steps, 1), k = 0 .. steps
    size = np.abs(direction)
    steps = np.maximum(size[0], size[1], out=per[0])   # (a ufunc call costs less than a reduction)
    _CEIL(steps, steps)
    whole = steps.astype(np.intp)         # whole steps (clipped or inside: at most the canvas)
    n = whole + _ONE
    past = _ACCUMULATE(n)
    # each sample's t looked up (no division): its segment's row of the table, less the
    # samples before it, plus the running count. Lookups whose places are in range by
    # construction take mode 'clip': for such places the same as 'wrap' (round 8) and 'raise'
    # (numpy's default), and the cheapest of the three (a clamp, not a loop or a check)
    at = past_row.take(whole, None, None, "clip")
    at -= past
    at = at.repeat(n)
    counting, total = _COUNTING[0], len(at)
    at += counting[:total] if len(counting) >= total else _counting(total)
    t = fractions.take(at, None, None, "clip")
    # the four rows repeated to their samples in one call (contiguous rows: no strided
    # passes), then every pass in place in that copy
    each = ends.repeat(n, 1)
    xy = each[2:]
    xy *= t
    xy += each[:2]
    dots = xy.astype(np.int32)      # (a canvas of 2 ** 28 cells would need a 16 GB table)
    if clipped:      # inside, samples lie between two in-range ends: no clamping needed
        np.clip(dots[0], 0, wd - 1, out=dots[0])
        np.clip(dots[1], 0, hd - 1, out=dots[1])
    # a dot's bit: its row's (``_row_bits``) plus 4 x (its cell * 8 + 4 c + r)
    lit = row_bits.take(dots[1], None, None, "clip")
    column = dots[0]
    column <<= _TWO
    lit += column
    return lit >> _THREE, lit, prio.repeat(n)    # the cell: the bit's byte


_MAX = np.maximum.reduce
_CEIL = np.ceil
_ONE = np.ones((), dtype=np.intp)
_TWO = np.full((), 2, dtype=np.int32)
_THREE = np.full((), 3, dtype=np.intp)
_ACCUMULATE = np.add.accumulate
_MIN = np.minimum.reduce
_NO_SAMPLES = (np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp))
_COUNTING = [np.arange(4096, dtype=np.intp)]


def _counting(total: int) -> np.ndarray:
    """0, 1, ... total - 1 (a view of one kept array, grown when a frame needs more)."""
    if len(_COUNTING[0]) < total:
        _COUNTING[0] = np.arange(max(total, 2 * len(_COUNTING[0])), dtype=np.intp)
    return _COUNTING[0][:total]


_FRACTIONS: list[tuple[np.ndarray, np.ndarray]] = []


def _fractions(longest: int) -> tuple[np.ndarray, np.ndarray]:
    """Every sample's t of segments of up to ``longest`` steps: row s of the table holds
    k / max(s, 1) for k = 0 .. s (the same quotients of whole numbers the sampling made as
    floats, so the same t), and where row s + 1 starts. Kept, and grown for a bigger canvas."""
    if not _FRACTIONS or len(_FRACTIONS[0][1]) <= longest:
        s = np.arange(longest + 1)
        ends = np.cumsum(s + 1)                   # row s ends (row s + 1 starts) here
        row = np.repeat(s, s + 1)
        k = np.arange(int(ends[-1])) - (ends - (s + 1)).repeat(s + 1)
        _FRACTIONS[:] = [(k / np.maximum(row, 1).astype(float), ends)]
    return _FRACTIONS[0]


_ROW_BITS: dict[tuple[int, int], np.ndarray] = {}


def _row_bits(w: int, h: int) -> np.ndarray:
    """Per dot row y of a w x h canvas, the bit in the packed bit map of its dot in column 0:
    the dot in column x is bit ``(y >> 2) * 8 (w + 1) + (y & 3) + 4 x``, that is bit 4 c + r
    (c, r: its column and row in its cell) of byte ``cell = (y >> 2) (w + 1) + (x >> 1)``.
    One lookup in a table of 4 h places and a shift per sample (round 11: the earlier table
    of every dot, 8 bytes a dot, was 768 KB at 200x60 and a lookup spread over all of it);
    ``_PACKED_TO_BRAILLE`` turns the packed codes into braille codes.

    Cells are numbered in rows of w + 1 (``row * (w + 1) + column``): the last cell of each
    row, which no dot lights, is where the frame's text puts its newline (``_text_grid``)."""
    found = _ROW_BITS.get((w, h))
    if found is None:
        if len(_ROW_BITS) >= 8:
            _ROW_BITS.pop(next(iter(_ROW_BITS)))
        y = np.arange(4 * h)
        found = _ROW_BITS[(w, h)] = (y >> 2) * 8 * (w + 1) + (y & 3)
    return found


# the braille code (``BRAILLE_WEIGHTS``) of each packed code: bit 4 c + r is the dot in row r,
# column c of its cell
_PACKED_TO_BRAILLE = (((np.arange(256)[:, None] >> np.arange(8)) & 1) * BRAILLE_WEIGHTS.T.ravel()).sum(axis=1)


_LIT = np.True_    # (a numpy scalar: no Python bool converted at every frame)


def _dots_to_codes(lit: np.ndarray, n_cells: int) -> np.ndarray:
    """Packed codes per cell from the lit dots (their bits in the bit map, ``_row_bits``):
    each dot set in a bit map and the map packed, eight bits a cell (cheaper than an OR per
    dot). ``_PACKED_TO_BRAILLE`` maps a code to braille, the character tables include it."""
    bitmap = np.zeros(n_cells * 8, np.bool_)
    bitmap[lit] = _LIT
    codes: np.ndarray = np.packbits(bitmap, None, "little")
    return codes
_BACKGROUNDS: dict[tuple[int, bytes, int, int, bool, float], tuple[Scene, np.ndarray, np.ndarray]] = {}


def _background(scene: Scene, view: ViewTransform, w: int, h: int, back_faces: bool,
                dot_aspect: float, maps: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]
                ) -> tuple[np.ndarray, np.ndarray]:
    """The static scene's braille codes and colours per cell for this view and size (flat),
    rasterised once and kept. ``maps``: ``_to_dots`` of this view and size (its key)."""
    a_mat, b_vec, to_dots, _ = maps
    key = (id(scene), a_mat.tobytes() + b_vec.tobytes() + to_dots.tobytes(), w, h, back_faces, dot_aspect)
    found = _BACKGROUNDS.get(key)
    if found is not None and found[0] is scene:
        return found[1], found[2]
    segs, prio = scene.segments(view, back_faces)
    polys = len(prio) - len(scene.lines)
    cells, lit, painted = _samples(segs[:polys], scene.colours.take(prio[:polys] - 1), maps, w, h)
    codes = _dots_to_codes(lit, h * (w + 1))   # cells in rows of w + 1 (``_row_bits``)
    colours = np.zeros(h * (w + 1), dtype=np.uint8)
    colours[cells] = painted     # samples in priority order: the last wins
    if len(_BACKGROUNDS) >= 8:          # a few views and sizes (the app, a hardcopy, a bench)
        _BACKGROUNDS.pop(next(iter(_BACKGROUNDS)))
    _BACKGROUNDS[key] = (scene, codes, colours)
    return codes, colours


def _chars(codes: np.ndarray, ascii: bool) -> np.ndarray:
    """Character per packed code (``_dots_to_codes``), as UTF-16 units (every one lies below
    the surrogates): its braille pattern's in the U+2800 block (blank for none), or the ASCII
    stand-in.

    Two cells at a time where they pair up (a table of the 65536 pairs: half the lookups);
    ``codes`` contiguous (packed from a bit map, or taken from such codes)."""
    chars: np.ndarray
    if len(codes) % 2:
        chars = (_ascii_units() if ascii else _BRAILLE_TABLE).take(codes)
    else:
        chars = _pair_table(ascii).take(codes.view(_UNITS), None, None, "clip").view(_UNITS)  # (any two codes: a row)
    return chars


@lru_cache(maxsize=2)
def _pair_table(ascii: bool) -> np.ndarray:
    """The characters of two neighbouring codes (first + 256 * second) as one 4-byte word."""
    table = (_ascii_units() if ascii else _BRAILLE_TABLE).astype("<u4")
    # row: the second code, column: the first (a broadcast of the 256 x 256, not two gathers)
    both: np.ndarray = ((table[:, None] << np.uint32(16)) | table[None, :]).ravel()
    return both


@lru_cache(maxsize=1)
def _ascii_units() -> np.ndarray:
    """``_ascii_table`` by packed code (``_PACKED_TO_BRAILLE``), as UTF-16 units."""
    units: np.ndarray = _ascii_table().take(_PACKED_TO_BRAILLE).astype("<u2")
    return units


_UNITS = np.dtype("<u2")   # a UTF-16 unit (a dtype made once: a string is parsed at every use)
_NEWLINE = np.full((), ord("\n"), dtype=_UNITS)

# the character of each packed code: U+2800 + its braille code, blank for none (UTF-16 units)
_BRAILLE_TABLE = np.where(_PACKED_TO_BRAILLE > 0, BRAILLE_BASE + _PACKED_TO_BRAILLE, 0x20).astype("<u2")


def _text_grid(codes: np.ndarray, ascii: bool, w: int) -> np.ndarray:
    """The characters of the codes of a frame's cells in rows of w + 1 (``_row_bits``), the
    last cell of every row a newline: the frame's text as UTF-16 units (``Frame.text``)."""
    grid = _chars(codes, ascii)
    grid[w::w + 1] = _NEWLINE
    return grid


_STATIC_CHARS: dict[tuple[int, bool], tuple[np.ndarray, np.ndarray]] = {}


def _static_chars(scene: Scene, codes: np.ndarray, ascii: bool, w: int) -> np.ndarray:
    """The background's ``_text_grid``, kept with the codes array it was made from."""
    found = _STATIC_CHARS.get((id(codes), ascii))
    if found is not None and found[0] is codes:
        return found[1]
    if len(_STATIC_CHARS) >= 16:
        _STATIC_CHARS.pop(next(iter(_STATIC_CHARS)))
    chars = _text_grid(codes, ascii, w)
    _STATIC_CHARS[(id(codes), ascii)] = (codes, chars)
    return chars


def rasterize(
    scene: Scene,
    view: ViewTransform,
    width_cells: int,
    height_cells: int,
    back_faces: bool = True,
    axes: bool = False,
    ascii: bool = False,
    dot_aspect: float = 1.0,
) -> Frame:
    """Draw ``scene`` into a ``width_cells`` x ``height_cells`` frame.

    ``dot_aspect`` is a braille dot's height over its width (1.0 for the usual 1:2 cell);
    the same dot grid backs the ASCII fallback so both keep the same proportions. The
    scene's ``background`` (the static cell) is rasterised once per view and size and
    each frame draws only the scene's own items over a copy of it.
    """
    w, h = max(int(width_cells), 0), max(int(height_cells), 0)
    if w == 0 or h == 0:
        return empty_frame(w, h)
    canvas = _canvas(view, w, h, dot_aspect)
    # each segment's colour repeated to its samples (not each sample's priority looked up)
    per, paint = _scene_dots(scene, view, back_faces, axes, canvas)
    cells, lit, painted = _end_samples(per, paint, w, h, canvas.row_bits, canvas.fractions, canvas.past_row)
    colours: np.ndarray
    # cells in rows of w + 1, the last a newline: the characters are the text's own units
    n_cells = h * (w + 1)
    codes = _dots_to_codes(lit, n_cells)
    if scene.background is None:
        colours = np.zeros(n_cells, np.uint8)
        grid = _text_grid(codes, ascii, w)
    else:
        static_codes, static_colours = _background(scene.background, view, w, h, back_faces, dot_aspect, canvas.maps)
        codes |= static_codes
        colours = static_colours.copy()
        # only the cells this frame touched change character: the rest are the background's
        grid = _static_chars(scene.background, static_codes, ascii, w).copy()
        grid[cells] = _chars(codes.take(cells), ascii)
    colours[cells] = painted     # samples come in priority order: the later item wins
    chars = grid.reshape(h, w + 1)[:, :w]
    colours = colours.reshape(h, w + 1)[:, :w]

    if axes:
        a_mat, b_vec, to_dots, centre = canvas.maps
        _label_axes(chars, colours, a_mat, b_vec, to_dots, centre)
    return Frame(chars, colours, grid)


def _scene_dots(scene: Scene, view: ViewTransform, back_faces: bool, axes: bool, canvas: _Canvas
                ) -> tuple[np.ndarray, np.ndarray]:
    """The scene's segments' ends in dot coordinates, as ``_end_samples`` takes them (rows
    1-4 of five), and their colours: each point projected once, then paired into segments."""
    points = scene._drawn_points[axes]
    if back_faces:        # every edge: where its ends lie and its colour kept with the scene
        at, paint = scene._every_end_at[axes], scene._every_paint[axes]
    else:
        pairs, prio = scene.drawn_pairs(view, back_faces, axes)
        at, paint = _end_at(pairs), scene._palette_with_axes.take(prio)
    # the offset added to the flat (x, y, x, y ...) products in one contiguous pass (the same
    # sums as ``points @ project + offset``), then one take (a fancy index costs several times more)
    flat = (points @ canvas.project).ravel()
    flat += canvas.offsets_for(len(points))
    per: np.ndarray = flat.take(at, None, None, "clip")   # (every place a point's coordinate: in range)
    return per, paint


def _end_at(pairs: np.ndarray) -> np.ndarray:
    """Where the ends' coordinates of segments ``pairs`` (S, 2) lie in the flattened (P, 2)
    points, as rows 1-4 (first x, first y, last x, last y) of the five ``_end_samples`` takes
    (row 0 takes the first coordinate: room for the sampling's own row, no copy)."""
    at = np.zeros((5, len(pairs)), dtype=np.intp)   # row 0: any valid place
    at[1::2] = 2 * pairs.T
    at[2::2] = at[1::2] + 1
    return at


def _label_axes(chars: np.ndarray, colours: np.ndarray, a_mat: np.ndarray, b_vec: np.ndarray,
                to_dots: np.ndarray, centre: np.ndarray) -> None:
    """Write X, Y, Z just beyond the tips of the drawn WCS axes."""
    h, w = chars.shape
    ends = np.array([[0.0, 0, 0], *(np.eye(3) * AXIS_LENGTH * 1.15)])
    dots = (ends @ a_mat[:2].T + b_vec[:2]) @ to_dots.T + centre
    origin_cell = dots[0] / [2, 4]
    for i, name in enumerate("XYZ"):
        cell = dots[i + 1] / [2, 4]
        if np.abs(cell - origin_cell).max() < 1.0:
            cell = origin_cell + [1.0, 1.0]  # axis points at the viewer: label beside the origin
        col, row = int(math.floor(cell[0])), int(math.floor(cell[1]))
        if 0 <= row < h and 0 <= col < w:
            chars[row, col] = ord(name)
            colours[row, col] = AXES_COLOUR


_AXES_POINTS = frame_lines((0.0, 0.0, 0.0)).reshape(-1, 3)  # the WCS axes (``rasterize(axes=True)``)
