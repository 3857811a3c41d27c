"""What a screen reads of the app: one typed, read-only view (issue 37, build 1).

Screens read the app's state through ``KeyedScreen.stage`` (this Protocol, which the app
satisfies) rather than the app's attributes; they change it by message (``ui.messages``)
or a screen change, never by assignment (mypy: these are read-only properties).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Protocol

if TYPE_CHECKING:
    from valterm.core.render.raster import Scene, ViewTransform
    from valterm.core.session import Session
    from valterm.core.simulator import Simulator


class Stage(Protocol):
    """The app as its screens see it."""

    @property
    def session_read(self) -> Session | None:
        """The open session, if a set-up has been read (none before the first frame's)."""

    @property
    def active_session(self) -> Session:
        """The open session (a screen that shows a cell is opened only once there is one)."""

    @property
    def simulator(self) -> Simulator:
        """The open session's simulator."""

    @property
    def view_transform(self) -> ViewTransform:
        """ORIENT's view, shared by every model view."""

    @property
    def back_faces(self) -> bool:
        """FACES: back faces drawn (hidden surfaces not removed)."""

    @property
    def axes(self) -> bool:
        """AXES: the world axes drawn."""

    @property
    def ascii(self) -> bool:
        """The model drawn in ASCII, not braille."""

    @property
    def setup_modified(self) -> bool:
        """The cell moved since its set-up file was read or saved."""

    @property
    def keys_1985(self) -> bool:
        """``--keys 1985``: the thesis's keyboard."""

    def scene(self, part_axes: int | None = None) -> Scene | None:
        """The picture as it stands (None before a set-up is read)."""
