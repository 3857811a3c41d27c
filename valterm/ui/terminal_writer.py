"""Frames the terminal has not taken are dropped, not queued (issue 38 item 7).

Textual hands each frame to a writer thread through a queue of 30 writes. A terminal that
stops reading (a frozen SSH client) first lets sshd buffer about a megabyte, then blocks the
thread, fills the queue and blocks the app's own loop: no key is taken, and the stale frames
go out first once it reads again. Worse, sshd asks a silent client whether it is alive only
after ClientAliveInterval seconds in which nothing at all happened on the connection, the
app's output included: an app that keeps drawing for a frozen client keeps it connected.

So the app asks the terminal where its cursor is (``ESC [ 6 n``, which every VT100 answers)
after a frame, one question at a time. Until the answer comes back, the terminal has not read
that far. A question unanswered for ``LAG`` seconds, or more than a few writes waiting for
the writer thread, and frames are skipped (the screen's compositor has drawn them, nothing is
written); when the terminal catches up, the whole screen is drawn afresh, so nothing is left
half-drawn. A terminal that never answers the first question is never held back (as before).
An idle app asks nothing: a question follows a frame.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

PROBE = "\x1b[6n"  # DSR 6, cursor position report: the terminal answers ESC [ row ; col R
LAG = 1.0  # seconds the terminal may take to answer before frames are skipped
MAX_WRITES = 24  # writes waiting for Textual's writer thread (its queue holds 30: never full) ...
MAX_CHARS = 256 * 1024  # ... or characters: more, and the terminal is behind


class FrameGate:
    """What the terminal has not taken yet, and whether a frame may be written now.

    Frames stop when the terminal is behind (a question unanswered for LAG s, or more than
    MAX_WRITES or MAX_CHARS waiting for the writer thread) and start again, with the whole
    screen, once it has caught up (the question answered, and at most half of those waiting).

    Called from three threads: the app's loop (``admit``, ``drawn``, ``queued``), Textual's
    writer thread (``written``) and its input thread (``answered``, ``stirred``); ``repaint`` is called
    from the latter two when the terminal has caught up after frames were skipped."""

    def __init__(self, write: Callable[[str], None], repaint: Callable[[], None],
                 clock: Callable[[], float] = time.monotonic) -> None:
        self._write = write
        self._repaint = repaint
        self._clock = clock
        self._lock = threading.Lock()
        self.handed = 0  # writes handed to the writer thread, ever
        self.writes = 0  # handed to the writer thread, not yet written by it
        self.chars = 0
        self.asked: float | None = None  # when the unanswered question was sent
        self.answers = 0  # the terminal answers questions: its silence means something
        self.holding = False  # frames are skipped until the terminal has caught up

    def _late(self) -> bool:
        return self.answers > 0 and self.asked is not None and self._clock() - self.asked > LAG

    def admit(self) -> bool:
        """May a frame be written now? No: it is skipped (the screen is drawn whole later)."""
        with self._lock:
            if self.holding or self._late() or self.writes > MAX_WRITES or self.chars > MAX_CHARS:
                self.holding = True
                return False
            return True

    def drawn(self, mark: int) -> None:
        """A frame was written (``handed`` moved on from ``mark``; Textual writes nothing
        while it is batching or closing): the question follows it, unless one is out."""
        with self._lock:
            if self.asked is not None or self.handed == mark:
                return
            self.asked = self._clock()
        self._write(PROBE)

    def stirred(self) -> None:
        """The terminal sent something (a key): it runs. A question it has let go late (its
        answer lost, say inside a paste) is asked again, still late until answered; a frozen
        client sends nothing, so the app stays quiet for it (sshd's questions need silence)."""
        with self._lock:
            late = self._late()
        if late:
            self._write(PROBE)

    def restart(self) -> None:
        """The app takes the terminal again (after a suspend): no question is out."""
        with self._lock:
            self.asked = None
            self.holding = False

    def queued(self, text: str) -> None:
        with self._lock:
            self.handed += 1
            self.writes += 1
            self.chars += len(text)

    def written(self, text: str) -> None:
        """The writer thread has written ``text`` out."""
        with self._lock:
            self.writes -= 1
            self.chars -= len(text)
            due = self._caught_up()
        if due:
            self._repaint()

    def answered(self) -> None:
        """The terminal answered: it has read everything up to the question."""
        with self._lock:
            self.answers += 1
            self.asked = None
            due = self._caught_up()
        if due:
            self._repaint()

    def _caught_up(self) -> bool:
        """Frames were skipped and the terminal takes them again: the one repaint is due."""
        if self.holding and not self._late() and self.writes * 2 <= MAX_WRITES and self.chars * 2 <= MAX_CHARS:
            self.holding = False
            return True
        return False
