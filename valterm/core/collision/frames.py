"""The scene's collision check fed straight from the robot's link frames (what the simulator has).

``CollisionWorld.check`` takes polyhedra: the simulator used to build ten ``Polyhedron`` objects
per pose and the check concatenated every part's vertices again. ``RobotScene`` keeps instead:

* the link shapes in their own frames (fingers at the current gap), placed at each pose with
  one einsum from the 4x4 link frames, written into a vertex array allocated once;
* the parts' vertices, centres, radii and boxes, computed once and again only when a part is
  moved (its vertex array replaced) - a carried part is re-placed every pose like a link;
* a broad phase, each mover on its own: the free parts are kept in groups of neighbours
  (built when the parts change), and a mover's pairs go to the coarse + fine check only with
  the parts of the groups whose box, grown by that mover's radius and the margin, holds its
  centre: a few dozen pairs of the thousands on a dense cell. The skipped pairs are ones the
  coarse test would call clear, so the findings are those of ``CollisionWorld.check``.

The same pair rules, kinds and message order as ``CollisionWorld`` (it is used for them).
With ``checker="exact"`` python-fcl answers the pairs the broad phase keeps
(``valterm.core.collision.exact.FrameExact``: link objects built once, moved by their frames).
"""

from __future__ import annotations

import itertools
import math
import operator
from typing import TYPE_CHECKING, Callable, Collection, Literal, Sequence

import numpy as np

from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.collision import arrays
from valterm.core.collision.glance import GLANCE, Glancing, at_risk
from valterm.core.collision.thesis import (CLEAR, COLLIDES, EPS, NEAR, SEPARATED, Layout, Scene, check_pairs,
                                           face_planes, figures, layout, margin)
from valterm.core.collision.moments import MomentsBatch, PathFigures, over_middle
from valterm.core.collision.world import CollisionWorld, Finding, _Pairs

if TYPE_CHECKING:
    from valterm.core.collision.exact import FrameExact


class RobotScene(MomentsBatch):
    """Collision check of robot links given as frames, against the parts of a work cell."""

    # below this many mover x part pairs the coarse test of them all costs less than the
    # broad phase that would pick among them (a few numpy calls either way)
    broad_phase_from = 600

    def __init__(self, labels: Sequence[str], owners: Sequence[int],
                 checker: Literal["thesis", "exact"] = "thesis",
                 near_with_collision: bool = False, thesis_axes: bool = True) -> None:
        self.world = CollisionWorld(labels, near_with_collision=near_with_collision)
        # the thesis's link frames: joint j turns about frame j's origin, about the column
        # arrays.AXIS_COLUMNS gives. Another robot's frames (a DH table's: joint j turns about frame
        # j-1's z) get the swept bound from lengths alone (_reach_table): never too small
        self.thesis_axes = thesis_axes
        self.owners = np.asarray(owners, dtype=np.intp)
        self._n_frames = int(self.owners.max()) + 1 if len(self.owners) else 0   # the frames used
        # flat indices into (links, 4, 4) frames of ``arrays.stacked``'s (4, 3 x frames) layout
        self._stack_pick = (np.arange(self._n_frames)[None, :, None] * 16 + np.arange(3)[None, None, :] * 4
                            + np.arange(4)[:, None, None]).reshape(4, -1)
        self.checker = checker
        self._exact: FrameExact | None = None
        self._exact_pairs: tuple[_Pairs, list[int], dict[tuple[int, int], int]] | None = None
        self._local = np.zeros((0, 3))
        self._link_ks: tuple[int, ...] = ()
        self._owner_rows = np.zeros(0, dtype=np.intp)
        self._parts: tuple[np.ndarray, ...] | None = None   # the part arrays the cache was built from
        self._carried: tuple[int, ...] = ()
        self._thin: dict[int, tuple[np.ndarray, float]] = {}
        self._pairs_now: _Pairs | None = None       # the pairs of the last ``check``
        self._placements = -1                        # Polyhedron.placements when the parts were last seen
        self._objects: tuple[Polyhedron, ...] = ()   # and the objects then
        self._pairs_for: tuple[int, tuple[int, ...]] = (0, ())   # their objects and carried parts
        self._gaps_now: np.ndarray | None = None     # their box gaps, when it measured every pair
        self._every: np.ndarray | None = None
        self._part_widths: tuple[object, np.ndarray] | None = None
        self._thinnest_kept: tuple[object, float] | None = None
        self._table: tuple[object, np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None = None   # _travel_table's
        # the pose ``swept`` last saw: (pose, parts, carried, box gaps of every pair, or the boxes)
        self._ends: tuple[object, object, object, np.ndarray | None, np.ndarray | None, np.ndarray | None] | None = None
        self._planes_due: tuple[np.ndarray, np.ndarray] | None = None   # frames whose planes are not set yet
        self._link_widths = np.zeros(0)
        self._pair_widths: tuple[object, np.ndarray] | None = None    # _ruled_widths'
        self._sel_kept: tuple[_Pairs, int, np.ndarray, np.ndarray] | None = None   # _sel_parts'
        self._group_kept: tuple[object, float, np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None = None
        self._linked: tuple[_Pairs, tuple[np.ndarray, np.ndarray, np.ndarray]] | None = None   # _link_pairs'
        self._picks: dict[int, tuple[np.ndarray, np.ndarray]] = {}    # _path_picks'
        self._past_kept: dict[int, tuple[np.ndarray, ...]] = {}   # _past_width's, by the bounds' id
        self._fixed_kept: tuple[object, object, dict[tuple[float, ...], tuple[np.ndarray, np.ndarray, np.ndarray,
                                np.ndarray, bool, float]]] | None = None   # _fixed_lengths'
        # the pairs the last ``swept`` or ``swept_path`` left to look at between its moments
        self.glancing: Glancing | None = None

    # -- what is built once ----------------------------------------------------------------
    def set_shapes(self, local: Sequence[np.ndarray]) -> None:
        """The link shapes, each (2k, 3) in its link's frame (call again when the fingers move)."""
        if len(local) != len(self.world.labels):
            raise ValueError(f"expected {len(self.world.labels)} robot links, got {len(local)}")
        self._local = np.concatenate(local)
        self._link_ks = tuple(len(v) // 2 for v in local)
        self._owner_rows = np.repeat(self.owners, [len(v) for v in local])
        self._local_h = np.column_stack([self._local, np.ones(len(self._local))])
        self._own_flat = arrays.pick(self._owner_rows, self._n_frames)
        self._parts = None
        # what a rigid motion keeps: each link's centre and radius in its own frame
        own = Scene.of([Polyhedron(np.asarray(v, dtype=float)) for v in local])
        self._local_centres = np.column_stack([own.centres, np.ones(len(local))])
        # the vertices and the centres placed by one product, each then taken from it
        self._local_all = np.concatenate([self._local_h, self._local_centres])
        self._own_centre_pick = arrays.pick(self.owners, self._n_frames)
        self._centre_pick = self._own_centre_pick + len(self._local) * 3 * self._n_frames
        self._local_radii = own.radii
        self._link_widths = np.array([arrays.thickness(np.asarray(v, dtype=float), len(v) // 2) for v in local])
        self._linked = None
        self._picks = {}
        if self.checker == "exact":
            from valterm.core.collision.exact import FrameExact   # fcl only when asked for
            self._exact = FrameExact()
            self._exact.set_shapes(local, self.owners)

    def _rebuild(self, objects: Sequence[Polyhedron], carried: tuple[int, ...]) -> None:
        """Layout, vertex array and per-polyhedron figures for the parts where they are now."""
        ks = self._link_ks + tuple(p.k for p in objects)
        self._layout: Layout = layout(ks)
        nl = len(self._link_ks)
        self._nl_rows = int(self._layout.starts[nl]) if objects else len(self._local)
        scene = Scene.of([Polyhedron(np.zeros((2 * k, 3))) for k in self._link_ks] + list(objects))
        lay = self._layout
        scene.planes = face_planes(scene.vertices, lay.face_idx, lay.face_next)
        # the links' face planes in their own frames (padded as the whole scene's): moved by _update
        self._local_planes = face_planes(self._local, lay.face_idx[:nl], lay.face_next[:nl])
        scene.planes[2][:nl] = self._local_planes[2]      # a face's area does not move,
        # for ``_apart``: each link's face planes in its own frame, turned to look away from its
        # centre (normals as columns); other bodies' planes 0 with an infinite offset (never apart)
        unit, off = self._local_planes[0], self._local_planes[1]
        outward = -np.sign(np.einsum("nfk,nk->nf", unit, self._local_centres[:, :3]) - off)
        self._apart_normals = np.zeros((len(ks), 3, unit.shape[1]))
        self._apart_normals[:nl] = (unit * outward[..., None]).transpose(0, 2, 1)
        self._apart_offsets = np.full((len(ks), unit.shape[1]), np.inf)
        self._apart_offsets[:nl] = off * outward
        self._body_frames = np.zeros(len(ks), dtype=np.intp)
        self._body_frames[:nl] = self.owners
        # each polyhedron's vertex rows, padded with its last (a repeated vertex changes no extreme)
        self._vertex_rows = lay.starts[:, None] + np.minimum(np.arange(int(lay.counts.max())), lay.counts[:, None] - 1)
        scene.apart = self._apart
        self._local_normals = self._local_planes[0].reshape(-1, 3)
        faces = self._local_planes[0].shape[1]
        self._normal_pick = arrays.pick(np.repeat(self.owners, faces), self._n_frames)
        scene.radii[:nl] = self._local_radii                # nor a link's radius
        scene.stale = np.zeros(len(ks), dtype=bool)
        scene.refresh = self._move_planes
        self._planes_due = None
        self._scene = scene
        # the links' rows of the scene's arrays (views, kept while the scene is) and room for
        # their boxes' corners: what ``_update`` writes at each pose
        self._link_rows = (scene.vertices[: self._nl_rows], scene.centres[:nl], scene.mid[:nl], scene.half[:nl],
                           lay.starts[:nl], np.empty((nl, 3)), np.empty((nl, 3)))
        self._parts = tuple(p.vertices for p in objects)
        self._placements, self._objects = Polyhedron.placements, tuple(objects)
        self._carried = carried
        self._movers = np.array([*range(nl), *(nl + c - 1 for c in carried)], dtype=np.intp)
        scene.stale[nl + np.asarray(carried, dtype=np.intp) - 1] = True   # links' planes kept by _update
        free = np.array([nl + n - 1 for n in range(1, len(objects) + 1) if n not in set(carried)], dtype=np.intp)
        self._free = free
        self._free_lo, self._free_hi = scene.mid[free] - scene.half[free], scene.mid[free] + scene.half[free]
        self._groups = arrays.groups(self._free_lo, self._free_hi)
        # the carried parts' polyhedra, their vertex rows in the scene, and where each starts
        self._held_at = np.array([nl + c - 1 for c in carried], dtype=np.intp)
        sizes = np.array([2 * objects[c - 1].k for c in carried], dtype=np.intp)
        self._held_rows = np.concatenate([np.arange(int(lay.starts[i]), int(lay.starts[i]) + n)
                                          for i, n in zip(self._held_at.tolist(), sizes.tolist())]
                                         ) if carried else np.zeros(0, dtype=np.intp)
        self._held_sizes = sizes
        self._held_starts = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.intp)

    def _parts_changed(self, objects: Sequence[Polyhedron], carried: tuple[int, ...]) -> bool:
        parts = self._parts
        if parts is None or carried != self._carried or len(parts) != len(objects):
            return True
        if not carried:
            if Polyhedron.placements == self._placements:    # no vertices set since: the same objects?
                return not _same_objects(self._objects, objects)
            self._placements, self._objects = Polyhedron.placements, tuple(objects)
            return not all(map(operator.is_, parts, map(_VERTICES, objects)))   # one pass in C
        # a carried part moves every pose: not part of the cache
        if Polyhedron.placements == self._placements and _same_free(self._objects, objects, carried):
            return False
        self._placements, self._objects = Polyhedron.placements, tuple(objects)
        now = list(map(_VERTICES, objects))
        for c in carried:
            now[c - 1] = parts[c - 1]
        return not all(map(operator.is_, parts, now))

    # -- each pose -----------------------------------------------------------------------------
    def place(self, frames: np.ndarray) -> np.ndarray:
        """World vertices of every link shape at these (links, 4, 4) frames, concatenated."""
        # every vertex in every frame is one 2-D matmul (cheaper than a stack of tiny ones or
        # picking each vertex's frame first); the coordinates wanted are then taken in one call
        return self._place(arrays.stacked(frames[: self._n_frames]))

    def _place(self, stacked: np.ndarray) -> np.ndarray:
        placed: np.ndarray = (self._local_h @ stacked).take(self._own_flat)
        return placed

    def _update(self, frames: np.ndarray) -> np.ndarray:
        """Put the links where they are now; the indices of the moving polyhedra."""
        placed, centres, mid, half, starts, lo, hi = self._link_rows
        stacked = frames.take(self._stack_pick)      # ``arrays.stacked`` in one call: (4, 3 x frames)
        # taken straight into the scene's arrays ("wrap": the indices are valid, and numpy
        # buffers a take into ``out`` in its default mode)
        every = self._local_all @ stacked
        every.take(self._own_flat, out=placed, mode="wrap")
        # a link's centre, radius and face planes move with its frame: no pass over its vertices
        every.take(self._centre_pick, out=centres, mode="wrap")
        self._planes_due = (frames, stacked)       # the face planes follow when a fine check asks
        self._frames_now = frames
        np.minimum.reduceat(placed, starts, axis=0, out=lo)
        np.maximum.reduceat(placed, starts, axis=0, out=hi)
        np.multiply(np.add(lo, hi, out=mid), 0.5, out=mid)
        np.multiply(np.subtract(hi, lo, out=half), 0.5, out=half)
        return self._movers

    def _place_carried(self, objects: Sequence[Polyhedron]) -> None:
        """The carried parts' vertices, centres, radii and boxes as they are now (all at once)."""
        s, at, starts, sizes = self._scene, self._held_at, self._held_starts, self._held_sizes
        nl = len(self._link_ks)
        now = np.concatenate([objects[i - nl].vertices for i in at.tolist()])
        s.vertices[self._held_rows] = now
        s.centres[at], s.radii[at], s.mid[at], s.half[at] = figures(now, starts, sizes)

    def _move_planes(self) -> None:
        """The links' face planes at the frames of the last ``_update`` (turned normals, moved offsets)."""
        if self._planes_due is None:
            return
        frames, stacked = self._planes_due
        self._planes_due = None
        planes, nl = self._scene.planes, len(self._link_ks)
        assert planes is not None
        unit = planes[0][:nl]
        unit.reshape(-1, 3)[:] = (self._local_normals @ stacked[:3]).take(self._normal_pick)    # R n
        planes[1][:nl] = self._local_planes[1] + np.matmul(unit, frames[self.owners, :3, 3:])[..., 0]

    def _apart(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """Per pair (a[i], b[i]) with a[i] a link: is every vertex of b[i] more than ``SEPARATED``
        mm beyond one of the link's face planes? Only the planes of the links asked about are
        placed (from their own frames, kept turned to look outward), not every link's; the fine
        test would answer clear (its own shortcut's argument). False where a[i] is not a link.
        For ``Scene.apart``; the links where the last ``_update`` put them."""
        frame = self._frames_now.take(self._body_frames.take(a), axis=0)
        turned = frame[:, :3, :3] @ self._apart_normals.take(a, axis=0)               # R n: the planes placed
        off = self._apart_offsets.take(a, axis=0) + (frame[:, None, :3, 3] @ turned)[:, 0]
        d = self._scene.vertices[self._vertex_rows.take(b, axis=0)] @ turned            # (pairs, V, faces)
        d -= off[:, None]
        self._apart_now = (self._frames_now, a, b, over_middle(d, np.minimum).max(axis=1))   # for poses_clear
        found: np.ndarray = self._apart_now[3] > SEPARATED
        return found

    def _candidates(self, movers: np.ndarray, grow: float) -> np.ndarray:
        """Broad phase: positions among the free parts of those a mover could be near
        (``arrays.candidates_batch`` at the pose now)."""
        s = self._scene
        reach = np.array([float(s.radii[movers].max()) + grow])
        near = arrays.candidates_batch(s.centres[movers][None], reach, self._free_lo, self._free_hi)
        return np.flatnonzero(near[0])

    def _near_pairs(self, movers: np.ndarray, grow: float, n_free: int) -> np.ndarray:
        """Broad phase, each mover on its own: the positions (rules 1 and 2) of the pairs of each
        mover with the parts of every group whose box, grown by that mover's radius and the margin,
        holds its centre: a few more than the coarse test calls near, never fewer."""
        s = self._scene
        mid, half, at, reach = self._group_table(movers, grow, n_free)
        # (3, movers x groups): how far each centre is outside each group's box on each axis
        d = s.centres.take(movers, axis=0).T.repeat(len(mid[0]) // len(movers), axis=1)
        np.subtract(mid, d, out=d)
        np.abs(d, out=d)
        d -= half
        near: np.ndarray = at.take(np.flatnonzero(arrays.largest_of(d) <= reach), axis=0).ravel()
        return near

    def _group_table(self, movers: np.ndarray, grow: float, n_free: int
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The groups' box middles and half sizes once for each mover (3, movers x groups), the
        pair positions of each (mover, group) and each mover's reach, repeated likewise: kept
        per set of parts and margin (a carried part's reach measured at each call)."""
        kept = self._group_kept
        if kept is None or kept[0] is not self._parts or kept[1] != grow:
            members, lo, hi = self._groups
            m = len(movers)
            at = (np.arange(m)[:, None, None] * n_free + members[None]).reshape(m * len(members), -1)
            kept = self._group_kept = (self._parts, grow, np.tile((lo + hi) * 0.5, m), np.tile((hi - lo) * 0.5, m), at,
                                       self._reach(movers, grow, len(members)))
        elif self._carried:
            kept = (*kept[:5], self._reach(movers, grow, len(self._groups[0])))
        return kept[2], kept[3], kept[4], kept[5]

    def _reach(self, movers: np.ndarray, grow: float, groups: int) -> np.ndarray:
        # 1 mm over the coarse test's reach: the group's box is the same test in other roundings
        reach: np.ndarray = (self._scene.radii.take(movers) + (grow + 1.0)).repeat(groups)
        return reach

    def check(self, frames: np.ndarray, objects: Sequence[Polyhedron], carried: Collection[int] = (),
              speed: float = 100.0) -> list[Finding]:
        """One motion step: findings for the links at ``frames`` (links, 4, 4) and the parts."""
        if type(carried) is tuple and carried == self._carried:   # as the last step (sorted, once each)
            held = self._carried
        else:
            held = tuple(sorted(set(carried))) if carried else ()
        if self._parts_changed(objects, held):
            self._rebuild(objects, held)
        world = self.world
        pairs = self._pairs_now
        if pairs is None or self._pairs_for != (len(objects), held):
            pairs = world.pairs(len(objects), held)
            self._pairs_for = (len(objects), held)
        self._pairs_now = pairs
        if len(pairs.moving) == 0:
            return []
        if self.checker == "exact":                     # fcl keeps its own copy of the shapes
            hits = self._exact_hits(frames, objects, held, pairs)
            return world.findings_at(pairs, tuple((p, COLLIDES) for p in hits)) if hits else []
        movers = self._update(frames)
        if held:                                        # the carried parts: figures from their vertices
            self._place_carried(objects)
        grow = margin(speed)
        n_free = len(self._free)
        ruled = len(movers) * n_free                     # rules 1 and 2: movers x free parts
        if n_free and ruled >= self.broad_phase_from:
            sel = np.concatenate([self._near_pairs(movers, grow, n_free), self._sel_parts(pairs, ruled, n_free)[1]])
        else:                      # every pair: their box gaps kept for the swept check
            gaps = np.empty(len(pairs.moving))
            codes = check_pairs(self._scene, pairs.moving, pairs.stationary, grow, gaps=gaps)
            self._gaps_now = gaps
            return world.findings(pairs, codes)
        self._gaps_now = None
        found = check_pairs(self._scene, pairs.moving.take(sel), pairs.stationary.take(sel), grow)
        hit = np.flatnonzero(found)
        if len(hit) == 0:              # nothing near (about half the poses on a dense cell)
            return []
        # by position, once each (a group's padding repeats a pair)
        return world.findings_at(pairs, tuple(sorted(set(zip(sel.take(hit).tolist(), found.take(hit).tolist())))))

    def _sel_parts(self, pairs: _Pairs, ruled: int, n_free: int) -> tuple[np.ndarray, np.ndarray]:
        """Where each mover's pairs with the free parts start (a column), and the positions of
        the pairs after those (links x links); kept per set of pairs."""
        kept = self._sel_kept
        if kept is None or kept[0] is not pairs or kept[1] != n_free:
            kept = self._sel_kept = (pairs, n_free, np.arange(0, ruled, n_free)[:, None],
                                     np.arange(ruled, len(pairs.moving)))
        return kept[2], kept[3]

    def collisions_between(self, frames: np.ndarray, objects: Sequence[Polyhedron], only: np.ndarray,
                           speed: float = 100.0) -> list[Finding]:
        """The collisions of the pairs at positions ``only`` (``swept``'s, at one of its moments)
        with the links at ``frames``: the parts are those of the last ``check``, a carried one
        moved with the hand."""
        pairs = self._pairs_now
        assert pairs is not None
        self._update(frames)
        if self._carried:
            self._place_carried(objects)
        codes = np.zeros(len(pairs.moving), dtype=np.int8)
        codes[only] = check_pairs(self._scene, pairs.moving.take(only), pairs.stationary.take(only), margin(speed))
        codes[codes != COLLIDES] = CLEAR
        return self.world.findings(pairs, codes)

    def _exact_hits(self, frames: np.ndarray, objects: Sequence[Polyhedron], held: tuple[int, ...],
                    pairs: _Pairs) -> list[int]:
        """python-fcl on the same pairs (its own AABB trees are the broad phase): the positions
        of those that collide."""
        assert self._exact is not None
        if self._exact_pairs is None or self._exact_pairs[0] is not pairs:   # once per set of pairs
            nl = len(self._link_ks)
            free = [n for n in range(1, len(objects) + 1) if n not in set(held)]
            ruled = (nl + len(held)) * len(free)
            link_pairs = {(int(i), int(j)): n for n, (i, j) in
                          enumerate(zip(pairs.moving[ruled:], pairs.stationary[ruled:]), start=ruled)}
            self._exact_pairs = (pairs, free, link_pairs)
        _, free, link_pairs = self._exact_pairs
        # the links' centres (fcl's objects are placed by them) as ``_update`` works them out;
        # no vertex is placed: fcl has its own copy of the shapes
        centres = (self._local_centres @ arrays.stacked(frames[: self._n_frames])).take(self._own_centre_pick)
        return self._exact.hits(frames, objects, free, held, link_pairs, self._local_radii, centres, self._parts)

    # -- swept motion (issue 13) -----------------------------------------------------------------
    def _width(self, p: Polyhedron) -> float:
        """A part's thinnest width, cached with the vertex array it was measured on."""
        found = self._thin.get(id(p.vertices))
        if found is not None and found[0] is p.vertices:
            return found[1]
        if len(self._thin) > 4096:
            self._thin.clear()
        w = arrays.thickness(p.vertices, p.k)
        self._thin[id(p.vertices)] = (p.vertices, w)
        return w

    def swept(self, frames: np.ndarray, turned: Sequence[float], objects: Sequence[Polyhedron],
              since: object = None, now: object = None) -> tuple[np.ndarray, np.ndarray]:
        """Conservative advancement over the step that ended at ``frames``: the moments between
        the two poses to check (fractions of the step, none when nothing can be met) and, for
        each, the pairs to check there (a boolean row over the step's pairs).

        ``turned``: each joint's turn over the step (radians, JT1..JT6). With the joints
        moving linearly, a point of a body carried by frame k moves at most
        sum over j <= k of |turn j| x (its distance from joint j's origin), that distance
        bounded from where it is now and from the chain's fixed lengths. A box holding a body
        moves no more than its points, and the fine test finds a collision only where the two
        boxes meet: with the boxes ``g0`` apart at the start and ``g1`` at the end, and ``b``
        the most both can move, they can meet only from ``g0 / b`` to ``1 - g1 / b`` of the
        step, and never when ``g0 + g1 > b``. Those pairs are checked at moments no farther
        apart than the thinnest part among them (for collisions: "near" is said at the poses,
        as in 1985). Link x link pairs (the arm against itself) likewise, their boxes closing
        by at most both bounds, at moments no farther apart than the proximal link's width
        measured against the distal link's travel relative to it (``_link_gaps``). ``since`` and
        ``now`` name the two poses (the boxes at ``since`` are those kept by the last call,
        when it was given ``now=since``; else ``g0`` is 0).
        Call after ``check`` at ``frames`` (it uses the figures placed there).
        """
        pairs, s = self._pairs_now, self._scene
        kept, self._ends = self._ends, None
        never, self.glancing = _NEVER, None
        if pairs is None or self.checker == "exact" or len(pairs.moving) == 0:
            return never
        gaps = self._gaps_now
        if now is not None:           # the boxes themselves only when the gaps were not all measured
            self._ends = (now, self._parts, self._carried, gaps,
                          *((s.mid.copy(), s.half.copy()) if gaps is None else (s.mid, s.half)))
        if not any(turned):
            return never
        thinnest = self._thinnest(objects)
        linked = self._link_pairs(pairs)
        turns, terms, bound, relative, linking, top = self._fixed_lengths(frames, turned, linked)
        parts: tuple[np.ndarray, ...] | None = None
        links: tuple[np.ndarray, ...] | None = None
        link_risky = False  # the fixed lengths first (one product; they clear many steps), then from where bodies are
        for tight in (False, True):
            if tight:
                terms = self._sweep_terms(frames, turns, terms)
                bound, relative, linking, top = self._bounds(terms, linked)
            if top <= min(thinnest, GLANCE) and not linking:
                return never              # nothing moves as far as the thinnest part is wide
            if links is None and linking:
                links = self._link_gaps(linked, since, kept)
            # a pair whose boxes can meet and that moves past its part's width needs moments
            if parts is None and gaps is not None:   # every pair's gaps measured: the few past theirs
                risky = self._past_width(bound, objects, since, kept, not tight, (frames, now))
            else:
                if parts is None:         # the pairs (and their gaps) the fixed lengths can reach
                    parts = self._part_pairs(top, objects, since, kept)
                moved = bound.take(parts[1])
                risky = self._risky(parts[0], moved, parts[5], parts[3] - parts[5] + 2.0 * EPS, parts[4],
                                    (frames, since, now))
            if links is not None:
                closing = bound.take(links[1]) + bound.take(links[2])
                link_risky = bool(((links[3] <= closing) & (relative > 1.0)).any())
            if not (risky or link_risky):
                return never
        if self._glance_left is not None and not link_risky:   # glancing pairs alone: no moments
            self.glancing = self._glance_left
            return never
        if parts is None:
            parts = self._part_pairs(top, objects, since, kept)
            moved = bound.take(parts[1])
        columns = [(parts[0], parts[5], parts[3], moved, moved / parts[4])]
        picks = [np.flatnonzero(parts[3] <= moved)]
        if links is not None:
            columns.append((links[0], links[5], links[3], closing, relative))
            picks.append(np.flatnonzero((links[3] <= closing) & (relative > 1.0)))
        sel, b0, both, reach, need = (np.concatenate([c[i].take(p) for c, p in zip(columns, picks)]) for i in range(5))
        _, moments, rows = arrays.moments(np.ones((1, len(sel)), dtype=bool), sel, b0[None], both[None], reach[None],
                                    need[None], len(pairs.moving))
        glance = np.flatnonzero((parts[3] <= moved) & (moved > GLANCE))
        self.glancing = at_risk((np.zeros(len(glance), dtype=np.intp), parts[0].take(glance)), moved.take(glance),
                                parts[5].take(glance), parts[3].take(glance), len(pairs.moving))
        return moments, rows

    def _fixed_lengths(self, frames: np.ndarray, turned: Sequence[float], linked: tuple[np.ndarray, ...]
                       ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, bool, float]:
        """``swept``'s first pass, the bound from the fixed lengths: the joints' turns (absolute),
        the travel terms, each body's bound, the link pairs' steps needed, whether one needs
        more than one and the largest bound. The same for the same turns while the travel
        table is the one kept (links only, on the thesis's axes): a path turns its joints
        alike at every step, so the last step's are used again."""
        table = self._travel_table(frames)
        kept = self._fixed_kept
        if kept is None or kept[0] is not table or kept[1] is not linked:
            kept = self._fixed_kept = (table, linked, {})
        key = tuple(turned)
        found = kept[2].get(key)
        if found is None:
            turns = np.absolute(turned, dtype=float)
            terms = table * turns
            found = (turns, terms, *self._bounds(terms, linked))
            if len(kept[2]) >= 16:         # a few turns at a time (a path's differ in the last bits)
                kept[2].clear()
            kept[2][key] = found
        return found

    def _bounds(self, terms: np.ndarray, linked: tuple[np.ndarray, ...]) -> tuple[np.ndarray, np.ndarray, bool, float]:
        """From the (movers, joints) travel terms: each body's bound (0 for the still ones; with
        nothing carried the movers are the links, the first rows, and theirs alone will do),
        each link pair's steps needed, whether one needs more than one, the largest bound."""
        movers, nl = self._movers, len(self._link_ks)
        if len(movers) > nl:
            bound = np.zeros(len(self._scene.radii))
            bound[movers] = terms.sum(axis=1)
        else:
            bound = terms.sum(axis=1)
        relative = linked[2] @ terms[:nl].ravel()           # link x link: the steps each needs
        return bound, relative, float(relative.max(initial=0.0)) > 1.0, float(bound.max())

    # -- a whole path's steps together (issue 25, round 7) -------------------------------------
    def path_figures(self, count: int, since: object) -> PathFigures | None:
        """Room for what ``swept_path`` needs of a path's ``count`` poses (``keep_pose``), the
        gaps at the pose before (named ``since``) as ``swept`` kept them. Call after ``check``
        at the path's first pose; None when there is nothing to sweep."""
        pairs = self._pairs_now
        if pairs is None or self.checker == "exact" or len(pairs.moving) == 0:
            return None
        movers, n = self._movers, len(pairs.moving)
        gaps = np.empty((count + 1, n))
        gaps[0] = self._kept_gaps(self._ends, since, self._all_pairs(n), pairs.moving, pairs.stationary)
        figures = PathFigures(pairs, self._parts, self._carried, [since], gaps, np.empty((count, len(movers), 3)),
                              np.empty((count, len(movers))), [], [], not self._carried and self.thesis_axes, [])
        if figures.rigid:           # the links' radii and the fixed lengths: the same at every pose
            figures.radii[:] = self._scene.radii.take(movers)
        return figures

    def keep_pose(self, figures: PathFigures, frames: np.ndarray, key: object) -> None:
        """Keep the figures of the pose the last ``check`` saw (at ``frames``, named ``key``):
        the box gaps of every pair, the moving bodies' centres and radii, their travel table."""
        s, i = self._scene, len(figures.keys)
        if self._pairs_now is not figures.pairs or self._parts is not figures.parts:
            raise ValueError("the path's parts changed while it was checked")
        gaps = self._gaps_now
        row = figures.gaps[i]
        if gaps is None:             # the broad phase skipped pairs: their gaps from the boxes
            figures.narrow.append(i - 1)
            row[:] = arrays.body_box_gaps(s.mid, s.half, figures.pairs.moving, figures.pairs.stationary)
        else:
            row[:] = gaps
        s.centres.take(self._movers, axis=0, out=figures.centres[i - 1])
        if not figures.rigid or not figures.tables:
            if not figures.rigid:
                s.radii.take(self._movers, out=figures.radii[i - 1])
            figures.tables.append(self._travel_table(frames))
        figures.keys.append(key)

    def path_ready(self, objects: Sequence[Polyhedron], carried: Collection[int] = ()) -> bool:
        """Whether the last ``check`` left the scene set up for these parts (the same parts where
        they were, none carried, as the thesis's checker): then
        ``keep_path`` can check a path's first pose too, with no ``check`` before it."""
        if self.checker != "thesis" or carried or self._pairs_now is None or self._pairs_for != (len(objects), ()):
            return False
        if self._parts_changed(objects, ()):
            # as ``check`` would: asking again would find the same objects and say unchanged
            self._rebuild(objects, ())
            return False
        return True

    def keep_path(self, figures: PathFigures, frames: np.ndarray, keys: Sequence[object],
                  speed: float) -> list[list[Finding] | None] | None:
        """``check`` and ``keep_pose`` of a path's poses together (the links at ``frames``
        (poses, links, 4, 4), the poses named ``keys``): the links placed at every pose by one
        product, then the box gaps of (pairs x poses) in a few numpy calls and the coarse test
        where the boxes are within its reach (a body's centre lies in its box: nowhere else can
        it pass), the arithmetic of the pose-by-pose ``check`` (the same numbers, bit for bit).
        Per pose its findings: the near pairs whose boxes meet get the fine test, every pose's
        at once (``_fine_at``). Every pair at every pose, so no broad phase is needed (the box
        gaps of a few thousand pairs are a few numpy calls). None when this does not apply: a
        part is carried (it moves with the hand), or the scene is not the one ``figures`` were
        made in."""
        if self._carried or self._pairs_now is not figures.pairs or self._parts is not figures.parts:
            return None
        s, pairs, nl, count = self._scene, figures.pairs, len(self._link_ks), len(frames)
        # every pose's frames side by side: one product places every vertex at every pose
        every = self._local_all @ frames[:, : self._n_frames, :3, :].transpose(3, 0, 1, 2).reshape(4, -1)
        place, centre = self._path_picks(count)
        placed = every.take(place)                                      # (vertices, 3 x poses)
        starts = self._layout.starts[:nl]
        lo = np.minimum.reduceat(placed, starts).reshape(nl, 3, count).transpose(1, 0, 2)
        hi = np.maximum.reduceat(placed, starts).reshape(nl, 3, count).transpose(1, 0, 2)
        # (3, bodies, poses): a coordinate's values side by side
        mid, half = np.empty((3, len(s.mid), count)), np.empty((3, len(s.mid), count))
        mid[:, nl:], half[:, nl:] = s.mid[nl:].T[:, :, None], s.half[nl:].T[:, :, None]
        np.multiply(np.add(lo, hi), 0.5, out=mid[:, :nl])
        np.multiply(np.subtract(hi, lo), 0.5, out=half[:, :nl])
        centres = every.take(centre)                                    # the links', (3, links, poses)
        m, st = pairs.moving, pairs.stationary          # nothing carried: every moving body is a link
        apart = mid.take(m, axis=1)                    # |mid_m - mid_s| - (half_m + half_s), in place
        apart -= mid.take(st, axis=1)
        np.abs(apart, out=apart)
        halves = half.take(m, axis=1)
        halves += half.take(st, axis=1)
        apart -= halves
        gaps = arrays.largest_of(apart)                                       # (pairs, poses)
        # the coarse test (``check_pairs``'s arithmetic) only where the boxes are within its
        # reach (+1 mm): a body's centre lies in its box, so it is never nearer than the box
        reach = s.radii.take(m) + margin(speed)
        at = np.flatnonzero(gaps <= (reach + 1.0)[:, None])             # (pair, pose) flat
        pair = at // count
        pose = at - pair * count
        st_at = st.take(pair) * count + pose
        coarse = np.abs(centres.reshape(3, -1).take(m.take(pair) * count + pose, axis=1)
                        - mid.reshape(3, -1).take(st_at, axis=1))
        coarse -= half.reshape(3, -1).take(st_at, axis=1)
        near = arrays.largest_of(coarse) <= reach.take(pair)
        pair, pose = pair[near], pose[near]
        i = len(figures.keys)
        figures.gaps[i: i + count] = gaps.T
        figures.centres[i - 1: i - 1 + count] = centres.transpose(2, 1, 0)
        if not figures.rigid:
            figures.radii[i - 1: i - 1 + count] = s.radii.take(self._movers)
            figures.tables.extend(self._travel_table(pose_frames) for pose_frames in frames)
        elif not figures.tables:                      # the fixed lengths, once
            figures.tables.append(self._travel_table(frames[0]))
        figures.keys.extend(keys)
        # each pose's near pairs, by position (as ``check`` finds them); the fine test of those
        # whose boxes meet, every pose's at once
        codes = np.full(len(pair), NEAR)
        fined = np.flatnonzero(gaps[pair, pose] <= EPS)
        if len(fined):
            hit = fined[self._fine_at(frames, pose.take(fined), pair.take(fined))]
            codes[hit] = COLLIDES
            figures.collided.append((i - 1 + pose.take(hit)) * len(pairs.moving) + pair.take(hit))
        order = np.argsort(pose, kind="stable")          # by pose, then by pair (as found)
        bounds = np.searchsorted(pose.take(order), np.arange(count + 1)).tolist()
        said = list(zip(pair.take(order).tolist(), codes.take(order).tolist()))
        return [self.world.findings_at(pairs, tuple(said[a:b])) if b > a else []
                for a, b in itertools.pairwise(bounds)]

    def _path_picks(self, count: int) -> tuple[np.ndarray, np.ndarray]:
        """Flat indices into the product of ``keep_path`` (rows, poses x 3 x frames) of every
        vertex's coordinates in its own frame, (vertices, 3 x poses), and of the links' centres,
        (3, links, poses); kept per number of poses."""
        kept = self._picks.get(count)
        if kept is None:
            width = 3 * self._n_frames
            rows = len(self._local)
            shift = (np.arange(count) * width)[None, :, None]
            place = self._own_flat - (np.arange(rows) * width)[:, None] + (np.arange(rows) * width * count)[:, None]
            centre = self._own_centre_pick - (np.arange(len(self.owners)) * width)[:, None]
            centre = centre + ((np.arange(len(self.owners)) + rows) * width * count)[:, None]
            kept = self._picks[count] = ((place[:, None, :] + shift).transpose(0, 2, 1).reshape(rows, -1),
                                         (centre[:, None, :] + shift).transpose(2, 0, 1).copy())
            if len(self._picks) > 64:
                self._picks.clear()
        return kept

    def keep_ends(self, figures: PathFigures | None, reached: int) -> None:
        """The path's pose ``reached`` (0 the pose before it) is where the next step starts, as
        ``swept(now=...)`` keeps it (nothing when there was nothing to sweep)."""
        self._ends = None if figures is None else (figures.keys[reached], figures.parts, figures.carried,
                                                   figures.gaps[reached], None, None)

    def swept_path(self, frames: np.ndarray, turned: np.ndarray, objects: Sequence[Polyhedron],
                   figures: PathFigures, start: Callable[[], np.ndarray] | None = None,
                   frames_at: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None,
                   figure_order: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``swept`` for every step of a path at once: the moments of every step in order, each
        with its step (an index into the path) and its row of pairs to check. ``frames``
        (steps, links, 4, 4) are the poses each step ends at, ``turned`` (steps, 6) the joints'
        turns (radians), ``figures`` what ``keep_pose`` kept of them. The same decision as
        ``swept``, step by step, in a few dozen numpy calls for the path. ``frames_at``: the link
        frames at moments of the steps (their steps and fractions of them); with it, a link x
        part pair whose link's hulls over the step keep clear of the part (``hulls_clear``)
        needs no moment; ``start``: the link frames at the first step's start. ``figure_order``:
        a step's findings are said in Fig. C-12's order (the 1985 rules), not as found."""
        never = np.zeros(0, dtype=np.intp), np.zeros(0), np.zeros((0, 0), dtype=bool)
        self.glancing = None
        count = len(figures.keys) - 1
        if not count:
            return never
        pairs, turns, frames = figures.pairs, np.abs(turned[:count]), frames[:count]
        before, after = figures.gaps[:count], figures.gaps[1: count + 1]
        movers = self._movers
        ruled = len(movers) * len(self._free)
        linked = self._link_pairs(pairs)
        tables = figures.tables
        table = tables[0] if figures.rigid else np.stack(tables[:count])
        far = table * turns[:, None, :]                                  # (steps, movers, joints)
        widths = self._ruled_widths(objects, pairs.stationary[:ruled]) if ruled else np.zeros(0)
        both = before + after
        both -= 2.0 * EPS
        if figures.narrow and ruled:     # the pairs the broad phase keeps, by the fixed lengths' reach
            narrow = figures.narrow
            reach = far[narrow].sum(axis=2).max(axis=1)
            near = arrays.candidates_batch(figures.centres[narrow], figures.radii[narrow].max(axis=1) + reach,
                                     self._free_lo, self._free_hi)
            both[narrow, :ruled] = np.where(np.tile(near, (1, len(movers))), both[narrow, :ruled], np.inf)
        # the bound from where the bodies are now, of every step. ``swept`` first tries the fixed
        # lengths (never smaller: a step they clear it clears too) only to skip this, which saves
        # nothing on a whole path
        far = self._path_terms(frames, turns, far, figures.centres[:count], figures.radii[:count])
        bound, relative = self._path_bounds(far, linked[2])
        # only the parts' pairs whose boxes a step's reach can close go on (and the link pairs)
        near = np.flatnonzero((both[:, :ruled] <= bound.max(axis=1)[:, None]).any(axis=0))
        cols = np.concatenate([near, linked[0]])
        n = len(near)
        both, before = both[:, cols], before[:, cols]
        moved = bound.take(pairs.moving.take(near), axis=1)
        closing = bound.take(linked[1][:, 0], axis=1) + bound.take(linked[1][:, 1], axis=1)
        # a pair whose boxes can meet and that moves past its part's width (a link pair: turns
        # past the proximal link's width) needs moments; a step with none needs none. (``swept``'s
        # other tests follow: such a pair moves past the thinnest part, and a link pair's turn
        # by the fixed lengths is never less than by this bound)
        pick = np.concatenate([both[:, :n] <= moved, (both[:, n:] <= closing) & (relative > 1.0)], axis=1)
        widths = widths.take(near)
        k = np.flatnonzero(np.any(pick[:, :n] & (moved > np.minimum(widths, GLANCE)), axis=1)
                           | np.any(pick[:, n:], axis=1))
        if not len(k):
            return never
        # the moments the pairs picked need (a pair is found where it was), less the needless pairs
        needless = self.needless(pick, cols, n, (far, turns), figures, (frames, start, frames_at), figure_order)
        glance = pick[:, :n] & (moved > GLANCE)
        if needless is not None:
            glance &= ~needless[:, :n]
        step, col = np.nonzero(glance)
        self.glancing = at_risk((step, near.take(col)), moved[step, col], before[step, col], both[step, col],
                                len(pairs.moving), figures.collided)
        if needless is not None:          # the steps with a pair left (a step's moments are its own)
            k = k.compress((pick.take(k, axis=0) & ~needless.take(k, axis=0)).any(axis=1))
            if not len(k):
                return never[0], never[1], np.zeros((0, len(pairs.moving)), dtype=bool)
        reach = np.concatenate([moved, closing], axis=1)
        need = np.concatenate([moved / widths, relative], axis=1)
        step, moments, rows = arrays.moments(pick[k], cols, before[k], both[k], reach[k], need[k], len(pairs.moving))
        if needless is not None:
            rows[:, cols] &= ~needless[k.take(step)]
            kept = np.flatnonzero(rows.any(axis=1))
            step, moments, rows = step.take(kept), moments.take(kept), rows.take(kept, axis=0)
        return k.take(step), moments, rows

    def _path_bounds(self, terms: np.ndarray, weights: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Each body's bound (steps, bodies; 0 for the still ones) and the link pairs' steps
        needed (steps, link pairs) from the (steps, movers, joints) travel terms."""
        nl = len(self._link_ks)
        bound = np.zeros((len(terms), len(self._scene.radii)))
        bound[:, self._movers] = terms.sum(axis=2)
        flat = terms[:, :nl].reshape(len(terms), -1, 1)
        relative: np.ndarray = (weights[None] @ flat)[..., 0]          # one matrix-vector product a step
        return bound, relative

    def _path_terms(self, frames: np.ndarray, turns: np.ndarray, far: np.ndarray, centres: np.ndarray,
                    radii: np.ndarray) -> np.ndarray:
        """(steps, movers, joints): how far each joint's turn can carry each moving body over
        each step, from its distance from the joint's axis at the step's end pose (``frames``
        (steps, links, 4, 4), the bodies' ``centres`` and ``radii`` there), grown by what the
        later joints can add (``far``: the same from the fixed lengths, ``_travel_table``
        times the turns)."""
        if not self.thesis_axes:
            return far
        d = centres[:, :, None, :] - frames[:, None, 1: self._n_frames, :3, 3]
        # the distance from each joint's axis (a point turns on a circle about it, not about
        # the frame's origin): the part of d square to the axis
        axes = frames.reshape(len(frames), -1).take(arrays.AXIS_FLAT, axis=1)  # (steps, joints, 3)
        along = np.einsum("smjk,sjk->smj", d, axes)
        square = np.maximum(np.einsum("smjk,smjk->smj", d, d) - along * along, 0.0)
        now = np.sqrt(square) + radii[:, :, None]
        # far @ LATER: the later joints
        terms: np.ndarray = np.minimum(far, (now + far @ arrays.LATER) * turns[:, None, :])
        return terms

    def _kept_gaps(self, kept: tuple[object, ...] | None, since: object, at: np.ndarray,
                   m: np.ndarray, st: np.ndarray) -> np.ndarray:
        """The box gaps at the step's start of the pairs at positions ``at`` (bodies ``m``, ``st``):
        those kept by the last ``swept`` call when it named that pose, else 0."""
        if since is None or kept is None or kept[0] != since or kept[1] is not self._parts \
                or kept[2] != self._carried:
            return np.zeros(len(at))
        if kept[3] is None:                       # the boxes were kept (copies)
            return arrays.body_box_gaps(kept[4], kept[5], m, st)  # type: ignore[arg-type]
        gaps: np.ndarray = kept[3].take(at)  # type: ignore[attr-defined]
        return gaps

    def _part_pairs(self, reach: float, objects: Sequence[Polyhedron], since: object,
                    kept: tuple[object, ...] | None) -> tuple[np.ndarray, ...]:
        """The parts' pairs (rules 1 and 2) a body moving ``reach`` could meet: their positions,
        moving bodies, parts, box gaps at start plus end (less 2 EPS), the parts' widths (at
        least 1 mm) and the gaps at the start."""
        pairs, s, movers = self._pairs_now, self._scene, self._movers
        assert pairs is not None
        gaps = self._gaps_now
        ruled = len(movers) * len(self._free)
        if gaps is not None:
            sel, m, st, after = self._all_pairs(ruled), pairs.moving[:ruled], pairs.stationary[:ruled], gaps[:ruled]
            widths = self._ruled_widths(objects, st)
        else:
            near = self._candidates(movers, reach)
            sel = (self._sel_parts(pairs, ruled, len(self._free))[0] + near).ravel()
            m, st = pairs.moving.take(sel), pairs.stationary.take(sel)
            after = arrays.body_box_gaps(s.mid, s.half, m, st)
            widths = np.maximum(self._widths(objects, st), 1.0)
        before = self._kept_gaps(kept, since, sel, m, st)
        return sel, m, st, before + after - 2.0 * EPS, widths, before

    def _past_width(self, bound: np.ndarray, objects: Sequence[Polyhedron], since: object,
                    kept: tuple[object, ...] | None, keep: bool, poses: tuple[np.ndarray, object]) -> bool:
        """``_risky`` when every pair's box gaps were measured, of the pairs that move past their part's
        width or ``GLANCE`` (``bound`` of its mover), kept with the bounds kept (``keep``)."""
        pairs, gaps = self._pairs_now, self._gaps_now
        assert pairs is not None and gaps is not None
        ruled = len(self._movers) * len(self._free)
        widths = self._ruled_widths(objects, pairs.stationary[:ruled])
        got = self._past_kept.get(id(bound))
        if got is None or got[0] is not bound or got[1] is not widths:
            moved = bound.take(pairs.moving[:ruled])
            mask = moved > np.minimum(widths, GLANCE)
            past, reach = np.flatnonzero(mask), np.where(mask, moved, -np.inf)   # reach: -inf where not past
            got = (bound, widths, past, moved.take(past), pairs.moving.take(past), pairs.stationary.take(past), reach)
            if keep:
                if len(self._past_kept) >= 16:
                    self._past_kept.clear()
                self._past_kept[id(bound)] = got     # the entry holds the bound: its id stays its own
        past, moved, m, st, reach = got[2:]
        if not len(past):
            return False
        if (before := self._kept_row(kept, since)) is not None:       # most steps: every pair at once
            return self._meet_any(before, gaps, reach, widths, (poses[0], since, poses[1]))
        return self._risky(past, moved, self._kept_gaps(kept, since, past, m, st), gaps.take(past), widths.take(past),
                           (poses[0], since, poses[1]))

    def _ruled_widths(self, objects: Sequence[Polyhedron], st: np.ndarray) -> np.ndarray:
        """The widths (at least 1 mm) of the parts of the pairs whose parts are ``st``
        (rules 1 and 2, every pair), measured once per set of parts."""
        kept = self._pair_widths
        if kept is None or kept[0] is not self._parts or len(kept[1]) != len(st):
            kept = self._pair_widths = (self._parts, np.maximum(self._widths(objects, st), 1.0))
        return kept[1]

    def _link_gaps(self, linked: tuple[np.ndarray, np.ndarray, np.ndarray], since: object,
                   kept: tuple[object, ...] | None) -> tuple[np.ndarray, ...]:
        """Link x link pairs (rule 3), laid out as ``_part_pairs`` lays out the parts' pairs.

        Both boxes move, so they close by at most the sum of the two bounds; the moments a
        pair needs are the distal link's travel relative to the proximal one (only the joints
        between them turn it) over the proximal link's width (``_link_pairs``), the stationary
        part of the pair as in rules 1 and 2."""
        s = self._scene
        at, i, j = linked[0], linked[1][:, 0], linked[1][:, 1]
        gaps = self._gaps_now
        after = gaps.take(at) if gaps is not None else arrays.body_box_gaps(s.mid, s.half, i, j)
        before = self._kept_gaps(kept, since, at, i, j)
        return at, i, j, before + after - 2.0 * EPS, np.zeros(0), before

    def _all_pairs(self, count: int) -> np.ndarray:
        """0 .. count - 1, kept."""
        if self._every is None or len(self._every) != count:
            self._every = np.arange(count)
        return self._every

    def _sweep_bounds(self, frames: np.ndarray, turned: np.ndarray, tight: bool = True) -> np.ndarray:
        """How far any point of each moving body can travel over a step of these joint turns.

        ``tight``: the distances from the joints' axes taken from where the bodies are now,
        grown by how far the later joints can carry them over the step (a few more numpy
        calls; without it the fixed lengths of ``_travel_table``)."""
        far = self._travel_table(frames) * turned
        travel: np.ndarray = (self._sweep_terms(frames, turned, far) if tight else far).sum(axis=1)
        return travel

    def _sweep_terms(self, frames: np.ndarray, turned: np.ndarray, far: np.ndarray) -> np.ndarray:
        """(movers, joints): ``_path_terms`` of the one step ending at ``frames`` (links, 4, 4),
        the moving bodies where they are now."""
        if not self.thesis_axes:
            return far
        s, movers = self._scene, self._movers
        terms: np.ndarray = self._path_terms(frames[None], np.asarray(turned, dtype=float)[None], far[None],
                                             s.centres.take(movers, axis=0)[None], s.radii.take(movers)[None])[0]
        return terms

    def _link_pairs(self, pairs: _Pairs) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The link x link pairs (rule 3) of ``pairs``: their positions, their (distal, proximal)
        links, and weights that turn the links' (links, joints) travel terms, flattened, into
        each pair's steps needed: the distal link's travel from the joints after the proximal
        link's frame (the others carry both alike) over the proximal link's width."""
        kept = self._linked
        if kept is not None and kept[0] is pairs:
            return kept[1]
        nl, joints = len(self._link_ks), self._n_frames - 1
        at = np.flatnonzero((pairs.moving < nl) & (pairs.stationary < nl))
        ij = np.column_stack([pairs.moving.take(at), pairs.stationary.take(at)])
        weights = np.zeros((len(at), nl, joints))
        for row, (i, j) in enumerate(ij.tolist()):
            weights[row, i, int(self.owners[j]):] = 1.0 / max(float(self._link_widths[j]), 1.0)
        found = (at, ij, weights.reshape(len(at), nl * joints))
        self._linked = (pairs, found)
        return found

    def _travel_table(self, frames: np.ndarray) -> np.ndarray:
        """(movers, joints): how far a point of each moving body can be from each joint's axis.

        Joint j turns about an axis through frame j's origin; a body carried by frame k is
        no farther from it than the chain from frame j's origin to frame k's, plus the body's
        farthest point from frame k's origin: lengths no motion changes (kept per set of
        bodies; a carried part's measured at each call)."""
        if not self.thesis_axes:
            return self._reach_table(frames)
        movers = self._movers
        nl = len(self._link_ks)
        origins = frames[1: self._n_frames, :3, 3]
        table = self._table
        if table is None or table[0] is not self._parts:
            links = origins[1:] - origins[:-1]
            chain = np.concatenate([[0.0], np.cumsum(np.sqrt(np.einsum("jk,jk->j", links, links)))])
            owner = np.concatenate([self.owners, np.full(len(movers) - nl, self._n_frames - 1)])
            mask = np.arange(len(chain))[None, :] < owner[:, None]
            last = np.maximum(owner - 1, 0)
            starts = np.concatenate([[0], np.cumsum([2 * k for k in self._link_ks])[:-1]]).astype(np.intp)
            own = np.sqrt(np.maximum.reduceat(np.einsum("ij,ij->i", self._local, self._local), starts))
            chain_part = np.where(mask, chain[last][:, None] - chain[None, :], 0.0)
            table = self._table = (self._parts, chain_part, mask, own, chain_part[:nl] + own[:, None] * mask[:nl])
        _, chain_part, mask, far, links_only = table
        if len(movers) == nl:        # nothing carried: the same every step
            return links_only
        held = self._held_reach(origins[-1])
        reach: np.ndarray = chain_part + np.concatenate([far, held])[:, None] * mask
        return reach

    def _reach_table(self, frames: np.ndarray) -> np.ndarray:
        """(movers, joints) for frames without the thesis's axes: every point of the arm and
        what it carries is no farther from any joint's axis (which passes through a frame
        origin of the chain) than the chain's length (between frame origins: no joint changes
        it) plus the farthest point of any body from its own frame's origin."""
        movers = self._movers
        origins = frames[: self._n_frames, :3, 3]
        links = origins[1:] - origins[:-1]
        chain = float(np.sqrt(np.einsum("jk,jk->j", links, links)).sum())
        local = self._local   # each link's vertices in its own frame
        extent = float(np.sqrt(np.einsum("ij,ij->i", local, local)).max(initial=0.0))
        if len(movers) > len(self._link_ks):
            extent = max(extent, float(self._held_reach(origins[-1]).max()))
        return np.full((len(movers), self._n_frames - 1), chain + extent)

    def _held_reach(self, clamp: np.ndarray) -> np.ndarray:
        """Each carried part's farthest point from the clamp frame's origin ``clamp``."""
        d = self._scene.vertices[self._held_rows] - clamp
        reach: np.ndarray = np.sqrt(np.maximum.reduceat(np.einsum("ij,ij->i", d, d), self._held_starts))
        return reach

    def _thinnest(self, objects: Sequence[Polyhedron]) -> float:
        """The thinnest width of the free parts (measured once per set of parts)."""
        kept = self._thinnest_kept
        if kept is None or kept[0] is not self._parts:
            width = float(self._widths(objects, self._free).min()) if len(self._free) else math.inf
            kept = self._thinnest_kept = (self._parts, width)
        return kept[1]

    def _widths(self, objects: Sequence[Polyhedron], idx: np.ndarray) -> np.ndarray:
        """The thinnest widths of the scene's parts at indices ``idx``."""
        nl = len(self._link_ks)
        kept = self._part_widths
        if kept is None or kept[0] is not self._parts:       # measured once per set of parts
            kept = self._part_widths = (self._parts, np.full(len(self._scene.radii), np.nan))
        widths = kept[1]
        found: np.ndarray = widths.take(idx)
        missing = np.isnan(found)
        if missing.any():
            todo: dict[int, list[int]] = {}               # not kept, by their sides: each side count at once
            for i in np.unique(idx[missing]).tolist():
                p = objects[i - nl]
                thin = self._thin.get(id(p.vertices))
                if thin is not None and thin[0] is p.vertices:
                    widths[i] = thin[1]
                else:
                    todo.setdefault(p.k, []).append(i)
            if len(self._thin) > 4096:
                self._thin.clear()
            for k, at in todo.items():
                widths[at] = arrays.thicknesses(np.stack([objects[i - nl].vertices for i in at]), k)
                for i in at:
                    self._thin[id(objects[i - nl].vertices)] = (objects[i - nl].vertices, float(widths[i]))
            found = widths.take(idx)
        return found


_VERTICES = operator.attrgetter("vertices")

_NEVER = (np.zeros(0), np.zeros((0, 0), dtype=bool))    # ``swept``'s when no moment is needed (read-only)
for _empty in _NEVER:
    _empty.flags.writeable = False


def _same_objects(kept: tuple[Polyhedron, ...], objects: Sequence[Polyhedron]) -> bool:
    """Whether ``objects`` are the polyhedra ``kept``, in order: one tuple comparison in C, which
    takes an object as equal to itself at once. Two different polyhedra compare their fields:
    equal only when they share the same vertex array (the same shape where it is); else numpy
    cannot say whether two arrays are equal, and that is an answer too."""
    try:
        return kept == tuple(objects)
    except ValueError:
        return False


def _same_free(kept: tuple[Polyhedron, ...], objects: Sequence[Polyhedron], carried: tuple[int, ...]) -> bool:
    """``_same_objects`` but for the carried parts (object numbers ``carried``), which may be others."""
    now = list(objects)
    for c in carried:
        now[c - 1] = kept[c - 1]
    return _same_objects(kept, now)
