"""Corners clipped between the swept check's moments (issue 40).

The swept check spaces a step's moments by the thinnest part's width: enough to find a link
that passes through a part, not a corner that clips one and leaves before the next moment.
So after those moments, each link x part pair that could meet in a step (its boxes within
reach of its moving body's bound ``b``, the most any of its points moves over the step) is
looked at between them, conservative advancement on what the moments and the step's two
poses found: where the pair was at least ``d0`` apart at moment ``t0`` and ``d1`` at the next,
``t1``, no point can reach the part before ``t0 + d0 / b`` or after ``t1 - d1 / b``; between
those the pair is checked at moments no more than ``GLANCE / b`` of the step apart (no point
moves farther than ``GLANCE`` mm between two). How far apart: the boxes' gap, and where that
leaves a span to look in, the face planes of either (``RobotScene.apart_at``; never more
than the distance, a test says so against fcl).

Why that is enough: a pair found apart at two moments its points move at most ``g`` between
overlaps at any time between them by less than ``g / 2`` (a plane separates the two at the
nearer moment, and no point has moved ``g / 2`` from where it was then, so moving the link
that far along the plane's normal parts them). A contact deeper than ``GLANCE / 2`` is found
in its step. A pair that collides at a step's end pose is said there, and not looked for.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from valterm.core.collision.thesis import EPS

# mm: between two of the moments looked at no point of a link moves farther than this
# relative to a part it may meet: a contact deeper than half of it is found in its step
GLANCE = 2.0

_FINEST = 2 ** 20        # moments are k / 2^20 of their step (one at a moment two pairs share)


@dataclass(frozen=True)
class Glancing:
    """The pairs (scene positions) that could meet in a path's steps (indices as the moments'),
    each with its moving body's bound over the step (mm) and at least how far apart it is at
    the step's start and end (mm, where not negative): its boxes' gaps, or with ``measured``
    its face planes' too (``RobotScene.clear_glancing``)."""

    step: np.ndarray
    pair: np.ndarray
    bound: np.ndarray
    start: np.ndarray
    end: np.ndarray
    pairs: int                   # how many pairs the scene has
    measured: bool = False       # start and end measured by the face planes: not to measure again


def at_risk(items: tuple[np.ndarray, np.ndarray], bound: np.ndarray, start: np.ndarray, both: np.ndarray,
            pairs: int, said: list[np.ndarray] | None = None) -> Glancing | None:
    """``Glancing`` of the (step, pair) ``items`` the swept check found could meet (their
    moving bodies' bounds, box gaps at the start and start plus end less 2 EPS, as it has
    them), but for those ``said`` (step x ``pairs`` + pair: a pair that collides at its step's
    end pose is said there, nothing between to look for); None when there are none."""
    step, pair = items
    if said:
        keep = ~np.isin(step * pairs + pair, np.concatenate(said))
        step, pair, bound, start, both = (x[keep] for x in (step, pair, bound, start, both))
    if not len(step):
        return None
    return Glancing(step, pair, bound, start, both - start + 2.0 * EPS, pairs)


def cleared(glancing: Glancing, start: np.ndarray, end: np.ndarray) -> Glancing | None:
    """``glancing`` but for the pairs that cannot meet in their step, being at least ``start``
    apart at its start and ``end`` at its end (``start + end`` more than the most any point of
    the link moves: conservative advancement from either end leaves nothing between), the
    others with those distances (``measured``); None when none is left."""
    keep = np.flatnonzero(start + end <= glancing.bound)
    if not len(keep):
        return None
    return Glancing(glancing.step.take(keep), glancing.pair.take(keep), glancing.bound.take(keep), start.take(keep),
                    end.take(keep), glancing.pairs, True)


# moments and what to look at there: each moment's step and fraction of it (in order), and
# the (moment, pair) items, by moment
Items = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]


@dataclass(frozen=True)
class Spans:
    """Each candidate's spans between two moments known of it (``spans``): the candidates'
    keys (step x pairs + pair, sorted), each span's candidate (an index into them), its two
    ends (fractions of the step, and the known items there) and its pair's bound (mm)."""

    key: np.ndarray
    cand: np.ndarray
    start: np.ndarray
    end: np.ndarray
    first: np.ndarray
    last: np.ndarray
    bound: np.ndarray
    pairs: int

    def clear_of(self, clear: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The part of each span no point can reach the part in (``lo`` to ``hi``, fractions of the
        step; empty where its pair collided at a known moment of the step, found there)."""
        apart = np.maximum(clear, 0.0)
        lo = self.start + apart.take(self.first) / self.bound
        hi = self.end - apart.take(self.last) / self.bound
        hit = np.zeros(len(self.key), dtype=bool)
        hit[self.cand[(clear.take(self.first) < 0) | (clear.take(self.last) < 0)]] = True
        return lo, np.where(hit.take(self.cand), lo, hi)


def spans(glancing: Glancing, known: Items) -> Spans:
    """The spans between the ``known`` moments of each pair of ``glancing`` in its step (its
    poses are known moments: ``ends``)."""
    n = glancing.pairs
    step_of, t, at, p = known
    item_key = step_of.take(at) * n + p
    key = glancing.step * n + glancing.pair
    order = np.argsort(key)
    key = key.take(order)
    where = np.minimum(np.searchsorted(key, item_key), len(key) - 1)     # a candidate's key, if any
    item = np.flatnonzero(key.take(where) == item_key)
    cand, when = where.take(item), t.take(at.take(item))
    seq = np.argsort(cand * 2.0 + when)                 # by candidate, then moment (a moment is 0 to 1)
    cand, when, item = cand.take(seq), when.take(seq), item.take(seq)
    span = np.flatnonzero(cand[1:] == cand[:-1])
    c = cand.take(span)
    return Spans(key, c, when.take(span), when.take(span + 1), item.take(span), item.take(span + 1),
                 glancing.bound.take(order).take(c), n)


def between(found: Spans, clear: np.ndarray, spacing: float = GLANCE) -> Items:
    """The moments where the pairs of ``found`` spans must be looked at, given what the known
    moments found of each item: ``clear``, how far apart it was at least (0: not known),
    negative where it collided (the pair is then found in that step: nothing more to look
    for). In each span's part a point may reach the part in, moments evenly spaced no more
    than ``spacing`` mm of its pair's travel apart and from the part's ends (``GLANCE``)."""
    lo, hi = found.clear_of(clear)
    return _spaced(lo, hi, found.bound, found.key.take(found.cand), found.pairs, spacing)


def between_poses(glancing: Glancing, spacing: float = GLANCE) -> Items:
    """``between`` where the step's poses are the only moments known of the pairs (no width-spaced
    moments) and their distances were measured there (``measured``): one span a pair."""
    lo, hi = glancing.start / glancing.bound, 1.0 - glancing.end / glancing.bound
    return _spaced(lo, hi, glancing.bound, glancing.step * glancing.pairs + glancing.pair, glancing.pairs, spacing)


def _spaced(lo: np.ndarray, hi: np.ndarray, bound: np.ndarray, key: np.ndarray, pairs: int, spacing: float) -> Items:
    """The moments of ``between``: in each span's part ``lo`` to ``hi`` (fractions of its step),
    moments evenly spaced no more than ``spacing`` mm of its pair's travel (``bound``) apart,
    the span's pair ``key`` (step x ``pairs`` + pair)."""
    if len(lo) <= _FEW:
        few = _spaced_few(lo.tolist(), hi.tolist(), bound.tolist(), key.tolist(), pairs, spacing)
        if few is not None:
            return few
    count = np.maximum(np.ceil((hi - lo) * bound / (spacing * (1.0 - 1e-6))) - 1.0, 0.0).astype(np.intp)
    each = np.repeat(np.arange(len(lo)), count)
    nth = np.arange(len(each)) - np.repeat(np.cumsum(count) - count, count) + 1
    frac = lo.take(each) + nth * ((hi - lo) / (count + 1)).take(each)
    pair_key = key.take(each)
    return _items(pair_key // pairs, np.round(frac * _FINEST).astype(np.int64), pair_key % pairs)


def _spaced_few(lo: list[float], hi: list[float], bound: list[float], key: list[int], pairs: int,
                spacing: float) -> Items | None:
    """``_spaced`` of a few spans (a pose by pose step's pair or two, most paths' few dozen) in
    Python numbers: the same figures (the same operations on the same doubles, ``round`` to
    even as ``np.round``), not a dozen numpy calls of a few items each; None where they make
    more than ``_FEW_MOMENTS`` moments (numpy's then)."""
    counts = [max(math.ceil((b - a) * reach / (spacing * (1.0 - 1e-6))) - 1, 0) for a, b, reach in zip(lo, hi, bound)]
    if sum(counts) > _FEW_MOMENTS:
        return None
    codes: list[int] = []
    pair_of: list[int] = []
    for a, b, count, k in zip(lo, hi, counts, key):
        part = (b - a) / (count + 1)
        base = (k // pairs) * (2 * _FINEST)
        for nth in range(1, count + 1):
            codes.append(base + round((a + nth * part) * _FINEST))
            pair_of.append(k % pairs)
    keys = sorted(set(codes))
    index = {code: i for i, code in enumerate(keys)}
    width = max(pair_of, default=0) + 1
    item = sorted({index[code] * width + q for code, q in zip(codes, pair_of)})
    return (np.array([c // (2 * _FINEST) for c in keys], dtype=np.intp),
            np.array([(c % (2 * _FINEST)) / _FINEST for c in keys], dtype=float),
            np.array([i // width for i in item], dtype=np.intp), np.array([i % width for i in item], dtype=np.intp))


_FEW = 32                # spans: up to this many, making up to
_FEW_MOMENTS = 64        # this many moments, ``_spaced`` in Python numbers


def doubtful(found: Spans, clear: np.ndarray, spacing: float = GLANCE) -> np.ndarray:
    """Which known items end a span ``between`` would look in: knowing better how far apart
    they are may clear it."""
    lo, hi = found.clear_of(clear)
    counted = (hi - lo) * found.bound > spacing
    out = np.zeros(len(clear), dtype=bool)
    out[found.first[counted]] = True
    out[found.last[counted]] = True
    return out


def _items(step: np.ndarray, tick: np.ndarray, pair: np.ndarray) -> Items:
    """``Items`` of (step, moment ``tick / _FINEST`` of it, pair) triples: the moments sorted
    and shared, each pair once at each."""
    code = step.astype(np.int64) * (2 * _FINEST) + tick
    keys, inverse = np.unique(code, return_inverse=True)
    width = int(pair.max(initial=0)) + 1
    item = np.unique(inverse.astype(np.int64) * width + pair)
    return (keys // (2 * _FINEST)).astype(np.intp), (keys % (2 * _FINEST)) / _FINEST, \
        (item // width).astype(np.intp), (item % width).astype(np.intp)


def ends(glancing: Glancing) -> tuple[Items, np.ndarray]:
    """The items at each step's two poses (0 and 1 of it), a pair of ``glancing`` each, each at a
    moment of its own, and how far apart they are at least (every span ``between`` looks in
    lies between two known items of its pair)."""
    count = len(glancing.step)
    step = np.concatenate([glancing.step, glancing.step])
    t = np.repeat(np.array([0.0, 1.0]), count)
    items = (step, t, np.arange(2 * count), np.concatenate([glancing.pair, glancing.pair]))
    return items, np.maximum(np.concatenate([glancing.start, glancing.end]), 0.0)
