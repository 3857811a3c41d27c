"""Any exception escaping a screen's handler leaves the app running (issue 27 item 4).

Textual ends a node's message loop, and then the app, on the first exception a handler
raises. A guarded screen that is up hands it to the app's ``survive`` instead (one that
fails while it is being built still ends the app, exit 70): the crash log gets the
traceback, the screen on top gets the one line naming the log, and the session, the
unsaved set-up and the editor's journal stay as they were.
"""

from __future__ import annotations

from textual.message import Message
from textual.message_pump import MessagePump


class Guarded:
    """Mixed into every screen class before ``Screen``."""

    async def _dispatch_message(self, message: Message) -> None:
        try:
            await super()._dispatch_message(message)  # type: ignore[misc]
        except Exception as error:
            app = self.app if isinstance(self, MessagePump) else None
            survive = getattr(app, "survive", None)
            if survive is None or not getattr(self, "_is_mounted", True):
                raise  # a screen (or the app) that never got built: the crash line and exit 70
            survive(error)
