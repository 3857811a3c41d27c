"""tests/fuzz_keys.py with a small count and a fresh seed each run (the 20 000-key run is the
script's: ``python tests/fuzz_keys.py --keys 20000``)."""

from __future__ import annotations

import pytest

import asyncio
import random

from fuzz_keys import run

KEYS = 500  # small: the suite's share; the seed is printed and named on failure


@pytest.mark.slow  # CI runs it (pytest -m slow); the default run stays under 5 minutes
def test_random_keys_mid_motion_lose_nothing_and_end_nothing() -> None:
    seed = random.SystemRandom().randrange(2**32)
    print(f"fuzz seed {seed}")
    tally = asyncio.run(run(seed, KEYS))
    assert tally.keys >= KEYS and tally.probes >= 2, f"seed {seed}: {tally}"
    assert tally.clean, f"seed {seed}: lost {tally.lost}, crashes {tally.crashes}, survived {tally.survived}"
