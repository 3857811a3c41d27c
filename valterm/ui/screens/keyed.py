"""The one screen base (issue 27): every screen of the app is a ``KeyedScreen``.

One key path for all of them, ``on_key``:

1. An open line (``line_taking_keys``) takes every printable key, RETURN and BACKSPACE that
   reach the screen, typed ahead or not, in the order typed (a ``+`` typed before the line
   has the focus is text, not the view's zoom).
2. A key bound (by id, as the keymap file has it) and switched on in the screen's present
   state is let through: the app runs its binding after this handler.
3. ``?`` and F1 are a binding like the rest (``screen.help``, rebindable): HELP in every
   state, ``?`` only where no line takes it as text; any other key is the open line's
   business (nothing more happens).
4. What is left goes to the screen's ``other_key`` (a letter that opens the command line,
   the editor's TAB); a key nobody took gets the one wrong-key message (``keymap.unknown_key``)
   through ``say_wrong_key`` (the editor also saves the program then, §5.2: ``wrong_key``).

Which bindings work in which state is said in one place per screen, ``STATES`` (an action
name and the states it works in; an action not listed works in every state), and the state
itself is one value, ``key_state``. ``check_action`` reads both, so the footer, HELP's key
legend and the keymap file see exactly the keys that work.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, ClassVar, TypeVar

from textual import events
from textual.screen import ModalScreen, Screen
from textual.widgets import Input

from valterm.ui import keymap, legends
from valterm.ui.compositor import RowCompositor
from valterm.ui.screens.guard import Guarded
from valterm.ui.widgets.prompt import type_ahead

if TYPE_CHECKING:
    from textual import getters

    from valterm.ui.app import ValtermApp
    from valterm.ui.stage import Stage

ResultT = TypeVar("ResultT")


action_name = legends.action_name  # the action a binding runs, without its arguments


class KeyedScreen(Guarded, Screen[ResultT]):
    """A screen of valterm: a typed app, one key path, bindings switched on per state."""

    BINDINGS = [legends.HELP]  # ? and F1 (rebindable as screen.help): HELP in every state
    STATES: ClassVar[Mapping[str, frozenset[str]]] = {}  # action -> the states it works in
    UNKNOWN_KEY_HINT = ""  # what a key that is no key here may have meant

    def __init__(self, name: str | None = None, id: str | None = None, classes: str | None = None) -> None:
        super().__init__(name, id, classes)
        if not isinstance(self, ModalScreen):  # a modal one renders the screen under it as it goes
            self._compositor = RowCompositor()  # a frame renders the rows it writes (issue 40)

    if TYPE_CHECKING:  # the app every screen runs in, typed (Textual's own says App[object])
        app = getters.app(ValtermApp)

    @property
    def stage(self) -> Stage:
        """The app's state, read-only (ui/stage.py): what a screen reads of the app."""
        return self.app

    def _compositor_refresh(self) -> None:
        # Textual (pinned 8.2) draws a screen's frame even while the app holds a batch of
        # updates, and then drops it (App._display): the first screen, pushed while the app
        # mounts (one batch), was drawn twice before it showed (issue 25, the start). The
        # frame waits for the batch's end instead (a timer: the loop runs the batch on).
        if self.app._batch_count:
            self.set_timer(0.001, self._compositor_refresh, name="frame after the batch")
            return
        drawing = self.is_current
        super()._compositor_refresh()
        if drawing and not self._first_frame_drawn:
            self._first_frame_drawn = True
            self.call_later(self.after_first_frame)

    _first_frame_drawn = False
    _styled_at_mount = True  # until the first resume (see _on_screen_resume)

    def _on_screen_resume(self, event: events.ScreenResume) -> None:
        # Textual (pinned 8.2) restyles every widget of a screen each time it resumes; a screen
        # just pushed was styled as its widgets mounted, before this first resume, and nothing
        # has changed since: MAIN MENU was styled twice before its first frame (issue 25, the
        # start). Later resumes (a screen above it gone) restyle as Textual does.
        if self._styled_at_mount:
            self._styled_at_mount = False
            event.refresh_styles = False

    def after_first_frame(self) -> None:
        """Once the screen's first frame is drawn: what it does not show yet (issue 25, the start)."""

    # -- the state ------------------------------------------------------------------------
    @property
    def key_state(self) -> str:
        """The screen's one state value (its STATES name it)."""
        return ""

    def check_action(self, action: str, parameters: tuple[object, ...]) -> bool | None:
        states = self.STATES.get(action)
        return True if states is None else self.key_state in states

    def bound_here(self, key: str) -> bool:
        """True when ``key`` runs a binding that is switched on (this screen's, its focused
        widget's or the app's)."""
        active = self.active_bindings.get(key)
        return active is not None and active.enabled

    # -- the one key path ---------------------------------------------------------------------
    def on_key(self, event: events.Key) -> None:
        self.before_key(event)
        line = self.line_taking_keys()
        if line is not None and type_ahead(event, line):
            return  # text, RETURN or BACKSPACE: the line's, in the order typed
        if self.bound_here(event.key):
            return  # the app runs the binding (HELP's too: screen.help)
        if line is not None:
            return  # a key the open line has no use for (TAB, a function key bound nowhere)
        if self.other_key(event):
            self._take(event)
        elif event.key == "enter" and getattr(self.app, "keys_1985", False):
            self._take(event)  # 1985 ignored a RETURN that meant nothing ("DEMO3.SET" RETURN RETURN)
        elif not keymap.is_silent(event) and event.key != "ctrl+c":
            self._take(event)
            self.wrong_key(event)

    @staticmethod
    def _take(event: events.Key) -> None:
        event.stop()
        event.prevent_default()

    def before_key(self, event: events.Key) -> None:
        """Every key first (e.g. the model alone goes at any key)."""

    def line_taking_keys(self) -> Input | None:
        """The open line every key goes to in the present state (None: keys are single keys)."""
        return None

    def other_key(self, event: events.Key) -> bool:
        """A key no binding took, the line closed: True if the screen used it."""
        return False

    def wrong_key(self, event: events.Key) -> None:
        """A key that means nothing here: the one wrong-key message."""
        self.say_wrong_key(keymap.unknown_key(event, self.unknown_key_hint(), legends.help_hint(self)))

    def unknown_key_hint(self) -> str:
        """What a key that is no key here may have meant (with the keys bound now)."""
        return self.UNKNOWN_KEY_HINT.format(val=legends.key_for(self, "val", "V"))

    def say_wrong_key(self, text: str) -> None:
        """The one wrong-key message, where this screen shows messages."""
        self.notify(text, severity="warning")

    def action_help(self) -> None:
        """? / F1: the screen's help."""


class KeyedModalScreen(KeyedScreen[ResultT], ModalScreen[ResultT]):
    """A question shown over the screen below (quit, the I/O panel, a file changed)."""
