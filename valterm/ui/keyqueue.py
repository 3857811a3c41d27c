"""No key is ever dropped (issue 27): keys typed while the app is busy wait here, in order.

The app is busy while a motion is drawn (the player paces poses), while the screen on top
is still being mounted (a screen change), and until the key handed on last has been
handled by the node it went to (a key that closes a screen is done before the next key
picks its screen). A key typed then is queued and handed on, one at a time, once the app
is free again. CTRL-C never waits: it is how a motion or a program is stopped, and it
drops the keys still waiting (as a terminal drops its type-ahead: a jog key held down must
not go on moving the arm); nor does ESC wait when no key waits before it (it cancels what
moves where a screen says so), and where the screen says ESC aborts what runs (VAL-II mode's
RUNNING line: CTRL-C OR ESC: ABORT) it does as CTRL-C, whatever waits: a program of motions
back to back never lets a waiting key go, and ESC behind one never reached it. Nor do the
keys wait that the screen's open line takes while a program runs (text, BACKSPACE, RETURN:
``typing``), when no key waits before them.

The app calls ``take`` for every key it receives; a key it returns False for is the
app's to hand on now (``handing_on`` marks the node it went to).
"""

from __future__ import annotations

import asyncio
import time
from collections import deque
from collections.abc import Callable
from typing import Any

from textual import events
from textual.app import App
from textual.dom import DOMNode
from textual.message_pump import MessagePump
from textual.screen import Screen

IMMEDIATE = frozenset({"ctrl+c"})  # keys that never wait
CANCEL = frozenset({"escape"})  # waits only behind other keys (or what the keymap file put ESC on)
KEPT = 10_000       # keys kept waiting at most (a cat on the keyboard during a long program)
POLL = 0.01         # seconds between looks at a busy app
HANDLED_LIMIT = 5.0  # seconds a key may take to be handled before the next goes anyway
QUEUED = "_valterm_queued"  # set on a key handed on from the queue
TYPED_AT = "_valterm_typed_at"  # when a key that waited was typed (time.monotonic)


def typed_at(event: events.Key) -> float:
    """When ``event`` was typed: a key that waited keeps its time (--keys 1985: letters typed
    while a command played belong to the line being typed, not to the menu shown after it)."""
    return float(getattr(event, TYPED_AT, time.monotonic()))


class KeyQueue:
    """The keys typed while the app was busy, handed on in order when it is free."""

    def __init__(self, app: App[Any], drawing: Callable[[], bool],
                 cancel: Callable[[], frozenset[str]] = lambda: CANCEL,
                 aborts: Callable[[], bool] = lambda: False,
                 typing: Callable[[events.Key], bool] = lambda event: False) -> None:
        self.app = app
        self.drawing = drawing  # a motion is being drawn (the app's player)
        self.cancel = cancel  # ESC's keys as bound now
        self.aborts = aborts  # ESC aborts what runs now (the screen on top says so)
        self.typing = typing  # the screen's open line takes this key now, drawn or not
        self.keys: deque[events.Key] = deque(maxlen=KEPT)
        self._pending: MessagePump | None = None  # the node the last key went to, until handled
        self._pending_since = 0.0
        self._draining = False

    def __len__(self) -> int:
        """Keys not yet handled: those waiting, and the one handed on last until it is."""
        return len(self.keys) + (1 if self._pending is not None and self.changing else 0)

    @property
    def busy(self) -> bool:
        """A motion is drawn, a screen is being mounted, or the last key is not yet handled."""
        return self.drawing() or self.changing

    @property
    def changing(self) -> bool:
        """A screen is being mounted, or the last key handed on is not yet handled."""
        if not self._screen_mounted():
            return True
        pending = self._pending
        if pending is not None:
            if pending.is_attached and time.monotonic() - self._pending_since < HANDLED_LIMIT:
                return True
            self._pending = None
        return False

    def _screen_mounted(self) -> bool:
        try:
            screen = self.app.screen
        except Exception:  # no screen yet (starting) or any more (closing)
            return False
        return bool(screen.is_mounted)

    def take(self, event: events.Key) -> bool:
        """True when ``event`` waits (the app must not hand it on now)."""
        if getattr(event, QUEUED, False):
            return False
        if event.key in IMMEDIATE:
            self.keys.clear()
            return False
        escape = event.key in self.cancel()
        if escape and self.keys and not self.changing and self.aborts():
            self.keys.clear()        # the keys typed during the run go with it, as on CTRL-C
            return False
        if not self.keys and not (self.changing if escape else self.busy):
            return False
        # text for the line that is open while a program runs (VAL-II mode: KEYS TYPED NOW GO
        # TO THE LINE) goes there as typed: a program of motions back to back never lets a
        # waiting key go, and the line showed nothing of what was typed until the program ended
        # (the line keeps the order of what it takes; RETURN there queues the line: QUEUED)
        if not self.keys and self._screen_mounted() and self.typing(event):
            return False
        setattr(event, TYPED_AT, time.monotonic())
        self.keys.append(event)
        if not self._draining:
            self._draining = True
            self.app.run_worker(self._drain(), name="type-ahead", group="keys", exit_on_error=False)
        return True

    def handing_on(self, target: MessagePump) -> None:
        """The app hands a key to ``target``: busy until ``target`` has handled it, and each
        node up to its screen has handled it too. A key the target does not stop bubbles to
        its parent's queue (a RETURN in VAL-II mode's line is the screen's to take): the next
        key must wait for that, or it reaches the line first (on a busy machine, the T of
        ``TYPE`` ran in the DRIVE line before its RETURN did)."""
        self._pending, self._pending_since = target, time.monotonic()
        self._handled_here(target)

    def _handled_here(self, node: MessagePump) -> None:
        """When ``node`` has handled what it was sent so far, go on with its parent (queued
        behind a key that bubbled there), up to the screen."""

        def handled() -> None:
            if self._pending is not node:
                return  # a newer key is pending
            parent = node.parent if isinstance(node, DOMNode) else None
            if isinstance(node, Screen) or not isinstance(parent, DOMNode) or not parent.is_attached:
                self._pending = None
                return
            self._pending = parent
            self._handled_here(parent)

        if not node.call_later(handled):
            self._pending = None

    def clear(self) -> None:
        self.keys.clear()

    async def _drain(self) -> None:
        try:
            while self.keys:
                while self.busy and self.app.is_running:
                    await asyncio.sleep(POLL)
                if not self.keys or not self.app.is_running:
                    break
                event = self.keys.popleft()
                again = events.Key(event.key, event.character)
                again.__dict__.update({k: v for k, v in event.__dict__.items() if k.startswith("_valterm")})
                setattr(again, QUEUED, True)
                again.set_sender(self.app)
                self._pending, self._pending_since = self.app, time.monotonic()  # until the app forwards it
                self.app.post_message(again)
        finally:
            self._draining = False
