"""Textual's Linux driver with a FrameGate (terminal_writer): it counts what its writer thread
has not written yet, and takes the terminal's answers to the gate's questions off the input
before they reach the app."""

from __future__ import annotations

from typing import IO, TYPE_CHECKING, Any

from textual import events
from textual.drivers.linux_driver import LinuxDriver
from textual.message import Message

from valterm.ui.terminal_writer import FrameGate

if TYPE_CHECKING:
    from textual.app import App
    from textual.driver import Driver


class CountedOutput:
    """The writer thread's file: tells the gate each write it has done."""

    def __init__(self, file: IO[str], gate: FrameGate) -> None:
        self._file = file
        self._gate = gate

    def write(self, text: str) -> int:
        written = self._file.write(text)
        self._gate.written(text)
        return written

    def flush(self) -> None:
        self._file.flush()

    def fileno(self) -> int:
        return self._file.fileno()

    def isatty(self) -> bool:
        return self._file.isatty()


class GatedDriver(LinuxDriver):
    """LinuxDriver whose frames pass ``gate`` (ValtermApp._display asks it)."""

    def __init__(self, app: App[Any], **options: Any) -> None:
        super().__init__(app, **options)
        self.gate = FrameGate(self.write, self._repaint)
        if self._file is not None:  # sys.__stderr__ (None only without any stderr at all)
            self._file = CountedOutput(self._file, self.gate)  # type: ignore[assignment]

    def write(self, data: str) -> None:
        self.gate.queued(data)
        super().write(data)

    def _repaint(self) -> None:
        """The terminal caught up after skipped frames: the whole screen again, on the
        app's loop (called from the writer or the input thread)."""
        if not self._loop.is_closed():
            self._loop.call_soon_threadsafe(self._app.refresh)

    def start_application_mode(self) -> None:
        self.gate.restart()
        super().start_application_mode()  # type: ignore[no-untyped-call]

    def process_message(self, message: Message) -> None:
        if isinstance(message, events.CursorPosition):  # the answer to the gate's question
            self.gate.answered()
            return
        self.gate.stirred()
        super().process_message(message)


def gated(default: type[Driver]) -> type[Driver]:
    """The driver the app runs on: gated where Textual would use its Linux driver."""
    return GatedDriver if default is LinuxDriver else default
