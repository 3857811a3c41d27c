"""Drives a MotionPlayer from a Textual timer, only while a motion is playing.

The timer is stopped as soon as the motion ends or is aborted: a running interval timer
keeps the app busy and makes Pilot key presses in tests wait for it.
"""

from __future__ import annotations

import time
from typing import Callable, Generic, Iterable, TypeVar

from textual.message_pump import MessagePump
from textual.timer import Timer

from valterm.core.render.clock import DEFAULT_RATE, MotionPlayer

T = TypeVar("T")


class MotionDriver(Generic[T]):
    """Plays motions on ``host`` (a widget, screen or app): ``on_pose(pose)`` for each pose
    shown, ``on_done(player)`` when a motion ends (``player.aborted`` tells an abort)."""

    def __init__(
        self,
        host: MessagePump,
        on_pose: Callable[[T], None],
        on_done: Callable[[MotionPlayer[T]], None] | None = None,
        *,
        max_fps: float = 60.0,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.host = host
        self.on_pose = on_pose
        self.on_done = on_done
        self.max_fps = max_fps
        self.clock = clock
        self.player: MotionPlayer[T] | None = None
        self._timer: Timer | None = None
        self._active = False  # between play() and the one on_done call

    @property
    def playing(self) -> bool:
        return self._active

    def play(self, poses: Iterable[T], rate: float = DEFAULT_RATE) -> MotionPlayer[T]:
        """Start a motion; one still playing first jumps to its last pose."""
        if self.playing:
            self.skip_to_end()
        player: MotionPlayer[T] = MotionPlayer(poses, rate, clock=self.clock)
        self.player = player
        self._active = True
        self._tick()  # the first pose at once
        if self._active:
            interval = 1.0 / min(rate, self.max_fps)
            self._timer = self.host.set_interval(interval, self._tick, name="motion")
        return player

    def skip_to_end(self) -> None:
        """Show the last pose now and end the motion (tests, impatient users)."""
        player = self.player
        if player is None or not self._active:
            return
        pose = player.skip_to_end()
        if pose is not None:
            self.on_pose(pose)
        self._finish(player)

    def abort(self) -> None:
        """Stop the motion where it is (the pose on screen stays)."""
        player = self.player
        if player is None or not self._active:
            return
        player.abort()
        self._finish(player)

    def _tick(self) -> None:
        player = self.player
        if player is None or not self._active:
            return
        pose = player.poll()
        if pose is not None:
            self.on_pose(pose)
        if player.finished:
            self._finish(player)

    def _finish(self, player: MotionPlayer[T]) -> None:
        self._active = False
        if self._timer is not None:
            self._timer.stop()
            self._timer = None
        if self.on_done is not None:
            self.on_done(player)
