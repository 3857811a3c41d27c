"""The exact second opinion: python-fcl (GJK on convex polyhedra), same pairs as the 1985 check.

Each polyhedron becomes an ``fcl.Convex`` about its own centre, with every face wound
counter-clockwise seen from outside (fcl's convention; a setup file may wind either way).
A polyhedron that moves rigidly is not rebuilt: its rotation is recovered from three of its
vertices and set on the ``fcl.CollisionObject`` (``setRotation``/``setTranslation``
recompute the AABB), then the broad phase is ``update()``d. A polyhedron whose shape changed
(not a rigid move of the one we built) is rebuilt.

Broad phase: two ``fcl.DynamicAABBTreeCollisionManager`` (the moving polyhedra, the
stationary ones) collided against each other; the pairs of moving polyhedra (robot link
against robot link) are few and go straight to ``fcl.collide`` after a numpy box test.
Every query gets a fresh ``CollisionRequest``/``CollisionResult`` (fcl accumulates results).

Reports "collides" only, never "near". Like the thesis check with its containment test, it
sees a polyhedron wholly inside another. Exact touching (a shared face, edge or corner) is not a
collision for fcl either, but treat it as the tolerance band it is.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

import fcl
import numpy as np

from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.collision.thesis import _LEVI, CLEAR, COLLIDES

RIGID_TOL = 1e-6  # mm per mm of size: how far a vertex may be from a rigid move of the built one


def outward_faces(poly: Polyhedron) -> list[np.ndarray]:
    """The faces of ``poly`` as vertex-index arrays, each counter-clockwise seen from outside."""
    v = poly.vertices
    centre = v.mean(axis=0)
    faces = []
    for face in poly.topology.faces:
        pts = v[face] - centre
        normal = np.cross(pts, np.roll(pts, -1, axis=0)).sum(axis=0)
        faces.append(face if np.dot(normal, pts.mean(axis=0)) >= 0 else face[::-1].copy())
    return faces


def convex(poly: Polyhedron, centre: np.ndarray | None = None) -> fcl.Convex:
    """``fcl.Convex`` of ``poly`` with vertices relative to ``centre`` (default: its centre)."""
    c = poly.centre if centre is None else centre
    faces = outward_faces(poly)
    flat = np.concatenate([np.r_[len(f), f] for f in faces]).astype(np.int64)
    return fcl.Convex(poly.vertices - c, len(faces), flat)


def collides(a: Polyhedron, b: Polyhedron) -> bool:
    """fcl's answer for one pair."""
    oa = fcl.CollisionObject(convex(a), fcl.Transform(np.eye(3), a.centre))
    ob = fcl.CollisionObject(convex(b), fcl.Transform(np.eye(3), b.centre))
    return bool(fcl.collide(oa, ob, fcl.CollisionRequest(), fcl.CollisionResult()))


def distance(a: Polyhedron, b: Polyhedron) -> float:
    """Separation in mm (0 or less when they meet)."""
    oa = fcl.CollisionObject(convex(a), fcl.Transform(np.eye(3), a.centre))
    ob = fcl.CollisionObject(convex(b), fcl.Transform(np.eye(3), b.centre))
    return float(fcl.distance(oa, ob, fcl.DistanceRequest(), fcl.DistanceResult()))


def _frames(p0: np.ndarray, p1: np.ndarray, p2: np.ndarray) -> np.ndarray:
    """(n, 3, 3) orthonormal frames (columns) from three points each (Gram-Schmidt)."""
    def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        product: np.ndarray = (a[:, :, None] * b[:, None, :]).reshape(-1, 9) @ _LEVI
        return product

    e1 = p1 - p0
    e1 /= np.sqrt(np.einsum("ij,ij->i", e1, e1))[:, None]
    e3 = cross(e1, p2 - p0)
    e3 /= np.sqrt(np.einsum("ij,ij->i", e3, e3))[:, None]
    return np.stack([e1, cross(e3, e1), e3], axis=2)


class ExactChecker:
    """python-fcl checker with the ``Checker`` interface of ``valterm.core.collision.world``."""

    name = "exact"

    def __init__(self) -> None:
        self._ks: tuple[int, ...] | None = None
        self._objects: list[fcl.CollisionObject] = []
        self._index: dict[int, int] = {}
        self._managers: dict[tuple[tuple[int, ...], tuple[int, ...]], tuple[Any, ...]] = {}
        self._plan: tuple[Any, ...] | None = None  # pair bookkeeping for the last (moving, stationary) arrays

    # -- keeping fcl in step with the polyhedra ---------------------------------------------
    def _build(self, polys: Sequence[Polyhedron]) -> None:
        self._ks = tuple(p.k for p in polys)
        counts = np.array([2 * k for k in self._ks], dtype=np.intp)
        self._starts = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.intp)
        self._counts = counts
        self._objects = [None] * len(polys)
        self._geoms: list[fcl.Convex] = [None] * len(polys)
        self._local: list[np.ndarray] = [np.zeros((0, 3))] * len(polys)
        self._base_frames = np.zeros((len(polys), 3, 3))
        self._index = {}
        self._managers = {}
        self._extent = np.zeros(len(polys))
        for i, p in enumerate(polys):
            self._make(i, p)
        self._last = np.concatenate([p.vertices for p in polys]) if polys else np.zeros((0, 3))

    def _make(self, i: int, p: Polyhedron) -> None:
        c = p.centre
        geom = convex(p, c)
        old = self._geoms[i]
        if old is not None:
            self._index.pop(id(old), None)
            self._managers = {}  # a new object: build the broad phase again
        self._geoms[i] = geom
        self._index[id(geom)] = i
        self._objects[i] = fcl.CollisionObject(geom, fcl.Transform(np.eye(3), c))
        local = p.vertices - c
        self._local[i] = local
        self._local_all = np.concatenate(self._local)
        self._extent[i] = np.abs(local).max()
        self._base_frames[i] = _frames(local[None, 0], local[None, 1], local[None, p.k])[0]

    def sync(self, polys: Sequence[Polyhedron]) -> None:
        """Bring the fcl objects to where the polyhedra are now (rigid moves, else rebuild)."""
        if tuple(p.k for p in polys) != self._ks:
            self._build(polys)
            return
        if not polys:
            return
        v = np.concatenate([p.vertices for p in polys])
        moved_rows = np.any(v != self._last, axis=1)
        if not moved_rows.any():
            return
        self._last = v
        moved_mask = np.logical_or.reduceat(moved_rows, self._starts)
        moved = np.flatnonzero(moved_mask)
        rows = np.repeat(moved_mask, self._counts)
        counts = self._counts[moved]
        starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
        now = v[rows]
        centres = np.add.reduceat(now, starts, axis=0) / counts[:, None]
        s, k = self._starts[moved], counts // 2
        rot = _frames(v[s], v[s + 1], v[s + k]) @ np.transpose(self._base_frames[moved], (0, 2, 1))
        # rigid if every built vertex, turned and placed, lands on the vertex we were given
        placed = np.einsum("vij,vj->vi", np.repeat(rot, counts, axis=0), self._local_all[rows])
        err = np.abs(placed - (now - np.repeat(centres, counts, axis=0))).max(axis=1)
        err = np.maximum.reduceat(err, starts)
        ok = err <= RIGID_TOL * (1.0 + self._extent[moved])
        for n, i in enumerate(moved.tolist()):
            if ok[n]:
                obj = self._objects[i]
                obj.setRotation(rot[n])
                obj.setTranslation(centres[n])
            else:
                self._make(i, polys[i])      # not a rigid move of what fcl holds
        for m_moving, m_still in self._managers.values():
            m_moving.update()
            m_still.update()

    def _manager_pair(self, moving: tuple[int, ...], still: tuple[int, ...]) -> tuple[Any, ...]:
        key = (moving, still)
        found = self._managers.get(key)
        if found is None:
            built = []
            for group in key:
                m = fcl.DynamicAABBTreeCollisionManager()
                m.registerObjects([self._objects[i] for i in group])
                m.setup()
                built.append(m)
            found = self._managers[key] = tuple(built)
        return found

    # -- the check --------------------------------------------------------------------------
    def colliding(self, polys: Sequence[Polyhedron], moving: np.ndarray, stationary: np.ndarray) -> np.ndarray:
        """Boolean per (moving, stationary) pair."""
        self.sync(polys)
        hit = np.zeros(len(moving), dtype=bool)
        if len(moving) == 0:
            return hit
        plan = self._plan
        if plan is None or plan[0] is not moving or plan[1] is not stationary:
            movers = set(moving.tolist())
            bipartite = np.array([j not in movers for j in stationary.tolist()], dtype=bool)
            where = {(int(i), int(j)): n for n, (i, j) in enumerate(zip(moving, stationary))}
            plan = self._plan = (moving, stationary, bipartite, where)
        bipartite, where = plan[2], plan[3]
        if bipartite.any():
            if len(plan) == 4:
                plan = self._plan = (*plan, tuple(sorted(set(moving[bipartite].tolist()))),
                                     tuple(sorted(set(stationary[bipartite].tolist()))))
            group_m, group_s = plan[4], plan[5]
            m_moving, m_still = self._manager_pair(group_m, group_s)
            request = fcl.CollisionRequest(num_max_contacts=1 << 30)
            data = fcl.CollisionData(request, fcl.CollisionResult())
            m_moving.collide(m_still, data, fcl.defaultCollisionCallback)
            for contact in data.result.contacts:
                a, b = self._index[id(contact.o1)], self._index[id(contact.o2)]
                n = where.get((a, b), where.get((b, a)))
                if n is not None:
                    hit[n] = True
        rest = np.nonzero(~bipartite)[0]
        if len(rest):
            v = self._last
            lo = np.minimum.reduceat(v, self._starts, axis=0)
            hi = np.maximum.reduceat(v, self._starts, axis=0)
            ma, sb = moving[rest], stationary[rest]
            overlap = np.all((lo[ma] <= hi[sb]) & (lo[sb] <= hi[ma]), axis=1)
            for n in rest[overlap]:
                ok = fcl.collide(self._objects[moving[n]], self._objects[stationary[n]],
                                 fcl.CollisionRequest(), fcl.CollisionResult())
                hit[n] = bool(ok)
        return hit

    def check(self, polys: Sequence[Polyhedron], moving: np.ndarray, stationary: np.ndarray,
              grow: float = 0.0, coarse_only: np.ndarray | None = None) -> np.ndarray:
        """Kind codes per pair: COLLIDES or CLEAR (``grow`` and near are the thesis's, unused)."""
        codes = np.where(self.colliding(polys, moving, stationary), COLLIDES, CLEAR).astype(np.int8)
        if coarse_only is not None:
            codes[coarse_only] = CLEAR
        return codes


@dataclass
class _Held:
    """fcl's copy of the carried parts, kept in the hand's frame."""

    key: tuple[int, ...]                  # the carried parts' object numbers
    local: np.ndarray                     # their vertices in the hand's frame, stacked
    extent: float
    objects: list[fcl.CollisionObject]
    geoms: list[fcl.Convex]               # fcl reports contacts by geometry: keep them alive
    rows: dict[int, int]                  # id(geometry) -> row among the carried parts
    tree: fcl.DynamicAABBTreeCollisionManager


class FrameExact:
    """python-fcl fed by link frames: link objects built once in their own frames and moved by
    ``setTransform``; the free parts built once into one AABB tree that never updates; the
    links in a second tree, collided against it (fcl's broad phase picks the nearby pairs).
    Carried parts in a tree of their own, kept in the hand's frame, collided against the parts'
    tree; link-link pairs pair by pair."""

    def __init__(self) -> None:
        self._links: list[fcl.CollisionObject] = []
        self._link_centres = np.zeros((0, 3))
        self._links_tree: fcl.DynamicAABBTreeCollisionManager | None = None
        self._parts_key: tuple[object, ...] | None = None
        self._parts_known: object = None
        self._parts_tree: fcl.DynamicAABBTreeCollisionManager | None = None
        self._index: dict[int, tuple[str, int]] = {}
        self._link_ij: tuple[dict[tuple[int, int], int], np.ndarray, list[tuple[int, int, int]], np.ndarray,
                             np.ndarray] | None = None
        self._held: _Held | None = None
        # one request for every query (fcl only reads it); the data's result is emptied each time
        self._data = fcl.CollisionData(fcl.CollisionRequest(num_max_contacts=1 << 30), fcl.CollisionResult())
        self._one = fcl.CollisionRequest()          # a pair's query: is there a contact at all

    def set_shapes(self, local: Sequence[np.ndarray], owners: np.ndarray) -> None:
        """Link shapes (2k, 3) in their frames; ``owners`` (links,) the frame of each."""
        self._owners = np.asarray(owners, dtype=np.intp)
        self._hand = int(self._owners[-1]) if len(self._owners) else 0    # the frame the fingers ride
        self._links, centres = [], []
        self._geoms: list[fcl.Convex] = []
        self._index = {}
        self._parts_key = None
        for i, shape in enumerate(local):
            poly = Polyhedron(shape)
            c = poly.centre
            geom = convex(poly, c)
            obj = fcl.CollisionObject(geom, fcl.Transform(np.eye(3), c))
            self._links.append(obj)
            self._geoms.append(geom)          # fcl reports contacts by geometry: keep them alive
            self._index[id(geom)] = ("link", i)
            centres.append(c)
        self._link_centres = np.array(centres)
        self._links_tree = fcl.DynamicAABBTreeCollisionManager()
        self._links_tree.registerObjects(self._links)
        self._links_tree.setup()

    def _parts(self, objects: Sequence[Polyhedron], free: Sequence[int], known: object = None) -> None:
        """The free parts' tree, built again when they moved. ``known``: the caller's name for
        the parts where they are (an object it replaces when they move): no need to look."""
        old = self._parts_key
        if known is not None and known is self._parts_known and old is not None:
            return
        self._parts_known = known
        if old is not None and len(old) == len(free) + 1 and old[0] == tuple(free) and all(
                a is objects[n - 1].vertices for a, n in zip(old[1:], free)):
            return
        key = (tuple(free), *(objects[n - 1].vertices for n in free))
        self._index = {k: v for k, v in self._index.items() if v[0] == "link"}
        objs, geoms = [], []
        for position, n in enumerate(free):
            p = objects[n - 1]
            geom = convex(p)
            obj = fcl.CollisionObject(geom, fcl.Transform(np.eye(3), p.centre))
            self._index[id(geom)] = ("part", position)
            objs.append(obj)
            geoms.append(geom)
        tree = fcl.DynamicAABBTreeCollisionManager()
        tree.registerObjects(objs)
        tree.setup()
        self._parts_tree, self._parts_key, self._part_objects, self._part_geoms = tree, key, objs, geoms

    def _carried(self, frames: np.ndarray, objects: Sequence[Polyhedron], carried: Sequence[int]
                 ) -> tuple[dict[int, int], fcl.DynamicAABBTreeCollisionManager] | None:
        """The carried parts in an AABB tree of their own (with each geometry's row): built in
        the hand's frame, then moved with it while the parts ride it rigidly (as they do while
        the clamp holds them); built again when they do not."""
        if not carried:
            return None
        hand = frames[self._hand]
        rot, origin = hand[:3, :3], hand[:3, 3]
        now = np.concatenate([objects[c - 1].vertices for c in carried])
        held = self._held
        if held is not None and held.key == tuple(carried) and len(held.local) == len(now):
            off = held.local @ rot.T
            off += origin
            off -= now
            if np.abs(off, out=off).max() <= RIGID_TOL * (1.0 + held.extent):
                for obj in held.objects:
                    obj.setRotation(rot)
                    obj.setTranslation(origin)
                held.tree.update()
                return held.rows, held.tree
        local = (now - origin) @ rot                 # the parts' vertices in the hand's frame
        split = np.cumsum([len(objects[c - 1].vertices) for c in carried])[:-1]
        geoms = [convex(Polyhedron(part), np.zeros(3)) for part in np.split(local, split)]
        objs = [fcl.CollisionObject(g, fcl.Transform(rot, origin)) for g in geoms]
        tree = fcl.DynamicAABBTreeCollisionManager()
        tree.registerObjects(objs)
        tree.setup()
        self._held = _Held(tuple(carried), local, float(np.abs(local).max()), objs, geoms,
                           {id(g): row for row, g in enumerate(geoms)}, tree)
        return self._held.rows, tree

    def _contacts(self, tree: fcl.DynamicAABBTreeCollisionManager) -> list[Any]:
        """fcl's contacts of ``tree``'s objects with the free parts' (both trees' broad phase)."""
        data = self._data
        data.done = False
        data.result.is_collision = False
        data.result.contacts = []
        tree.collide(self._parts_tree, data, fcl.defaultCollisionCallback)
        contacts: list[Any] = data.result.contacts
        return contacts

    def hits(self, frames: np.ndarray, objects: Sequence[Polyhedron], free: Sequence[int],
             carried: Sequence[int], link_pairs: dict[tuple[int, int], int], radii: np.ndarray,
             centres: np.ndarray, parts_key: object = None) -> list[int]:
        """The positions of the pairs that collide, ascending, in ``CollisionWorld.pairs`` order
        (rules 1, 2, 3): a step finds a few of hundreds, so no code per pair is made.

        ``radii``: each link's farthest vertex from its centre (the link x link pairs whose
        spheres do not meet are not asked about). ``centres``: the links' centres in the world.
        ``parts_key``: an object the caller replaces whenever the free parts move or change
        (``RobotScene`` has one): while it is the same, the parts are not looked at."""
        self._parts(objects, free, parts_key)
        assert self._links_tree is not None and self._parts_tree is not None
        rot = frames.take(self._owners, axis=0)[:, :3, :3]
        for obj, r, t in zip(self._links, rot, centres):
            obj.setRotation(r)                  # (cheaper than a new Transform per link)
            obj.setTranslation(t)
        self._links_tree.update()
        found: list[int] = []
        n_free, nl = len(free), len(self._links)
        if n_free:
            for contact in self._contacts(self._links_tree):
                a = self._index.get(id(contact.o1))
                b = self._index.get(id(contact.o2))
                if a is None or b is None or a[0] == b[0]:
                    continue
                link, part = (a[1], b[1]) if a[0] == "link" else (b[1], a[1])
                found.append(link * n_free + part)
            held = self._carried(frames, objects, carried)
            if held is not None:
                rows, tree = held
                for contact in self._contacts(tree):
                    row = rows.get(id(contact.o1), rows.get(id(contact.o2)))
                    other = self._index.get(id(contact.o2 if id(contact.o1) in rows else contact.o1))
                    if row is not None and other is not None and other[0] == "part":
                        found.append((nl + row) * n_free + other[1])
        if link_pairs:                                  # robot link against robot link
            found += self._link_hits(link_pairs, radii, centres)
        return sorted(set(found))

    def _link_hits(self, link_pairs: dict[tuple[int, int], int], radii: np.ndarray, centres: np.ndarray) -> list[int]:
        """The positions of the link x link pairs that collide: fcl asked only about links whose
        spheres (about their centres, holding them) meet."""
        if self._link_ij is None or self._link_ij[0] is not link_pairs or self._link_ij[1] is not radii:
            ij = np.array(list(link_pairs), dtype=np.intp).reshape(-1, 2)
            # one product gives every pair's centre i less centre j (the other terms are 0)
            apart = np.zeros((len(ij), len(radii)))
            apart[np.arange(len(ij)), ij[:, 0]] = 1.0
            apart[np.arange(len(ij)), ij[:, 1]] = -1.0
            # 1 mm over the two spheres: a pair further apart is certainly clear
            reach = (radii.take(ij[:, 0]) + radii.take(ij[:, 1]) + 1.0) ** 2
            asked = [(int(i), int(j), link_pairs[(int(i), int(j))]) for i, j in ij.tolist()]
            self._link_ij = (link_pairs, radii, asked, apart, reach)
        _, _, asked, apart, reach = self._link_ij
        d = apart @ centres
        found = []
        for n in np.flatnonzero((d * d) @ _ONES3 <= reach).tolist():
            a, b, at = asked[n]
            if fcl.collide(self._links[a], self._links[b], self._one, fcl.CollisionResult()):
                found.append(at)
        return found


_ONES3 = np.ones(3)
