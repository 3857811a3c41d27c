"""Messages between the app and its screens (what moved, what finished, what to show).

The app posts them to the active screen; a screen that does not care ignores them.
"""

from __future__ import annotations

from textual.message import Message

from valterm.core.events import Event


class PoseShown(Message):
    """A pose of a running motion is due on screen: redraw the model and the readouts."""


class MotionDone(Message):
    """A motion (or a whole program) ended; ``aborted`` when CTRL-C stopped it."""

    def __init__(self, aborted: bool = False) -> None:
        super().__init__()
        self.aborted = aborted


class SimulatorEvent(Message):
    """A non-pose event of the core (message, collision, grasp, type-out, error, ...)."""

    def __init__(self, event: Event) -> None:
        super().__init__()
        self.event = event


class SceneChanged(Message):
    """The cell, the robot or a view option changed outside a motion: redraw."""
