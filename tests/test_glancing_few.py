"""A step's moments between its known moments, worked out in Python numbers for a few spans
(``glance._spaced_few``: a pose by pose step's pair or two, most paths' few dozen), are the
very moments and items numpy's path gives."""
from __future__ import annotations

import numpy as np
import pytest

from valterm.core.collision import glance


@pytest.mark.parametrize("seed", range(6))
def test_few_spans_give_numpys_moments(seed: int, monkeypatch: pytest.MonkeyPatch) -> None:
    rng = np.random.default_rng(seed)
    compared = 0
    for trial in range(300):
        n = int(rng.integers(0, glance._FEW + 1))
        lo = rng.random(n) * 0.6
        hi = lo + (rng.random(n) * 0.3 if trial % 3 else -rng.random(n) * 0.1)   # some spans empty
        bound = rng.random(n) * 40.0 + 2.0
        pairs = int(rng.integers(1, 500))
        key = rng.integers(0, 5, n) * pairs + rng.integers(0, pairs, n)
        if trial % 4 == 0 and n:
            key[:] = key[0]                                   # one pair's spans share moments
        few = glance._spaced_few(lo.tolist(), hi.tolist(), bound.tolist(), key.tolist(), pairs, glance.GLANCE)
        if few is None:                                       # too many moments: numpy's path
            continue
        with monkeypatch.context() as m:
            m.setattr(glance, "_FEW", -1)
            many = glance._spaced(lo, hi, bound, key, pairs, glance.GLANCE)
        for a, b in zip(few, many, strict=True):
            assert a.dtype == b.dtype and np.array_equal(a, b)
        compared += 1
    assert compared >= 150
