"""Messages between the app, its player and its screens (posting's way: whoever owns the state
handles them).

A run: a screen posts ``RunRequested`` (and ``RunResumed``, ``RunAbortRequested``) to the app,
which plays it on the one player (``ui.playback``); the player posts what the stream does
(``TranscriptLines``, ``SceneShown``, ``PictureMoved``, ``RunEvent``, ``RunPaused``,
``RunEnded``) to the screen that asked while it is up, else to the screen on top. No screen
calls the player; a screen that does not care about a message ignores it.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

from textual.message import Message

if TYPE_CHECKING:
    from valterm.core.events import Event, Pause


class SceneChanged(Message):
    """The cell, the robot or a view option changed outside a motion: redraw."""


# -- a screen to the app ----------------------------------------------------------------
class RunRequested(Message):
    """Play ``events`` (a command, a program, a jog) on the one player; what it does is
    posted to ``origin`` (the screen that asked) while it is up."""

    def __init__(self, events: Iterable[Event], origin: object = None) -> None:
        super().__init__()
        self.events = events
        self.origin = origin


class RunResumed(Message):
    """PROCEED (or a screen with no PROCEED line): a paused stream goes on."""


class RunAbortRequested(Message):
    """ESC or R while a stream plays: a program stops after its step, anything else at once."""


class Collided(Message):
    """Bodies found colliding where a motion left the robot: marked in the picture."""

    def __init__(self, parties: Iterable[str]) -> None:
        super().__init__()
        self.parties = frozenset(parties)


# -- the player to a screen (Message.bubble off: the app does not take them back) ----------
class _Run(Message, bubble=False):
    def __init_subclass__(cls, bubble: bool | None = False, verbose: bool = False, no_dispatch: bool | None = False,
                          namespace: str | None = None) -> None:
        # off for every subclass too: Textual's own default would set bubble=True on each
        super().__init_subclass__(bubble, verbose, no_dispatch, namespace)


class TranscriptLines(_Run):
    """Transcript lines (the core's renderer's) to add to what is shown."""

    def __init__(self, lines: list[str]) -> None:
        super().__init__()
        self.lines = lines


class SceneShown(_Run):
    """The robot or the cell changed (a pose shown): redraw the model and the readouts."""


class PictureMoved(_Run):
    """Only the picture moved (a pose between two of a motion's): redraw the model alone."""


class RunEvent(_Run):
    """A screen's own event (HELP, a monitor command, a finding): the screen takes it, or
    shows ``lines`` (the core's renderer's) as any other."""

    def __init__(self, event: Event, lines: list[str]) -> None:
        super().__init__()
        self.event = event
        self.lines = lines


class RunPaused(_Run):
    """PAUSE: the stream waits for ``RunResumed``."""

    def __init__(self, pause: Pause) -> None:
        super().__init__()
        self.pause = pause


class RunEnded(_Run):
    """The stream ended (``aborted`` by CTRL-C or ESC)."""

    def __init__(self, aborted: bool) -> None:
        super().__init__()
        self.aborted = aborted
