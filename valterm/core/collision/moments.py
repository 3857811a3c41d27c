"""Collision checks at many moments in one batch (issue 40): the fine test of the pairs at
risk at every moment of a path's steps, or at every pose of a path, run once.

``RobotScene`` keeps one scene: its links where the last pose put them, beside the parts.
For many moments at once a second scene is made for the call: the links' vertices at each
moment side by side (one product places them all), then the parts; a pair's bodies are
renumbered into it (a link's copy at the pair's moment, the part once). The box test and
the fine test of ``check_pairs`` then run once over every moment's pairs.

Before that a path's steps leave out the (step, pair) items no moment can find anything at
(``needless``): a pair colliding at both poses of a step, and a link x part pair whose
link's hulls over the step keep clear of the part (``hulls_clear``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable

import numpy as np

from valterm.core.collision.arrays import HAIR, sweep_bends
from valterm.core.collision.glance import GLANCE, Glancing, cleared
from valterm.core.collision.thesis import COLLIDES, EPS, SEPARATED, Layout, Scene, fine, largest_of_xyz

if TYPE_CHECKING:
    from valterm.core.collision.world import CollisionWorld, Finding, _Pairs


@dataclass
class PathFigures:
    """What the swept check keeps of a path's poses (``RobotScene.path_figures``, ``keep_pose``)."""

    pairs: _Pairs
    parts: object
    carried: tuple[int, ...]
    keys: list[object]             # the poses' names, the pose before the path first
    gaps: np.ndarray               # (poses + 1, pairs) box gaps, the pose before the path first
    centres: np.ndarray            # (poses, movers, 3) the moving bodies' centres and radii
    radii: np.ndarray
    tables: list[np.ndarray]       # their travel tables (``_travel_table``; one when ``rigid``)
    narrow: list[int]              # the poses whose check left pairs to the broad phase
    rigid: bool                    # only links move, on the thesis's axes: radii and table kept once
    collided: list[np.ndarray]     # step x pairs + pair of the pairs that collide at a step's end pose


class MomentsBatch:
    """``RobotScene``'s checks of many moments at once (a mixin: it reads the scene's arrays)."""

    world: CollisionWorld
    _pairs_now: _Pairs | None
    _carried: tuple[int, ...]
    _scene: Scene
    _layout: Layout
    _link_ks: tuple[int, ...]
    _nl_rows: int
    _n_frames: int
    _local_h: np.ndarray
    _local: np.ndarray
    _held_at: np.ndarray
    _held_starts: np.ndarray
    _local_centres: np.ndarray
    _local_radii: np.ndarray
    _apart_normals: np.ndarray
    _apart_offsets: np.ndarray
    owners: np.ndarray
    glancing: Glancing | None
    _parts: tuple[np.ndarray, ...] | None
    # how far apart link x part pairs were at least at the last few poses: (the parts and the
    # pairs then, pose name -> pair -> mm)
    _apart_kept: tuple[object, object, dict[object, dict[int, float]]] | None = None
    # the last fine test's face-plane figures: (the links' frames, links, parts, mm beyond)
    _apart_now: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None = None
    _ends_frames: tuple[object, np.ndarray] | None = None   # the last path's end pose: its name, link frames
    _glance_left: Glancing | None = None     # the pairs ``poses_clear`` last left (``RobotScene.swept``'s)
    _apart_kept_tables: tuple[object, object, tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]] | None = None
    # ``RobotScene.swept_path`` leaves out the (step, pair) items that need no moment (``needless``);
    # off only to show that it changes nothing said
    prune_moments = True

    def _path_picks(self, count: int) -> tuple[np.ndarray, np.ndarray]:
        raise NotImplementedError

    def apart_kept(self) -> dict[object, dict[int, float]]:
        """How far apart link x part pairs were found at least at the last few poses (by the
        pose's name, pair -> mm), for the parts and pairs there are now."""
        kept = self._apart_kept
        if kept is None or kept[0] is not self._parts or kept[1] is not self._pairs_now:
            kept = self._apart_kept = (self._parts, self._pairs_now, {})
        if len(kept[2]) > 4:                      # a path's two ends and the pose by pose steps'
            del kept[2][next(iter(kept[2]))]
        return kept[2]

    def poses_clear(self, frames: np.ndarray, pairs: list[int], b: list[float], start: list[float],
                    end: list[float], since: object, now: object) -> bool:
        """Can none of the link x part pairs ``pairs`` (positions) meet in the step from the pose named
        ``since`` to the one named ``now`` (the links at ``frames`` there), its points moving at
        most ``b``, its boxes ``start`` and ``end`` apart at the two? Not where it is at least
        ``d0`` apart at the start and ``d1`` at the end with ``d0 + d1 > bound`` (conservative
        advancement from either end leaves nothing between; ``glance.cleared``). Where the step
        before measured the start (``apart_kept``) and that alone clears the step, the end is
        ``d0 - bound`` apart at least, not measured; else it is measured (``apart_at``) and kept
        for the next step. Python floats: a pose by pose step has a pair or two."""
        known = self.apart_kept()
        at0 = {} if since is None else known.get(since, {})
        at1: dict[int, float] = {} if now is None else known.setdefault(now, {})
        d0 = [max(g, at0.get(q, 0.0)) for g, q in zip(start, pairs)]
        d1 = [max(g, at1.get(q, 0.0)) for g, q in zip(end, pairs)]
        ask = [i for i, q in enumerate(pairs) if q not in at1 and d0[i] <= b[i]]
        seen = self._apart_now          # what the fine test of the pose found of the link's face planes
        if ask and seen is not None and seen[0] is frames:
            assert self._pairs_now is not None
            pm, ps = self._pairs_now.moving, self._pairs_now.stationary
            beyond = dict(zip(zip(seen[1].tolist(), seen[2].tolist()), seen[3].tolist()))
            for i in ask:
                d1[i] = max(d1[i], beyond.get((pm.item(pairs[i]), ps.item(pairs[i])), 0.0))
            ask = [i for i in ask if d0[i] + d1[i] <= b[i]]
        if ask:
            found = self.apart_at(frames[None], np.zeros(len(ask), dtype=np.intp),
                                  np.array([pairs[i] for i in ask], dtype=np.intp)).tolist()
            for i, d in zip(ask, found):
                d1[i] = max(d1[i], d)
        left = []
        for i, q in enumerate(pairs):
            at1[q] = d1[i] = max(at1.get(q, 0.0), d1[i], d0[i] - b[i])
            if d0[i] + d1[i] <= b[i]:
                left.append(i)
        if left:              # the pairs left, as ``clear_glancing`` would leave them
            assert self._pairs_now is not None
            got = np.array([pairs, b, d0, d1]).take(left, axis=1)
            self._glance_left = Glancing(np.zeros(len(left), dtype=np.intp), got[0].astype(np.intp), got[1], got[2],
                                         got[3], len(self._pairs_now.moving), True)
        return not left

    def _kept_row(self, kept: tuple[object, ...] | None, since: object) -> np.ndarray | None:
        """Every pair's box gaps at the step's start as the last ``swept`` call kept them, when
        it named that pose and measured them all (else None: ``_kept_gaps``)."""
        if since is None or kept is None or kept[0] != since or kept[1] is not self._parts \
                or kept[2] != self._carried or kept[3] is None:
            return None
        row: np.ndarray = kept[3]  # type: ignore[assignment]
        return row

    def _meet_any(self, before: np.ndarray, gaps: np.ndarray, reach: np.ndarray, widths: np.ndarray,
                  poses: tuple[np.ndarray, object, object]) -> bool:
        """``_risky`` of the ruled pairs (the first ``len(reach)`` positions), their box gaps ``before``
        and ``gaps`` at the step's poses, moving ``reach`` (-inf where not past their width): whether
        a pair's boxes can meet over every pair at once, no take of those past their width."""
        self._glance_left = None
        ruled = len(reach)
        room = before[:ruled] + gaps[:ruled]
        room -= 2.0 * EPS
        meet = (room <= reach).nonzero()[0]     # flatnonzero's, without its Python wrappers
        return bool(len(meet)) and self._met(meet, reach, before, gaps, widths, poses)

    def _risky(self, sel: np.ndarray, moved: np.ndarray, before: np.ndarray, after: np.ndarray,
               widths: np.ndarray, poses: tuple[np.ndarray, object, object]) -> bool:
        """Does a parts' pair (positions ``sel``, moving ``moved``, boxes ``before`` and ``after`` apart
        at the poses) need moments: its boxes can meet and it moves past its part's width, or past
        ``GLANCE`` where its poses do not clear it (``poses_clear``: the links at ``poses[0]``, the
        poses named ``poses[1:]``; ``_glance_left`` the pairs it leaves when none is past its width)?
        With a part carried, past the width only (no glancing check)."""
        self._glance_left = None
        meet = np.flatnonzero(before + after - 2.0 * EPS <= moved)
        if not len(meet):
            return False
        return self._met(meet, moved, before, after, widths, poses, sel)

    def _met(self, meet: np.ndarray, moved: np.ndarray, before: np.ndarray, after: np.ndarray, widths: np.ndarray,
             poses: tuple[np.ndarray, object, object], sel: np.ndarray | None = None) -> bool:
        """``_risky`` of the pairs ``meet`` (indices into the other arrays) whose boxes can meet, their
        positions ``sel`` (``meet`` itself without). Python floats: a pose by pose step has a pair
        or two (an item read alone, not a take of a few)."""
        at = meet.tolist()
        reach = [moved.item(i) for i in at]
        wide = any(m > widths.item(i) for m, i in zip(reach, at))
        if wide or self._carried:
            return wide
        far = [k for k, m in enumerate(reach) if m > GLANCE]
        if not far:
            return False
        where = at if sel is None else [sel.item(i) for i in at]
        return not self.poses_clear(poses[0], [where[k] for k in far], [reach[k] for k in far],
                                    [before.item(at[k]) for k in far], [after.item(at[k]) for k in far], *poses[1:])

    def clear_glancing(self, frames: np.ndarray, start: Callable[[], np.ndarray], since: object, now: object) -> None:
        """Drop from ``glancing`` the pairs their poses clear (``poses_clear``'s test, ``glance.cleared``);
        the others keep how far apart they are there. Each end pose's distances measured once
        (``apart_at``, the face planes), not once per step it ends, and where ``apart_kept``
        has them not at all.

        ``frames``: (steps, links, 4, 4), each step's end pose; ``start``: the first step's
        start pose's frames (asked for only when needed); ``since`` and ``now`` name the first
        step's start pose and the last step's end pose (how far apart the pairs are there is
        kept for the step that starts at it). Nothing carried."""
        g = self.glancing
        if g is None or self._carried:
            return
        known, n, last = self.apart_kept(), g.pairs, len(frames)
        d0, d1 = np.maximum(g.start, 0.0), np.maximum(g.end, 0.0)
        # (pose, pair) -> how far apart, what is kept of the path's two ends
        pose = np.concatenate([g.step, g.step + 1])
        key = pose * n + np.concatenate([g.pair, g.pair])
        had = np.full(len(key), -1.0)
        for end, name in ((0, since), (last, now)):
            kept = None if name is None else known.get(name)
            rows = np.flatnonzero(pose == end)
            if kept and len(rows):
                had[rows] = [kept.get(q, -1.0) for q in (key.take(rows) % n).tolist()]
        ask, where = np.unique(key[had < 0.0], return_inverse=True)
        if len(ask):
            used, moment = np.unique(ask // n, return_inverse=True)
            ends_kept = self._ends_frames      # the last path's end pose is most often this one's start
            first = ends_kept[1] if ends_kept is not None and ends_kept[0] == since else start()
            at = np.concatenate([first[None], frames]) if used[0] == 0 else frames
            had[had < 0.0] = self.apart_at(at.take(used - (0 if used[0] == 0 else 1), axis=0), moment,
                                           ask % n, True).take(where)
        d0, d1 = np.maximum(d0, had[: len(g.step)]), np.maximum(d1, had[len(g.step):])
        ends = np.flatnonzero(g.step == last - 1)
        self._ends_frames = None if now is None else (now, frames[last - 1])
        kept_now: dict[int, float] = {} if now is None else known.setdefault(now, {})
        for q, d in zip(g.pair.take(ends).tolist(), d1.take(ends).tolist()):
            kept_now[q] = max(kept_now.get(q, 0.0), d)
        self.glancing = cleared(g, d0, d1)

    def collisions_at(self, frames: np.ndarray, rows: np.ndarray, steps: np.ndarray | None = None,
                      clear: np.ndarray | None = None) -> list[list[Finding]] | None:
        """``collisions_between`` at many moments in one batch (``_fine_at``): the links at
        ``frames`` (moments, links, 4, 4), the pairs of each moment's row (moments, pairs); per
        moment, its collisions. None with a part carried (it moves with the clamp:
        ``collisions_between`` moment by moment).

        ``steps``: the step of each moment (a step's moments together, in order). A step says a
        collision once, so a pair found at one of its moments is not looked for at the later
        ones: the moments go in rounds (each step's first, second, next two, next four ..., the
        rest at once after a round that found none).

        ``clear``: room for each (moment, pair) of ``rows`` (``np.nonzero``'s order) to be told how
        far apart the pair is at least there (``_fine_at``; 0 where not known)."""
        at, p = np.nonzero(rows)
        return self.collisions_of(frames, at, p, steps, clear)

    def collisions_of(self, frames: np.ndarray, at: np.ndarray, p: np.ndarray, steps: np.ndarray | None = None,
                      clear: np.ndarray | None = None, few: bool = False) -> list[list[Finding]] | None:
        """``collisions_at`` of the (moment ``at[i]``, pair ``p[i]``) items, by moment. ``few``:
        a moment has few items, each a link and a part (``_few_at`` first)."""
        pairs = self._pairs_now
        assert pairs is not None
        if self._carried:
            return None
        fine_at = self._few_at if few else self._fine_at
        if steps is None:
            hits = np.flatnonzero(fine_at(frames, at, p, clear))
        else:
            hits = self._first_hits(frames, at, p, steps, clear, fine_at)
        found: list[list[tuple[int, int]]] = [[] for _ in range(len(frames))]
        for k, q in sorted(zip(at.take(hits).tolist(), p.take(hits).tolist())):
            found[k].append((q, COLLIDES))
        return [self.world.findings_at(pairs, tuple(h)) if h else [] for h in found]

    def _first_hits(self, frames: np.ndarray, at: np.ndarray, p: np.ndarray, steps: np.ndarray,
                    clear: np.ndarray | None = None, fine_at: _FineAt | None = None) -> np.ndarray:
        """Of the (moment ``at[i]``, pair ``p[i]``) items, those that collide where their pair
        has not collided at an earlier moment of the same step (``collisions_at``'s rounds);
        ``clear`` as ``_fine_at``'s (0 for the items not looked at: their pair has collided)."""
        if clear is not None:
            clear[:] = 0.0
        fine_at = self._fine_at if fine_at is None else fine_at
        count = len(frames)
        first = np.searchsorted(steps, steps)            # each moment's step's first moment
        rank = (np.arange(count) - first).take(at)
        pair_in_step = steps.take(at) * (int(p.max(initial=0)) + 1) + p
        done = np.zeros(0, dtype=np.intp)
        hits = []
        low, high = 0, 1
        while low <= int(rank.max(initial=-1)):
            now = np.flatnonzero((rank >= low) & (rank < high) & ~np.isin(pair_in_step, done))
            if len(now):
                used = np.unique(at.take(now))
                renumber = np.zeros(count, dtype=np.intp)
                renumber[used] = np.arange(len(used))
                apart = None if clear is None else np.zeros(len(now))
                hit = now[fine_at(frames.take(used, axis=0), renumber.take(at.take(now)), p.take(now), apart)]
                if clear is not None and apart is not None:
                    clear[now] = apart
                hits.append(hit)
                done = np.union1d(done, pair_in_step.take(hit))
            # a round that found nothing would save nothing by more rounds: the rest at once
            low, high = high, (2 * high if len(now) and len(hit) else count)
        if not hits:
            return np.zeros(0, dtype=np.intp)
        every = np.concatenate(hits)
        # a pair hit at two moments of one round: its first
        _, keep = np.unique(pair_in_step.take(every) * count + at.take(every), return_index=True)
        ordered = every[keep]
        _, first_of_pair = np.unique(pair_in_step.take(ordered), return_index=True)
        return np.sort(ordered[first_of_pair])

    def meeting(self, frames: np.ndarray, rows: np.ndarray, held: np.ndarray | None) -> np.ndarray:
        """Per moment (the links at ``frames`` (moments, links, 4, 4), the carried parts'
        vertices ``held`` (moments, vertices, 3)): do the boxes of a pair of its row meet
        (within a hair)? The fine test finds a collision only where the boxes meet, so the
        other moments need no check. Call after ``check`` (the free parts are where it saw them)."""
        pairs, s = self._pairs_now, self._scene
        assert pairs is not None
        count, nl = len(frames), len(self._link_ks)
        # every moment's frames side by side, one product (as ``keep_path``); (bodies, moments, 3) boxes
        placed = (self._local_h @ frames[:, : self._n_frames, :3, :].transpose(3, 0, 1, 2).reshape(4, -1)
                  ).take(self._path_picks(count)[0])
        starts = self._layout.starts[:nl]
        lo: np.ndarray = np.empty((len(s.mid), count, 3))
        hi: np.ndarray = np.empty((len(s.mid), count, 3))
        lo[nl:], hi[nl:] = s.lo[nl:, None], s.hi[nl:, None]
        lo[:nl] = np.minimum.reduceat(placed, starts).reshape(nl, 3, count).transpose(0, 2, 1)
        hi[:nl] = np.maximum.reduceat(placed, starts).reshape(nl, 3, count).transpose(0, 2, 1)
        if held is not None and len(self._held_at):
            lo[self._held_at] = np.minimum.reduceat(held, self._held_starts, axis=1).transpose(1, 0, 2)
            hi[self._held_at] = np.maximum.reduceat(held, self._held_starts, axis=1).transpose(1, 0, 2)
        at, p = np.nonzero(rows)
        a, b = pairs.moving.take(p) * count + at, pairs.stationary.take(p) * count + at
        low, high = lo.reshape(-1, 3), hi.reshape(-1, 3)
        gap = np.maximum(low.take(b, axis=0) - high.take(a, axis=0), low.take(a, axis=0) - high.take(b, axis=0))
        meet = np.zeros(count, dtype=bool)
        meet[at[largest_of_xyz(gap) <= EPS + HAIR]] = True
        return meet

    def _few_at(self, frames: np.ndarray, at: np.ndarray, p: np.ndarray, clear: np.ndarray | None = None
                ) -> np.ndarray:
        """``_fine_at`` where a moment has few items, each a link and a part: each item's link
        placed alone (its vertices by its frame at the moment), its box and face planes
        against the part's; only the items those leave go to ``_fine_at`` (which places
        every link at their moments)."""
        gap, beyond = self._apart_of(frames, at, p)
        apart = np.maximum(np.maximum(gap, beyond), 0.0)
        meet = np.flatnonzero((gap <= EPS) & (beyond <= SEPARATED))
        hit = np.zeros(len(at), dtype=bool)
        if len(meet):
            told = np.zeros(len(meet))
            used, moment = np.unique(at.take(meet), return_inverse=True)     # their moments alone
            hit[meet] = self._fine_at(frames.take(used, axis=0), moment, p.take(meet), told)
            apart[meet] = told
        if clear is not None:
            clear[:] = apart
        return hit

    def apart_at(self, frames: np.ndarray, at: np.ndarray, p: np.ndarray, planes: bool = False) -> np.ndarray:
        """Per (moment ``at[i]``, pair ``p[i]``), a link and a part (the links at ``frames``):
        at least how far apart they are (``_apart_of``; 0 where it cannot say). ``planes``: by
        the link's face planes alone (the part beyond one of them; cheaper: not placing the link)."""
        gap, beyond = self._apart_of(frames, at, p, planes)
        found: np.ndarray = np.maximum(np.maximum(gap, beyond), 0.0)
        return found

    def _apart_of(self, frames: np.ndarray, at: np.ndarray, p: np.ndarray, planes: bool = False
                  ) -> tuple[np.ndarray, np.ndarray]:
        """Per (moment ``at[i]``, pair ``p[i]``), a link and a part: its link placed alone (its
        vertices by its frame at the moment), how far apart their boxes are (``largest_of_xyz``
        of the gaps) and the farthest a face plane of either has the other beyond it (a box's
        gap says little of a long link lying aslant); either is at most how far apart they are."""
        pairs, s = self._pairs_now, self._scene
        assert pairs is not None
        link, other = pairs.moving.take(p), pairs.stationary.take(p)
        local, vertices, units, offsets = self._apart_tables()
        frame = frames[at, self.owners.take(link)]
        rot, shift = frame[:, :3, :3], frame[:, :3, 3]
        # the part beyond the link's face planes (placed: normals R n, offsets + t . R n), as ``_apart_items``
        turned = rot @ self._apart_normals.take(link, axis=0)                    # (items, 3, planes)
        off = self._apart_offsets.take(link, axis=0) + (shift[:, None, :] @ turned)[:, 0]
        d = vertices.take(other, axis=0) @ turned
        d -= off[:, None, :]
        beyond = over_middle(d, np.minimum).max(axis=1)
        if planes:
            return beyond, beyond
        placed = local.take(link, axis=0) @ rot.transpose(0, 2, 1)                     # (items, vertices, 3)
        placed += shift[:, None, :]
        gap = largest_of_xyz(np.maximum(s.lo.take(other, axis=0) - over_middle(placed, np.maximum),
                                        over_middle(placed, np.minimum) - s.hi.take(other, axis=0)))
        # the link beyond the part's face planes
        d = placed @ units.take(other, axis=0)
        d -= offsets.take(other, axis=0)[:, None, :]
        return gap, np.maximum(beyond, over_middle(d, np.minimum).max(axis=1))

    def needless(self, pick: np.ndarray, cols: np.ndarray, n: int, bounds: tuple[np.ndarray, np.ndarray],
                 figures: PathFigures, at: tuple[np.ndarray, Callable[[], np.ndarray] | None,
                                                 Callable[[np.ndarray, np.ndarray], np.ndarray] | None],
                 figure_order: bool = False) -> np.ndarray | None:
        """(steps, columns) of ``swept_path``'s picked (step, pair) items (the pairs at positions
        ``cols``, the parts' the first ``n``): those that need no moment, or None when none
        is known to. A pair colliding at a step's end pose is among the step's findings
        whatever is found between, and one colliding at its start too is said, if at all, at
        the step before (``colliding``); with ``figure_order`` (a step's findings said in Fig.
        C-12's order, not as found) the end pose alone will do. A link x part pair whose
        link's hulls over the step keep clear of the part (``hulls_clear``) meets it nowhere
        between. ``bounds``: the travel terms (steps, movers, joints) and the joints' turns
        (radians, absolute) of each step; ``at``: the steps' end poses' link frames, the first
        step's start's (asked for when needed) and the link frames at moments given by their
        steps and fractions of them."""
        if not self.prune_moments:
            return None
        frames, start, frames_at = at
        pairs = figures.pairs
        needless = touching = None
        if figures.collided:     # a pair colliding at a pose of the step: lasting, or no hull clears it
            at_end, at_start = colliding(figures.collided, len(pick), len(pairs.moving))
            touching = (at_end | at_start).take(cols, axis=1)
            needless = (at_end if figure_order else at_end & at_start).take(cols, axis=1) & pick
        if start is None or frames_at is None or self._carried:
            return needless
        step, col = np.nonzero(pick[:, :n] if touching is None else pick[:, :n] & ~touching[:, :n])
        if not len(step):
            return needless
        p = cols.take(col)
        bend = sweep_bends(*bounds)[step, pairs.moving.take(p)]
        clear = self.hulls_clear(step, p, bend, np.concatenate([start()[None], frames]), frames_at)
        if needless is None:
            needless = np.zeros(pick.shape, dtype=bool)
        needless[step.compress(clear), col.compress(clear)] = True
        return needless

    def hulls_clear(self, step: np.ndarray, p: np.ndarray, bend: np.ndarray, poses: np.ndarray,
                    frames_at: Callable[[np.ndarray, np.ndarray], np.ndarray]) -> np.ndarray:
        """Per (step ``step[i]``, pair ``p[i]``) a link and a part: can the link be shown clear of
        the part all through the step, without looking at a moment of it?

        With the joints moving linearly a point of the link leaves the straight line between
        where it is at two moments by at most ``bend`` (mm, over the step: ``arrays.sweep_bends``;
        a quarter of it over half the step), so over the span between the two moments the link
        stays within that of the hull of its two placements there. The hull is clear of the
        part when a face plane of the part, or of the link at either moment, has the two apart
        by more than that and ``SEPARATED`` (the fine test then answers clear at every moment
        between: ``_hull_apart``). A span not cleared is halved, up to ``HULL_HALVINGS`` times;
        where a pair is not clear by then its step's moments are looked at as before.
        ``poses``: the link frames at the steps' poses (steps + 1, links, 4, 4), the first
        step's start first; ``frames_at``: the link frames at moments given by their steps and
        fractions of them."""
        pairs = self._pairs_now
        assert pairs is not None
        link, other = pairs.moving.take(p), pairs.stationary.take(p)
        owner = self.owners.take(link)
        short = self._hulls_short(link, other, poses[step, owner], poses[step + 1, owner], bend + SEPARATED)
        clear = np.ones(len(p), dtype=bool)
        if len(short):
            clear[short] = self._halves_clear(step.take(short), link.take(short), other.take(short),
                                              bend.take(short), frames_at)
        return clear

    def _halves_clear(self, step: np.ndarray, link: np.ndarray, other: np.ndarray, bend: np.ndarray,
                      frames_at: Callable[[np.ndarray, np.ndarray], np.ndarray]) -> np.ndarray:
        """``hulls_clear`` of the items its whole steps leave: their spans halved, each half's hull
        tested with a quarter of the bend, the halves not cleared halved again."""
        clear = np.ones(len(step), dtype=bool)
        scale = float(1 << HULL_HALVINGS)
        cand = np.repeat(np.arange(len(step)), 2)
        lo, hi = np.tile([0.0, 0.5], len(step)), np.tile([0.5, 1.0], len(step))
        for halving in range(1, HULL_HALVINGS + 1):
            at_step = step.take(cand) * (2.0 * scale)
            moments, where = np.unique(np.concatenate([at_step + lo * scale, at_step + hi * scale]),
                                       return_inverse=True)
            whole = np.floor(moments / (2.0 * scale))
            frames = frames_at(whole.astype(np.intp), (moments - whole * 2.0 * scale) / scale)
            moving = link.take(cand)
            owner = self.owners.take(moving)
            short = self._hulls_short(moving, other.take(cand), frames[where[: len(cand)], owner],
                                      frames[where[len(cand):], owner], bend.take(cand) * 0.25 ** halving + SEPARATED)
            if not len(short):
                break
            if halving == HULL_HALVINGS:
                clear[cand.take(short)] = False
                break
            cand, lo, hi = cand.take(short), lo.take(short), hi.take(short)
            mid = (lo + hi) * 0.5
            cand, lo, hi = np.repeat(cand, 2), np.column_stack([lo, mid]).ravel(), np.column_stack([mid, hi]).ravel()
        return clear

    def _hulls_short(self, link: np.ndarray, other: np.ndarray, a: np.ndarray, b: np.ndarray, reach: np.ndarray
                     ) -> np.ndarray:
        """The items (indices) whose hulls (``_hull_apart``: the links at frames ``a`` and ``b``)
        no face plane has more than ``reach`` apart from the part: the part's planes first,
        then the link's own for the few those leave."""
        short = np.flatnonzero(self._hull_apart(link, other, a, b) <= reach)
        if not len(short):
            return short
        kept: np.ndarray = short[self._hull_apart(link.take(short), other.take(short), a.take(short, axis=0),
                                                  b.take(short, axis=0), True) <= reach.take(short)]
        return kept

    def _hull_apart(self, link: np.ndarray, other: np.ndarray, a: np.ndarray, b: np.ndarray,
                    own: bool = False) -> np.ndarray:
        """Per item, how far apart a face plane has the hull of link ``link[i]`` placed by the frames
        ``a[i]`` and ``b[i]`` (its own frame's at two moments) and the part ``other[i]`` (mm;
        negative where none has them apart): the part's planes, with ``own`` the link's at
        either moment. A hull's farthest point along a normal is one of its vertices, and a
        convex body reaches its own face plane and no farther."""
        local, vertices, units, offsets = self._apart_tables()
        shape = local.take(link, axis=0)                                  # (items, vertices, 3)
        ra, rb = a[:, :3, :3], b[:, :3, :3]
        if not own:
            # the link's vertices along the part's outward normals, at both moments: local @ R^T n + t.n
            n = units.take(other, axis=0)                                  # (items, 3, faces)
            ta, tb = a[:, None, :3, 3] @ n, b[:, None, :3, 3] @ n
            near = np.minimum(over_middle(shape @ (ra.transpose(0, 2, 1) @ n), np.minimum) + ta[:, 0],
                              over_middle(shape @ (rb.transpose(0, 2, 1) @ n), np.minimum) + tb[:, 0])
            found: np.ndarray = (near - offsets.take(other, axis=0)).max(axis=1)
            return found
        # the link's planes at each moment: the part beyond, the link at the other moment below
        normals, offs = self._apart_normals.take(link, axis=0), self._apart_offsets.take(link, axis=0)
        part = vertices.take(other, axis=0)
        best = np.full(len(link), -np.inf)
        for (r, t), (r2, t2) in (((ra, a[:, :3, 3]), (rb, b[:, :3, 3])), ((rb, b[:, :3, 3]), (ra, a[:, :3, 3]))):
            n = r @ normals                                                # (items, 3, planes)
            top = offs + (t[:, None, :] @ n)[:, 0]
            other_end = over_middle(shape @ (r2.transpose(0, 2, 1) @ n), np.maximum) + (t2[:, None, :] @ n)[:, 0]
            gap = over_middle(part @ n, np.minimum) - np.maximum(top, other_end)
            np.maximum(best, gap.max(axis=1), out=best)
        return best

    def _apart_tables(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``_apart_of``'s tables, kept per set of parts: each link's vertices in its own frame and
        each part's where it stands (padded to the most by repeating the last), and each part's
        face planes turned to look away from its centre, as (bodies, 3, faces) normals and
        (bodies, faces) offsets (a padding face never counts: its offset is infinite). Indexed
        by body; a link's rows in the parts' tables unused."""
        s, lay = self._scene, self._layout
        kept = self._apart_kept_tables
        if kept is not None and kept[0] is self._parts and kept[1] is s.planes:
            return kept[2]
        assert s.planes is not None

        def padded(counts: np.ndarray, starts: np.ndarray) -> np.ndarray:
            rows: np.ndarray = starts[:, None] + np.minimum(np.arange(int(counts.max())), counts[:, None] - 1)
            return rows

        nl = len(self._link_ks)
        unit, offset, size = s.planes
        outward = np.where(np.einsum("ifk,ik->if", unit, s.centres) > offset, -1.0, 1.0)
        # the parts' rows and faces only as many as the parts have (a box's 8 and 6, not a link's)
        faces = max(int((np.arange(1, size.shape[1] + 1) * (size[nl:] > 0.0)).max(initial=1)), 1)
        counts = lay.counts.copy()
        counts[:nl] = 1                                   # a link is never the part of a pair here
        tables = (self._local[padded(lay.counts[:nl], lay.starts[:nl])], s.vertices[padded(counts, lay.starts)],
                  (unit * outward[..., None])[:, :faces].transpose(0, 2, 1).copy(),
                  np.where(size > 0.0, offset * outward, np.inf)[:, :faces].copy())
        self._apart_kept_tables = (self._parts, s.planes, tables)
        return tables

    def _fine_at(self, frames: np.ndarray, at: np.ndarray, p: np.ndarray, clear: np.ndarray | None = None
                 ) -> np.ndarray:
        """Per (moment ``at[i]``, pair ``p[i]``), the links at ``frames[at[i]]`` and nothing
        carried: do the pair's boxes meet and the fine test find a collision? The links' boxes
        at every moment first (one product places every vertex); then one scene holds the
        links at the moments where boxes meet beside the parts, so the fine test runs once
        for every moment's pairs (the tests of ``check_pairs``, pair by pair: a pair whose
        boxes meet is near, its centre then in the other's box grown by its radius).

        ``clear`` (optional, one per item) is told how far apart the pair is at least: its boxes'
        gap, or where they meet how far the other lies beyond one of the link's face planes
        (0 where the fine test is needed, -1 where it finds a collision)."""
        pairs, s = self._pairs_now, self._scene
        assert pairs is not None
        count, nl, rows_l = len(frames), len(self._link_ks), self._nl_rows
        placed = (self._local_h @ frames[:, : self._n_frames, :3, :].transpose(3, 0, 1, 2).reshape(4, -1)
                  ).take(self._path_picks(count)[0]).reshape(rows_l, 3, count)
        starts = self._layout.starts[:nl]
        lo = np.concatenate([np.minimum.reduceat(placed, starts).transpose(2, 0, 1).reshape(-1, 3), s.lo[nl:]])
        hi = np.concatenate([np.maximum.reduceat(placed, starts).transpose(2, 0, 1).reshape(-1, 3), s.hi[nl:]])
        a, b = self._at_moment(pairs.moving.take(p), at, count), self._at_moment(pairs.stationary.take(p), at, count)
        gap = np.maximum(lo.take(b, axis=0) - hi.take(a, axis=0), lo.take(a, axis=0) - hi.take(b, axis=0))
        gap = largest_of_xyz(gap)
        meet = np.flatnonzero(gap <= EPS)
        hit = np.zeros(len(a), dtype=bool)
        if clear is not None:
            np.maximum(gap, 0.0, out=clear)
        if len(meet):           # a link's face plane with the other wholly beyond it: clear (``_apart``)
            beyond = self._apart_items(frames, placed, at.take(meet), p.take(meet))
            if clear is not None:
                clear[meet] = np.maximum(beyond, 0.0)
            meet = meet[beyond <= SEPARATED]
        if not len(meet):
            return hit
        # the scene of the moments where boxes meet, those moments numbered again from 0
        at = at.take(meet)
        used = np.flatnonzero(np.bincount(at, minlength=count))
        renumber = np.zeros(count, dtype=np.intp)
        renumber[used] = np.arange(len(used))
        at, count = renumber.take(at), len(used)
        a, b = self._at_moment(pairs.moving.take(p.take(meet)), at, count), \
            self._at_moment(pairs.stationary.take(p.take(meet)), at, count)
        placed = placed[:, :, used].transpose(2, 0, 1).reshape(-1, 3)
        # a link's centre and radius move with its frame (as ``_update`` has them), its box is the one above
        link_lo = lo[: len(lo) - len(s.lo) + nl].reshape(-1, nl, 3).take(used, axis=0).reshape(-1, 3)
        link_hi = hi[: len(hi) - len(s.hi) + nl].reshape(-1, nl, 3).take(used, axis=0).reshape(-1, 3)
        at_frames = frames.take(used, axis=0)[:, self.owners, :3, :]
        centres = np.einsum("mlij,lj->mli", at_frames, self._local_centres).reshape(-1, 3)
        lay = _moments_layout(self._layout, nl, rows_l, count)
        batch = Scene(lay, np.concatenate([placed, s.vertices[rows_l:]]), np.concatenate([centres, s.centres[nl:]]),
                      np.concatenate([np.tile(self._local_radii, count), s.radii[nl:]]),
                      np.concatenate([(link_lo + link_hi) * 0.5, s.mid[nl:]]),
                      np.concatenate([(link_hi - link_lo) * 0.5, s.half[nl:]]))
        hit[meet[fine(batch, a, b)]] = True
        if clear is not None:
            clear[hit] = -1.0
        return hit

    def _at_moment(self, bodies: np.ndarray, at: np.ndarray, count: int) -> np.ndarray:
        """The index in ``_fine_at``'s scene of each body at its moment: a link's own copy at
        that moment, a part's after every moment's links."""
        nl = len(self._link_ks)
        found: np.ndarray = np.where(bodies < nl, bodies + at * nl, bodies + (count - 1) * nl)
        return found

    def _apart_items(self, frames: np.ndarray, placed: np.ndarray, at: np.ndarray, p: np.ndarray) -> np.ndarray:
        """Per (moment ``at[i]``, pair ``p[i]``): how far beyond one of its moving link's face
        planes (placed from the link's own frame at that moment) every vertex of the pair's
        stationary body lies, the farthest such plane's (mm; negative when none has it wholly
        beyond). More than ``SEPARATED``: the fine test answers clear (``_apart``'s argument);
        and the two are at least that far apart. ``placed``: the links' vertices at every
        moment, (rows, 3, moments)."""
        pairs, s, lay = self._pairs_now, self._scene, self._layout
        assert pairs is not None
        nl = len(self._link_ks)
        link, other = pairs.moving.take(p), pairs.stationary.take(p)     # nothing carried: movers are links
        frame = frames[at, self.owners.take(link)]
        turned = frame[:, :3, :3] @ self._apart_normals.take(link, axis=0)
        off = self._apart_offsets.take(link, axis=0) + (frame[:, None, :3, 3] @ turned)[:, 0]
        width = int(lay.counts.max())
        rows = lay.starts.take(other)[:, None] + np.minimum(np.arange(width), lay.counts.take(other)[:, None] - 1)
        d = s.vertices[rows]                                     # a part's vertices, where it stands
        linked = np.flatnonzero(other < nl)                      # a link's, where it is at that moment
        if len(linked):
            d[linked] = placed[rows.take(linked, axis=0), :, at.take(linked)[:, None]]
        d = d @ turned
        d -= off[:, None]
        found: np.ndarray = over_middle(d, np.minimum).max(axis=1)
        return found


def over_middle(d: np.ndarray, pick: np.ufunc) -> np.ndarray:
    """``pick`` (np.minimum, np.maximum) over the middle axis of (items, n, m): numpy reduces a
    short axis of many rows slowly, so up to some thousand items that axis is made the first
    (a copy), else n - 1 calls on (items, m)."""
    if len(d) < 1500:
        few: np.ndarray = pick.reduce(np.ascontiguousarray(d.transpose(1, 0, 2)), axis=0)
        return few
    out: np.ndarray = d[:, 0].copy()
    for k in range(1, d.shape[1]):
        pick(out, d[:, k], out=out)
    return out


def colliding(collided: list[np.ndarray], count: int, pairs: int) -> tuple[np.ndarray, np.ndarray]:
    """(steps, pairs) twice: the pairs that collide at each step's end pose and at its start
    (``collided``: step x ``pairs`` + pair of those colliding at a step's end pose; the first
    step's start is not known here). A pair colliding at both is said, if at all, at the step
    before, and is among the step's findings whatever its moments find: nothing between the
    poses can change what is said."""
    codes = np.concatenate(collided)
    flat = np.zeros(count * pairs, dtype=bool)
    flat[codes[codes < count * pairs]] = True
    at_end = flat.reshape(count, pairs)
    at_start = np.zeros_like(at_end)
    at_start[1:] = at_end[:-1]
    return at_end, at_start


# how many times ``hulls_clear`` halves a span it cannot clear (the bend a quarter each time)
HULL_HALVINGS = 2

_FineAt = Callable[[np.ndarray, np.ndarray, np.ndarray, "np.ndarray | None"], np.ndarray]


def _moments_layout(lay: Layout, nl: int, rows: int, count: int) -> Layout:
    """The layout below, kept for the last few (layout, count)s (a path's moments come in few counts)."""
    key = (id(lay), nl, rows, count)
    kept = _LAYOUTS.get(key)
    if kept is not None and kept[0] is lay:
        return kept[1]
    if len(_LAYOUTS) >= 64:
        _LAYOUTS.clear()
    made = _moments_layout_of(lay, nl, rows, count)
    _LAYOUTS[key] = (lay, made)
    return made


_LAYOUTS: dict[tuple[int, int, int, int], tuple[Layout, Layout]] = {}


def _moments_layout_of(lay: Layout, nl: int, rows: int, count: int) -> Layout:
    """``lay`` (``nl`` links over ``rows`` vertex rows, then the parts) with its links
    repeated for ``count`` moments, each moment's vertex rows after the last's, the parts
    after them all: index arithmetic, no loop over the polyhedra."""
    def spread(idx: np.ndarray) -> np.ndarray:
        links = idx[:nl][None] + (np.arange(count) * rows).reshape(-1, *([1] * idx.ndim))
        return np.concatenate([links.reshape(-1, *idx.shape[1:]), idx[nl:] + (count - 1) * rows])

    return Layout(lay.ks[:nl] * count + lay.ks[nl:], spread(lay.starts), np.concatenate(
        [np.tile(lay.counts[:nl], count), lay.counts[nl:]]), spread(lay.edge_idx), spread(lay.face_idx),
        spread(lay.face_next))
