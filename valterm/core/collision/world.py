"""The collision scene the simulator checks at every motion step, and the messages of 1985.

Who is checked against whom (§2.7, App. C "possible collisions ... are checked, but
impossible ones are not"):

1. every robot link × every object not carried (the link is the moving polyhedron);
2. every carried object × every other object not carried (the carried one moves);
3. robot links × each other, except adjacent links (joined at a joint, they always touch)
   and the hand (WRIST, CLAMP, FINGER: the fingers ride on the clamp on the wrist). The more
   distal link of a pair is the moving one.

Links with the same label are one body (a link drawn as several polyhedra) and never checked
against each other. A carried object is not checked against the robot (it is held).

Messages, worded as in Figs. C-12 and 7-5::

    CLAMP IS NEAR PART 10        a link near an object (coarse check)
    PART 10 IS NEAR PART 5       a carried object near another object
    10 COLLIDES WITH 7           a carried object through another (fine check)
    CLAMP COLLIDES WITH 7        a link through an object
    CLAMP IS NEAR BASE / CLAMP COLLIDES WITH BASE   link against link

A pair that collides is reported once, as the collision; with ``near_with_collision`` the
near message is given first as well, the way the 1985 screen showed both
(Fig. C-12 c: ``PART 10 IS NEAR PART 5`` then ``10 COLLIDES WITH 5``).

Findings come in a stable order: rule 1 (links in the given order, objects by number),
then rule 2, then rule 3; identical messages (two FINGER polyhedra) are given once.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Collection, Iterable, Literal, Protocol, Sequence

import numpy as np

from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.collision.thesis import COLLIDES, NEAR, Scene, check_pairs, margin
from valterm.core.events import Collision, Near

HAND = frozenset({"WRIST", "CLAMP", "FINGER", "FINGERS"})

Party = str | int  # a robot link's name, or an object's 1-based number


def _long(x: Party) -> str:
    return f"PART {x}" if isinstance(x, int) else x


@dataclass(frozen=True)
class Finding:
    """One result of a step's check: ``a`` (the moving one) is near or collides with ``b``."""

    kind: Literal["near", "collides"]
    a: Party
    b: Party

    def __hash__(self) -> int:
        # kept: a dense cell says the same findings pose after pose, each looked up many times
        try:
            known: int = self.__dict__["_hash"]
            return known
        except KeyError:
            h = hash((self.kind, self.a, self.b))
            object.__setattr__(self, "_hash", h)
            return h

    def __reduce__(self) -> tuple[type[Finding], tuple[str, Party, Party]]:
        # the kept hash stays behind: another process hashes strings differently
        return Finding, (self.kind, self.a, self.b)

    @property
    def text(self) -> str:
        if self.kind == "near":
            return f"{_long(self.a)} IS NEAR {_long(self.b)}"
        return f"{self.a} COLLIDES WITH {self.b}"

    def event(self) -> Near | Collision:
        """The core event for this finding (what the simulator yields)."""
        cls = Near if self.kind == "near" else Collision
        return cls(a=str(self.a), b=str(self.b), text=self.text)


def bodies(labels: Sequence[str]) -> list[str]:
    """The robot's bodies, base to fingers: its link labels, each once (1985 numbered them
    1.. in this order: BASE 1 .. WRIST 5, CLAMP 6, FINGER 7 on the thesis's PUMA)."""
    found: list[str] = []
    for label in labels:
        if label not in found:
            found.append(label)
    return found


def figure_order(findings: Iterable[Finding], labels: Sequence[str]) -> list[Finding]:
    """The findings in Fig. C-12's order (the 1985 rules): the hand's bodies first (CLAMP,
    then FINGER), then the others from the hand down (WRIST, FOREARM, ...), carried parts
    after; for each, the parts by number, a near miss before its collision."""
    named = tuple(labels)
    keys, done = _order_keys(named)
    found = tuple(findings)
    known = done.get(found)
    if known is not None:
        return list(known)
    for f in found:
        if f not in keys:
            keys[f] = _order_key(f, named)
    ordered = sorted(found, key=keys.__getitem__)
    if len(done) >= 64:
        done.clear()
    done[found] = tuple(ordered)
    return ordered


@lru_cache(maxsize=8)
def _order_keys(labels: tuple[str, ...]) -> tuple[dict[Finding, tuple[int, str, int]],
                                                  dict[tuple[Finding, ...], tuple[Finding, ...]]]:
    """Each finding's place in Fig. C-12's order, and the last few lists put in order: worked
    out once (a dense cell says the same near misses pose after pose)."""
    return {}, {}


def _order_key(f: Finding, labels: tuple[str, ...]) -> tuple[int, str, int]:
    order = bodies(labels)
    hand = [b for b in order if b in HAND and b != "WRIST"]
    ranked = hand + [b for b in reversed(order) if b not in hand]
    rank = ranked.index(f.a) if isinstance(f.a, str) and f.a in ranked else len(ranked)
    other = f"{f.b:>6}" if isinstance(f.b, int) else str(f.b)
    return rank, other, 0 if f.kind == "near" else 1


class Checker(Protocol):
    """A pair checker: kind codes (0 clear, 1 near, 2 collides) for (moving, stationary) pairs."""

    def check(self, polys: Sequence[Polyhedron], moving: np.ndarray, stationary: np.ndarray,
              grow: float, coarse_only: np.ndarray | None = None) -> np.ndarray: ...


class ThesisChecker:
    """The 1985 coarse + fine check (``valterm.core.collision.thesis``) over labelled pairs."""

    name = "thesis"

    def check(self, polys: Sequence[Polyhedron], moving: np.ndarray, stationary: np.ndarray,
              grow: float, coarse_only: np.ndarray | None = None) -> np.ndarray:
        return check_pairs(Scene.of(polys), moving, stationary, grow, coarse_only)


def default_skip(labels: Sequence[str]) -> set[tuple[int, int]]:
    """Link index pairs (i < j) never checked: same body, adjacent bodies, both in the hand."""
    order = bodies(labels)
    body = [order.index(label) for label in labels]
    skip = set()
    for i in range(len(labels)):
        for j in range(i + 1, len(labels)):
            if abs(body[i] - body[j]) <= 1 or (labels[i] in HAND and labels[j] in HAND):
                skip.add((i, j))
    return skip


@dataclass(frozen=True)
class _Pairs:
    moving: np.ndarray
    stationary: np.ndarray
    a: tuple[Party, ...]
    b: tuple[Party, ...]


class CollisionWorld:
    """The scene's pair rules, built once for a robot model; ``check`` runs one motion step.

    ``link_labels``: robot links in order base .. fingers ("BASE", "WAIST", "UPPER ARM",
    "FOREARM", "WRIST", "CLAMP", "FINGER", ...). ``skip``: link index pairs not to check
    (default ``default_skip``). ``checker``: "thesis" (1985, near + collides), "exact"
    (python-fcl, collides only) or any ``Checker``.
    """

    def __init__(self, link_labels: Sequence[str], skip: Iterable[tuple[int, int]] | None = None,
                 checker: Literal["thesis", "exact"] | Checker = "thesis",
                 near_with_collision: bool = False) -> None:
        self.labels = tuple(link_labels)
        pairs = default_skip(self.labels) if skip is None else skip
        self.skip = {(min(i, j), max(i, j)) for i, j in pairs}
        if checker == "thesis":
            self.checker: Checker = ThesisChecker()
        elif checker == "exact":
            from valterm.core.collision.exact import ExactChecker  # fcl only when asked for
            self.checker = ExactChecker()
        else:
            self.checker = checker
        self.near_with_collision = near_with_collision
        self._pairs: dict[tuple[int, tuple[int, ...]], _Pairs] = {}
        self._findings: dict[tuple[object, ...], tuple[_Pairs, tuple[Finding, ...]]] = {}
        self._tables: dict[int, tuple[_Pairs, dict[int, list[tuple[Finding, ...]]]]] = {}

    def pairs(self, n_objects: int, carried: Collection[int] = ()) -> _Pairs:
        """The (moving, stationary) index pairs into links + objects, with their parties."""
        key = (n_objects, tuple(sorted(set(carried))))
        found = self._pairs.get(key)
        if found is not None:
            return found
        nl = len(self.labels)
        held = set(key[1])
        free = [n for n in range(1, n_objects + 1) if n not in held]
        mv: list[int] = []
        st: list[int] = []
        a: list[Party] = []
        b: list[Party] = []

        def add(i: int, j: int, pa: Party, pb: Party) -> None:
            mv.append(i)
            st.append(j)
            a.append(pa)
            b.append(pb)

        for i, label in enumerate(self.labels):                 # 1. links x objects
            for n in free:
                add(i, nl + n - 1, label, n)
        for c in key[1]:                                         # 2. carried x other objects
            for n in free:
                add(nl + c - 1, nl + n - 1, c, n)
        for j in range(nl):                                      # 3. links x links, distal moves
            for i in range(j):
                if (i, j) not in self.skip:
                    add(j, i, self.labels[j], self.labels[i])
        found = _Pairs(np.array(mv, dtype=np.intp), np.array(st, dtype=np.intp), tuple(a), tuple(b))
        self._pairs[key] = found
        return found

    def check(self, links: Sequence[Polyhedron], objects: Sequence[Polyhedron],
              carried: Collection[int] = (), speed: float = 100.0) -> list[Finding]:
        """One motion step: the findings for the robot links and objects where they are now."""
        if len(links) != len(self.labels):
            raise ValueError(f"expected {len(self.labels)} robot links, got {len(links)}")
        pairs = self.pairs(len(objects), carried)
        if len(pairs.moving) == 0:
            return []
        codes = self.checker.check([*links, *objects], pairs.moving, pairs.stationary, margin(speed))
        return self.findings(pairs, codes)

    def findings(self, pairs: _Pairs, codes: np.ndarray) -> list[Finding]:
        """The findings of a step from the kind code of each pair, in the stable order."""
        # consecutive steps mostly repeat the last codes: remember the findings of a few
        key = (id(pairs), codes.dtype.str, codes.tobytes())
        known = self._findings.get(key)
        if known is not None and known[0] is pairs:
            return list(known[1])
        hits = np.flatnonzero(codes)
        return self._remember(key, pairs, tuple(zip(hits.tolist(), codes.take(hits).tolist())))

    def findings_at(self, pairs: _Pairs, hits: tuple[tuple[int, int], ...]) -> list[Finding]:
        """The same from (position, kind code) of each pair not clear, by position: a few pairs
        of many need not make a code for every pair."""
        key = (id(pairs), hits)
        known = self._findings.get(key)
        if known is not None and known[0] is pairs:
            return list(known[1])
        return self._remember(key, pairs, hits)

    def _remember(self, key: tuple[object, ...], pairs: _Pairs, hits: tuple[tuple[int, int], ...]) -> list[Finding]:
        found = self._new_findings(pairs, hits)
        if len(self._findings) >= 256:
            self._findings.clear()
        self._findings[key] = (pairs, tuple(found))
        return found

    def _new_findings(self, pairs: _Pairs, hits: tuple[tuple[int, int], ...]) -> list[Finding]:
        said = self._said_table(pairs)
        # each once, in order (two FINGER polyhedra say the same): a dict keeps the first; the table's
        # equal findings are one object, so by identity (an int's hash, not ``Finding.__hash__``)
        if self.near_with_collision:
            return list({id(f): f for p, code in hits for f in said[code][p]}.values())
        return list({id(f): f for f in [said[code][p][0] for p, code in hits]}.values())

    def _said_table(self, pairs: _Pairs) -> dict[int, list[tuple[Finding, ...]]]:
        """What each pair says, by kind code (NEAR, COLLIDES) and position: made once per set
        of pairs (a dense cell's poses say dozens of near misses each)."""
        kept = self._tables.get(id(pairs))
        if kept is not None and kept[0] is pairs:
            return kept[1]
        one: dict[Finding, Finding] = {}       # equal findings (two FINGER polyhedra) one object

        def said(kind: Literal["near", "collides"], a: Party, b: Party) -> tuple[Finding, ...]:
            f = Finding(kind, a, b)
            return (one.setdefault(f, f),)

        near = [said("near", a, b) for a, b in zip(pairs.a, pairs.b)]
        hit = [said("collides", a, b) for a, b in zip(pairs.a, pairs.b)]
        if self.near_with_collision:
            hit = [n + h for n, h in zip(near, hit)]
        table = {NEAR: near, COLLIDES: hit}
        if len(self._tables) >= 8:
            self._tables.clear()
        self._tables[id(pairs)] = (pairs, table)
        return table


_WORLDS: dict[tuple[object, ...], CollisionWorld] = {}


def check_scene(links: Sequence[tuple[str, Polyhedron]], objects: Sequence[Polyhedron],
                carried: Collection[int] = (), speed: float = 100.0,
                skip: Iterable[tuple[int, int]] | None = None,
                checker: Literal["thesis", "exact"] = "thesis",
                near_with_collision: bool = False) -> list[Finding]:
    """One motion step's check in one call (a cached ``CollisionWorld`` per robot model)."""
    labels = tuple(label for label, _ in links)
    key = (labels, None if skip is None else frozenset(skip), checker, near_with_collision)
    world = _WORLDS.get(key)
    if world is None:
        world = _WORLDS[key] = CollisionWorld(labels, skip, checker, near_with_collision)
    return world.check([p for _, p in links], objects, carried, speed)


# codes re-exported for checkers written elsewhere
__all__ = ["Finding", "CollisionWorld", "ThesisChecker", "Checker", "check_scene", "default_skip",
           "NEAR", "COLLIDES"]
