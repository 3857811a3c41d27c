"""Messages between the app and its screens (events of the core go through ``ui.playback``).

The app posts them to the active screen; a screen that does not care ignores them.
"""

from __future__ import annotations

from textual.message import Message


class SceneChanged(Message):
    """The cell, the robot or a view option changed outside a motion: redraw."""
