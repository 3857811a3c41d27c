"""Entity geometry of an IGES model: model-space points of each top-level entity.

Top-level entities are the independent (or only logically dependent) geometric ones; their
physically dependent children (the curves of a composite, the boundary of a trimmed surface,
the edges of a B-rep face) are reached through them, so parameter-space curves (uv curves of
142/508) are never mistaken for model-space points. Curves are sampled (arcs at 64 points a
turn plus their axis extremes); spline curves and surfaces are evaluated, not just their
control points, so the envelope is not inflated by the control polygon.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from valterm.core.cad.iges_entities import NON_GEOMETRY, Entity, EntityModel

SAMPLES_PER_TURN = 64
SURFACE_GRID = 16

# A surface's evaluator: parameter arrays u, v -> (n, 3) points in the surface's own space.
Surface = Callable[[np.ndarray, np.ndarray], np.ndarray]


def _apply(m: np.ndarray, pts: np.ndarray) -> np.ndarray:
    return pts @ m[:3, :3].T + m[:3, 3] if len(pts) else pts


def _angles(a0: float, a1: float, full: bool, extremes: np.ndarray | None = None) -> np.ndarray:
    """Counter-clockwise angles from a0 to a1 (a full turn when ``full``) plus the extreme angles.

    ``extremes`` are angles (mod 2 pi) where a coordinate of the curve peaks; those inside the
    sweep are added so the envelope reaches the true extent, not a chord short of it.
    """
    sweep = 2 * math.pi if full else (a1 - a0) % (2 * math.pi)
    n = max(2, math.ceil(sweep / (2 * math.pi) * SAMPLES_PER_TURN))
    ts = a0 + np.linspace(0.0, sweep, n + 1)
    axes = np.arange(4) * (math.pi / 2)
    crit = axes if extremes is None else np.concatenate([axes, extremes])
    rel = (crit - a0) % (2 * math.pi)
    return np.concatenate([ts, a0 + rel[rel <= sweep]])


def _peaks(matrix: np.ndarray, a: float, b: float) -> np.ndarray:
    """Angles where each model axis peaks on ``(a cos t, b sin t)`` mapped by ``matrix``."""
    base = np.arctan2(matrix[:3, 1] * b, matrix[:3, 0] * a)
    return np.concatenate([base, base + math.pi])


def bspline_basis(knots: np.ndarray, degree: int, t: np.ndarray) -> np.ndarray:
    """(len(t), len(knots)-degree-1) B-spline basis values (Cox-de Boor, all parameters at once)."""
    k = np.asarray(knots, dtype=float)
    lo, hi = k[degree], k[len(k) - degree - 1]
    t = np.clip(np.asarray(t, dtype=float), lo, hi)
    n = ((k[:-1] <= t[:, None]) & (t[:, None] < k[1:])).astype(float)
    at_end = t >= hi
    if at_end.any():
        last = int(np.searchsorted(k, hi, side="left")) - 1   # last non-empty span ending at hi
        n[at_end] = 0.0
        n[at_end, max(last, 0)] = 1.0
    for p in range(1, degree + 1):
        d1 = k[p:-1] - k[:-p - 1]
        d2 = k[p + 1:] - k[1:-p]
        with np.errstate(divide="ignore", invalid="ignore"):
            a = np.where(d1 > 0, (t[:, None] - k[:-p - 1]) / np.where(d1 > 0, d1, 1), 0.0)
            b = np.where(d2 > 0, (k[p + 1:] - t[:, None]) / np.where(d2 > 0, d2, 1), 0.0)
        n = a * n[:, :-1] + b * n[:, 1:]
    return n


class Walker:
    """Visits the entities of an ``IgesModel`` and returns the points of each top-level one."""

    def __init__(self, model: EntityModel) -> None:
        self.m = model
        self.cache: dict[int, np.ndarray] = {}
        self.active: set[int] = set()
        self.ignored: dict[int, int] = {}
        self.handlers: dict[int, Callable[[Entity], np.ndarray]] = {
            100: self.arc, 102: self.composite, 104: self.conic, 106: self.copious, 108: self.plane,
            110: self.line, 112: self.spline112, 116: self.point, 118: self.ruled, 120: self.revolution,
            122: self.tabulated, 126: self.spline126, 128: self.surface128, 141: self.boundary141,
            142: self.curve_on_surface, 143: self.bounded_surface, 144: self.trimmed,
            186: self.msbo, 308: self.subfigure, 408: self.instance, 502: self.vertex_list,
            504: self.edge_list, 508: self.loop, 510: self.face, 514: self.shell,
        }

    # ------------------------------------------------------------------ driver
    def run(self) -> dict[int, np.ndarray]:
        ents = self.m.entities
        in_definitions: set[int] = set()
        for e in ents.values():
            if e.type == 308:
                n = self.m.integer(e, 3)
                in_definitions.update(abs(self.m.integer(e, 4 + i)) for i in range(n))
        roots = [e for e in ents.values()
                 if e.type not in NON_GEOMETRY and e.subordinate in (0, 2) and e.use not in (1, 2, 5)
                 and e.seq not in in_definitions]
        out = {e.seq: p for e in roots if len(p := self.visit(e))}
        if not out:
            # some writers mark everything dependent: fall back to every model-space entity
            loose = [e for e in ents.values() if e.type not in NON_GEOMETRY and e.use != 5 and e.type in self.handlers]
            out = {e.seq: p for e in loose if len(p := self.visit(e))}
            if out:
                self.m.warnings.append(f"{self.m.path.name}: no independent geometry; read every entity instead")
        if self.ignored:
            kinds = ", ".join(f"{t} (x{n})" for t, n in sorted(self.ignored.items()))
            self.m.warnings.append(f"{self.m.path.name}: ignored entity types without a point-set reading: {kinds}")
        factor = self.m.mm_per_unit / self.m.scale
        return {s: p * factor for s, p in out.items()}

    def visit(self, ent: Entity) -> np.ndarray:
        """Model-space points (file units) of one entity, its own matrix applied."""
        if ent.seq in self.cache:
            return self.cache[ent.seq]
        if ent.seq in self.active:
            raise self.m.error(ent.line, f"entity {ent.type} (D{ent.seq}) refers back to itself")
        handler = self.handlers.get(ent.type)
        if handler is None:
            self.ignored[ent.type] = self.ignored.get(ent.type, 0) + 1
            pts = np.zeros((0, 3))
        else:
            self.active.add(ent.seq)
            try:
                pts = np.asarray(handler(ent), dtype=float).reshape(-1, 3)
            finally:
                self.active.discard(ent.seq)
            pts = _apply(self.m.matrix(ent), pts)
        self.cache[ent.seq] = pts
        return pts

    def ref(self, ent: Entity, i: int) -> np.ndarray:
        target = self.m.pointer(ent, i, optional=True)
        return self.visit(target) if target is not None else np.zeros((0, 3))

    # ------------------------------------------------------------------ points and curves
    def point(self, e: Entity) -> np.ndarray:
        return self.m.nums(e, 1, 3)

    def line(self, e: Entity) -> np.ndarray:
        return self.m.nums(e, 1, 6)

    def arc(self, e: Entity) -> np.ndarray:
        zt, cx, cy, sx, sy, ex, ey = self.m.nums(e, 1, 7)
        r = math.hypot(sx - cx, sy - cy)
        a0 = math.atan2(sy - cy, sx - cx)
        a1 = math.atan2(ey - cy, ex - cx)
        full = math.isclose(sx, ex, abs_tol=1e-12 * (1 + r)) and math.isclose(sy, ey, abs_tol=1e-12 * (1 + r))
        ts = _angles(a0, a1, full, _peaks(self.m.matrix(e), r, r))
        pts = np.stack([cx + r * np.cos(ts), cy + r * np.sin(ts), np.full_like(ts, zt)], 1)
        return np.vstack([pts, [[ex, ey, zt]]])

    def conic(self, e: Entity) -> np.ndarray:
        a, b, c, d, ee, f, zt, x1, y1, x2, y2 = self.m.nums(e, 1, 11)
        scale = max(abs(a), abs(b), abs(c), abs(d), abs(ee), abs(f)) or 1.0
        ends = np.array([[x1, y1, zt], [x2, y2, zt]])

        def small(v: float) -> bool:
            return abs(v) <= 1e-12 * scale

        if small(b) and small(d) and small(ee) and a * c > 0 and -f / a > 0:       # ellipse
            ra, rb = math.sqrt(-f / a), math.sqrt(-f / c)
            t0, t1 = math.atan2(y1 / rb, x1 / ra), math.atan2(y2 / rb, x2 / ra)
            ts = _angles(t0, t1, math.isclose(x1, x2) and math.isclose(y1, y2), _peaks(self.m.matrix(e), ra, rb))
            pts = np.stack([ra * np.cos(ts), rb * np.sin(ts), np.full_like(ts, zt)], 1)
        elif small(b) and small(d) and small(ee) and a * c < 0 and not small(f):    # hyperbola
            u = np.linspace(0.0, 1.0, 33)
            if -f / a > 0:
                ra, rb = math.sqrt(-f / a), math.sqrt(f / c)
                s = np.asinh(y1 / rb) + u * (np.asinh(y2 / rb) - np.asinh(y1 / rb))
                pts = np.stack([math.copysign(ra, x1) * np.cosh(s), rb * np.sinh(s), np.full_like(s, zt)], 1)
            else:
                ra, rb = math.sqrt(f / a), math.sqrt(-f / c)
                s = np.asinh(x1 / ra) + u * (np.asinh(x2 / ra) - np.asinh(x1 / ra))
                pts = np.stack([ra * np.sinh(s), math.copysign(rb, y1) * np.cosh(s), np.full_like(s, zt)], 1)
        elif small(b) and small(c) and small(d) and not small(a) and not small(ee):  # y = -A x^2 / E
            x = np.linspace(x1, x2, 33)
            pts = np.stack([x, -a * x * x / ee, np.full_like(x, zt)], 1)
        elif small(b) and small(a) and small(ee) and not small(c) and not small(d):  # x = -C y^2 / D
            y = np.linspace(y1, y2, 33)
            pts = np.stack([-c * y * y / d, y, np.full_like(y, zt)], 1)
        else:
            self.m.warnings.append(f"{self.m.path.name}:{e.line}: conic (D{e.seq}) not in standard position; "
                                   "only its end points used")
            return ends
        return np.vstack([pts, ends])

    def copious(self, e: Entity) -> np.ndarray:
        if 20 <= e.form <= 40:
            return np.zeros((0, 3))  # centre lines, section and witness lines: drafting, not the part
        ip, n = self.m.integer(e, 1), self.m.integer(e, 2)
        if ip == 1:
            zt = self.m.num(e, 3)
            xy = self.m.nums(e, 4, 2 * n).reshape(n, 2)
            return np.column_stack([xy, np.full(n, zt)])
        if ip in (2, 3):
            width = 3 * ip - 3
            return self.m.nums(e, 3, width * n).reshape(n, width)[:, :3]
        raise self.m.error(e.param_lines[0], f"copious data (D{e.seq}): interpretation flag {ip} is not 1, 2 or 3")

    def spline112(self, e: Entity) -> np.ndarray:
        n = self.m.integer(e, 4)
        if n < 1:
            raise self.m.error(e.param_lines[3], f"parametric spline (D{e.seq}): {n} segments")
        t = self.m.nums(e, 5, n + 1)
        coef = self.m.nums(e, 6 + n, 12 * n).reshape(n, 3, 4)      # per segment: x, y, z cubics
        s = np.linspace(0.0, 1.0, 9)[None, :] * np.diff(t)[:, None]  # (n, 9)
        powers = np.stack([np.ones_like(s), s, s * s, s ** 3], -1)   # (n, 9, 4)
        pts: np.ndarray = np.einsum("nsk,nck->nsc", powers, coef)  # numpy types einsum as Any
        return pts.reshape(-1, 3)

    def spline126(self, e: Entity) -> np.ndarray:
        k, m = self.m.integer(e, 1), self.m.integer(e, 2)
        if m < 1 or k < m:
            raise self.m.error(e.param_lines[0],
                               f"rational B-spline curve (D{e.seq}): bad upper index {k} or degree {m}")
        polynomial = self.m.integer(e, 5, 0) == 1
        nk = k + m + 2
        knots = self.m.nums(e, 7, nk)
        w = self.m.nums(e, 7 + nk, k + 1)
        ctrl = self.m.nums(e, 8 + nk + k, 3 * (k + 1)).reshape(k + 1, 3)
        v0 = self.m.num(e, 11 + nk + 4 * k, float(knots[m]))        # parameter range after the points
        v1 = self.m.num(e, 12 + nk + 4 * k, float(knots[-m - 1]))
        if np.any(np.diff(knots) < 0):
            raise self.m.error(e.param_lines[6], f"rational B-spline curve (D{e.seq}): knots decrease")
        if polynomial or np.all(w == w[0]):
            w = np.ones(k + 1)
        if np.any(w <= 0):
            return ctrl  # negative weights: no convex-hull guarantee either way; the control polygon will do
        t = np.linspace(v0, v1, min(2000, max(SAMPLES_PER_TURN, 8 * (k + 1))))
        basis = bspline_basis(knots, m, t) * w
        pts: np.ndarray = (basis @ ctrl) / basis.sum(axis=1, keepdims=True)
        return pts

    def _surface128(self, e: Entity) -> tuple[Surface, tuple[float, float, float, float]]:
        """An evaluator (u, v arrays -> points, surface's own space) and the parameter ranges."""
        k1, k2, m1, m2 = (self.m.integer(e, i) for i in (1, 2, 3, 4))
        if min(k1, k2) < 0 or min(m1, m2) < 1:
            raise self.m.error(e.param_lines[0],
                               f"B-spline surface (D{e.seq}): bad indices {k1}, {k2}, degrees {m1}, {m2}")
        n1, n2 = k1 + m1 + 2, k2 + m2 + 2
        cnt = (k1 + 1) * (k2 + 1)
        s_knots = self.m.nums(e, 10, n1)
        t_knots = self.m.nums(e, 10 + n1, n2)
        w = self.m.nums(e, 10 + n1 + n2, cnt).reshape(k2 + 1, k1 + 1).T
        ctrl = self.m.nums(e, 10 + n1 + n2 + cnt, 3 * cnt).reshape(k2 + 1, k1 + 1, 3).transpose(1, 0, 2)
        base = 10 + n1 + n2 + 4 * cnt
        u0, u1, v0, v1 = (self.m.num(e, base + i, d) for i, d in
                          enumerate((s_knots[m1], s_knots[-m1 - 1], t_knots[m2], t_knots[-m2 - 1])))
        if self.m.integer(e, 7, 0) == 1 or np.any(w <= 0):
            w = np.ones_like(w)

        def evaluate(u: np.ndarray, v: np.ndarray) -> np.ndarray:
            bu = bspline_basis(s_knots, m1, u)
            bv = bspline_basis(t_knots, m2, v)
            num = np.einsum("pi,pj,ij,ijc->pc", bu, bv, w, ctrl)
            den = np.einsum("pi,pj,ij->p", bu, bv, w)
            pts: np.ndarray = num / den[:, None]
            return pts

        return evaluate, (u0, u1, v0, v1)

    def surface128(self, e: Entity) -> np.ndarray:
        evaluate, (u0, u1, v0, v1) = self._surface128(e)
        u, v = np.meshgrid(np.linspace(u0, u1, SURFACE_GRID), np.linspace(v0, v1, SURFACE_GRID))
        return evaluate(u.ravel(), v.ravel())

    # ------------------------------------------------------------------ composites and surfaces
    def composite(self, e: Entity) -> np.ndarray:
        n = self.m.integer(e, 1)
        return np.vstack([np.zeros((0, 3))] + [self.ref(e, 2 + i) for i in range(n)])

    def plane(self, e: Entity) -> np.ndarray:
        # bounded plane: its bounding curve; an unbounded one has no extent to envelop
        return self.ref(e, 5) if self.m.integer(e, 5, 0) else np.zeros((0, 3))

    def ruled(self, e: Entity) -> np.ndarray:
        return np.vstack([self.ref(e, 1), self.ref(e, 2)])

    def revolution(self, e: Entity) -> np.ndarray:
        axis = self.ref(e, 1)
        curve = self.ref(e, 2)
        sa, ta = self.m.num(e, 3, 0.0), self.m.num(e, 4, 2 * math.pi)
        if len(axis) < 2 or not len(curve):
            return curve
        p, d = axis[0], axis[1] - axis[0]
        d = d / (np.linalg.norm(d) or 1.0)
        ts = _angles(sa, ta, math.isclose((ta - sa) % (2 * math.pi), 0.0) and ta != sa)
        rel = curve - p
        along = rel @ d
        radial = rel - along[:, None] * d
        cross = np.cross(d, radial)
        # Rodrigues: every curve point at every angle
        pts: np.ndarray = ((p + along[:, None] * d)[None] + np.cos(ts)[:, None, None] * radial[None]
                           + np.sin(ts)[:, None, None] * cross[None])
        return pts.reshape(-1, 3)

    def tabulated(self, e: Entity) -> np.ndarray:
        curve = self.ref(e, 1)
        end = self.m.nums(e, 2, 3)
        return np.vstack([curve, curve + (end - curve[0])]) if len(curve) else curve

    def curve_on_surface(self, e: Entity) -> np.ndarray:
        model = self.ref(e, 4)
        if len(model):
            return model
        surface = self.m.pointer(e, 2, optional=True)
        uv = self.ref(e, 3)
        if surface is not None and surface.type == 128 and len(uv):
            evaluate, _ = self._surface128(surface)
            return _apply(self.m.matrix(surface), evaluate(uv[:, 0], uv[:, 1]))
        return np.zeros((0, 3))

    def trimmed(self, e: Entity) -> np.ndarray:
        surface = self.m.pointer(e, 1)
        assert surface is not None
        if self.m.integer(e, 2, 0) == 0:
            return self.visit(surface)  # outer boundary = the surface's own
        boundary = self.ref(e, 4)
        outer = self.m.pointer(e, 4)
        extra = self._inside_uv(surface, outer) if outer is not None and surface.type == 128 else np.zeros((0, 3))
        return np.vstack([boundary, extra])

    def _inside_uv(self, surface: Entity, outer: Entity) -> np.ndarray:
        """Surface points inside a uv trimming curve, so a curved patch's bulge is enveloped too."""
        uv_ent = self.m.pointer(outer, 3, optional=True)
        if uv_ent is None:
            return np.zeros((0, 3))
        poly = self.visit(uv_ent)[:, :2]
        if len(poly) < 3:
            return np.zeros((0, 3))
        evaluate, _ = self._surface128(surface)
        u, v = np.meshgrid(np.linspace(poly[:, 0].min(), poly[:, 0].max(), SURFACE_GRID),
                           np.linspace(poly[:, 1].min(), poly[:, 1].max(), SURFACE_GRID))
        q = np.stack([u.ravel(), v.ravel()], 1)
        a, b = poly, np.roll(poly, -1, axis=0)
        # even-odd rule, all grid points against all edges at once
        crosses = ((a[None, :, 1] > q[:, None, 1]) != (b[None, :, 1] > q[:, None, 1])) & (
            q[:, None, 0] < a[None, :, 0] + (q[:, None, 1] - a[None, :, 1]) * (b[None, :, 0] - a[None, :, 0])
            / np.where(b[None, :, 1] == a[None, :, 1], 1.0, b[None, :, 1] - a[None, :, 1]))
        inside = q[np.count_nonzero(crosses, axis=1) % 2 == 1]
        if not len(inside):
            return np.zeros((0, 3))
        return _apply(self.m.matrix(surface), evaluate(inside[:, 0], inside[:, 1]))

    def boundary141(self, e: Entity) -> np.ndarray:
        n = self.m.integer(e, 4)
        pts, i = [np.zeros((0, 3))], 5
        for _ in range(n):
            pts.append(self.ref(e, i))
            k = self.m.integer(e, i + 2)
            i += 3 + k
        return np.vstack(pts)

    def bounded_surface(self, e: Entity) -> np.ndarray:
        n = self.m.integer(e, 3)
        return np.vstack([np.zeros((0, 3))] + [self.ref(e, 4 + i) for i in range(n)])

    # ------------------------------------------------------------------ subfigures
    def subfigure(self, e: Entity) -> np.ndarray:
        n = self.m.integer(e, 3)
        return np.vstack([np.zeros((0, 3))] + [self.ref(e, 4 + i) for i in range(n)])

    def instance(self, e: Entity) -> np.ndarray:
        pts = self.ref(e, 1)
        x, y, z = (self.m.num(e, i, 0.0) for i in (2, 3, 4))
        s = self.m.num(e, 5, 1.0)
        placed: np.ndarray = pts * s + np.array([x, y, z])
        return placed

    # ------------------------------------------------------------------ B-rep
    def vertex_list(self, e: Entity) -> np.ndarray:
        n = self.m.integer(e, 1)
        return self.m.nums(e, 2, 3 * n).reshape(n, 3)

    def edge_list(self, e: Entity) -> np.ndarray:
        n = self.m.integer(e, 1)
        return np.vstack([np.zeros((0, 3))] + [self.ref(e, 2 + 5 * i) for i in range(n)])

    def loop(self, e: Entity) -> np.ndarray:
        n = self.m.integer(e, 1)
        pts, i = [np.zeros((0, 3))], 2
        for _ in range(n):
            kind = self.m.integer(e, i)
            lst = self.m.pointer(e, i + 1)
            ndx = self.m.integer(e, i + 2)
            k = self.m.integer(e, i + 4)
            assert lst is not None
            if kind == 0 and lst.type == 504:
                if not 1 <= ndx <= self.m.integer(lst, 1):
                    raise self.m.error(e.param_lines[i + 1], f"loop (D{e.seq}): edge {ndx} not in edge list D{lst.seq}")
                curve = self.m.pointer(lst, 2 + 5 * (ndx - 1))
                assert curve is not None
                pts.append(_apply(self.m.matrix(lst), self.visit(curve)))
            elif lst.type == 502:
                pts.append(_apply(self.m.matrix(lst), self.vertex_list(lst)[ndx - 1: ndx]))
            i += 5 + 2 * k
        return np.vstack(pts)

    def face(self, e: Entity) -> np.ndarray:
        n = self.m.integer(e, 2)
        return np.vstack([np.zeros((0, 3))] + [self.ref(e, 4 + i) for i in range(n)])

    def shell(self, e: Entity) -> np.ndarray:
        n = self.m.integer(e, 1)
        return np.vstack([np.zeros((0, 3))] + [self.ref(e, 2 + 2 * i) for i in range(n)])

    def msbo(self, e: Entity) -> np.ndarray:
        return self.ref(e, 1)
