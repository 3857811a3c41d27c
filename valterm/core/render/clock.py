"""The pacing clock of the apparent motion (§2.1): which pose of a motion to show now.

Elapsed time decides, not the drawing speed: pose i is due at ``start + i / rate``, and a
slow terminal simply skips (drops) the poses it had no time for, so a motion takes the same
time everywhere and always ends on its last pose. No textual import: the clock is injectable
so tests step it by hand.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable, Iterator
from typing import Generic, TypeVar

T = TypeVar("T")

DEFAULT_RATE = 40.0  # poses per second; SPEED sets the step size, so it sets how long a move takes


class MotionPlayer(Generic[T]):
    """Plays a sequence of poses (any objects) at ``rate`` poses per second.

    ``poses`` may be a lazy iterator (the motion generator): it is consumed only as far as
    the clock has got. ``rate`` may be ``math.inf`` (show the last pose at once).
    """

    def __init__(self, poses: Iterable[T], rate: float = DEFAULT_RATE,
                 clock: Callable[[], float] = time.monotonic, start: bool = True) -> None:
        if not rate > 0:
            raise ValueError("the pose rate must be positive")
        self.rate = float(rate)
        self.clock = clock
        self._poses: Iterator[T] = iter(poses)
        self._next_index = 0  # index of the next pose the iterator will give
        self._pending: T | None = None  # latest pose taken from the iterator, not yet shown
        self._has_pending = False
        self.current: T | None = None  # the pose last returned by poll()
        self.index = -1  # its index
        self.shown = 0  # poses returned by poll()
        self.dropped = 0  # poses skipped because their time had passed
        self.exhausted = False  # the iterator has ended
        self.aborted = False
        self.start_time: float | None = None
        if start:
            self.start()

    # -- control ------------------------------------------------------------------
    def start(self, now: float | None = None) -> None:
        self.start_time = self.clock() if now is None else now

    def abort(self) -> None:
        """Stop where it is: no further poses (the pose on screen stays)."""
        self.aborted = True

    @property
    def finished(self) -> bool:
        """True once aborted, or once the last pose has been returned."""
        return self.aborted or (self.exhausted and not self._has_pending)

    # -- playing ------------------------------------------------------------------
    def due_index(self, now: float | None = None) -> int:
        """Index of the pose due at ``now`` (can be past the end)."""
        if self.start_time is None:
            return -1
        if math.isinf(self.rate):
            return 1 << 62
        t = (self.clock() if now is None else now) - self.start_time
        return math.floor(t * self.rate + 1e-9)

    def poll(self, now: float | None = None) -> T | None:
        """The pose to show now if it is a new one, else None.

        Poses whose time has passed are dropped; the last pose is never dropped.
        """
        if self.aborted or self.start_time is None:
            return None
        due = self.due_index(now)
        while self._next_index <= due and not self.exhausted:
            try:
                pose = next(self._poses)
            except StopIteration:
                self.exhausted = True
                break
            if self._has_pending:
                self.dropped += 1
            self._pending, self._has_pending = pose, True
            self._next_index += 1
        if not self._has_pending:
            return None
        latest = self._pending  # a T (the flag says so); T itself may admit None
        self._pending, self._has_pending = None, False
        self.current, self.index = latest, self._next_index - 1
        self.shown += 1
        return latest

    def skip_to_end(self) -> T | None:
        """Drop everything up to the last pose and return it (None if none left or aborted)."""
        if self.aborted:
            return None
        last, got = self._pending, self._has_pending
        for pose in self._poses:
            if got:
                self.dropped += 1
            last, got = pose, True
            self._next_index += 1
        self.exhausted = True
        self._pending, self._has_pending = None, False
        if not got:
            return None
        self.current, self.index = last, self._next_index - 1
        self.shown += 1
        return last

    def next_due_in(self, now: float | None = None) -> float:
        """Seconds until the next pose is due (0 if one is due already)."""
        if self.start_time is None or math.isinf(self.rate):
            return 0.0
        t = (self.clock() if now is None else now) - self.start_time
        return max(0.0, self._next_index / self.rate - t)
