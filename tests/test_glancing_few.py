"""A pose by pose step's moments between its poses, worked out in Python numbers for a few
spans (``glance._spaced_few``), are the very moments and items numpy's path gives."""
from __future__ import annotations

import numpy as np
import pytest

from valterm.core.collision import glance


@pytest.mark.parametrize("seed", range(6))
def test_few_spans_give_numpys_moments(seed: int, monkeypatch: pytest.MonkeyPatch) -> None:
    rng, few_most = np.random.default_rng(seed), glance._FEW
    for trial in range(300):
        n = int(rng.integers(0, glance._FEW + 1))
        lo = rng.random(n) * 0.6
        hi = lo + (rng.random(n) * 0.5 if trial % 3 else -rng.random(n) * 0.1)   # some spans empty
        bound = rng.random(n) * 60.0 + 2.0
        pairs = int(rng.integers(1, 500))
        key = rng.integers(0, 5, n) * pairs + rng.integers(0, pairs, n)
        if trial % 4 == 0 and n:
            key[:] = key[0]                                   # one pair's spans share moments
        few = glance._spaced(lo, hi, bound, key, pairs, glance.GLANCE)
        monkeypatch.setattr(glance, "_FEW", -1)
        many = glance._spaced(lo, hi, bound, key, pairs, glance.GLANCE)
        monkeypatch.setattr(glance, "_FEW", few_most)
        for a, b in zip(few, many, strict=True):
            assert a.dtype == b.dtype and np.array_equal(a, b)
