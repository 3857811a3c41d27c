"""MotionPlayer: elapsed time decides which pose shows; frames are dropped, never the last."""

from __future__ import annotations

import math

import pytest

from valterm.core.render.clock import MotionPlayer


class FakeClock:
    def __init__(self) -> None:
        self.t = 100.0

    def __call__(self) -> float:
        return self.t


def test_poses_follow_the_clock_and_drop_late_frames() -> None:
    clock = FakeClock()
    player = MotionPlayer(range(10), rate=10.0, clock=clock)
    assert player.poll() == 0  # the first pose at once
    assert player.poll() is None  # nothing new yet
    clock.t += 0.1
    assert player.poll() == 1
    clock.t += 0.35  # 0.45 s: poses 2, 3 were due and missed
    assert player.poll() == 4
    assert player.dropped == 2 and player.shown == 3 and player.index == 4
    clock.t += 0.05
    assert player.poll() == 5
    assert not player.finished


def test_end_detection_shows_the_last_pose() -> None:
    clock = FakeClock()
    player = MotionPlayer(iter(["a", "b", "c"]), rate=2.0, clock=clock)
    assert player.poll() == "a"
    clock.t += 10.0  # far past the end: jump to the last pose, never skip it
    assert player.poll() == "c"
    assert player.finished and player.dropped == 1 and player.current == "c"
    assert player.poll() is None


def test_end_is_known_one_period_after_the_last_pose() -> None:
    clock = FakeClock()
    player = MotionPlayer([1, 2], rate=4.0, clock=clock)
    assert player.poll() == 1
    clock.t += 0.25
    assert player.poll() == 2
    assert not player.finished  # the iterator is lazy: its end shows on the next tick
    clock.t += 0.25
    assert player.poll() is None and player.finished


def test_lazy_iterator_is_consumed_only_as_far_as_the_clock() -> None:
    clock = FakeClock()
    taken: list[int] = []

    def gen():
        for i in range(100):
            taken.append(i)
            yield i

    player = MotionPlayer(gen(), rate=10.0, clock=clock)
    player.poll()
    clock.t += 0.3
    assert player.poll() == 3
    assert taken == [0, 1, 2, 3]


def test_abort_stops_at_once() -> None:
    clock = FakeClock()
    player = MotionPlayer(range(10), rate=10.0, clock=clock)
    assert player.poll() == 0
    player.abort()
    clock.t += 5
    assert player.poll() is None and player.finished and player.aborted
    assert player.current == 0
    assert player.skip_to_end() is None


def test_skip_to_end_and_infinite_rate() -> None:
    clock = FakeClock()
    player = MotionPlayer(range(5), rate=1.0, clock=clock)
    assert player.poll() == 0
    assert player.skip_to_end() == 4
    assert player.finished and player.dropped == 3
    fast = MotionPlayer(range(5), rate=math.inf, clock=clock)
    assert fast.poll() == 4 and fast.finished


def test_empty_motion_and_bad_rate() -> None:
    player = MotionPlayer([], rate=5.0, clock=FakeClock())
    assert player.poll() is None and player.finished
    with pytest.raises(ValueError):
        MotionPlayer([1], rate=0)


def test_next_due_in() -> None:
    clock = FakeClock()
    player = MotionPlayer(range(3), rate=4.0, clock=clock)
    player.poll()
    assert player.next_due_in() == pytest.approx(0.25)
    clock.t += 0.1
    assert player.next_due_in() == pytest.approx(0.15)
