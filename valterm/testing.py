"""Drive the VAL-II SIMULATOR from a script: grading exercises, checking a kiosk, tests.

A :class:`Simulation` is the whole app running headless at a chosen terminal size, on a
workspace folder and a set-up file, with the animation clock in the script's hands::

    import asyncio
    from valterm.testing import Simulation

    async def main() -> None:
        async with Simulation(workspace="my-workspace", setup="PROCESS", size=(80, 24)) as sim:
            await sim.press("K")                      # the KEYBOARD MENU
            await sim.type("LLISTF", enter=True)      # L, then LISTF and RETURN
            assert "PROCESS.DAT" in sim.text()
            print(sim.status())                       # the status line, as text

    asyncio.run(main())

What a script can do:

- ``press(*keys)`` and ``type(text, pace=...)``: keys by Textual's names (``"enter"``,
  ``"escape"``, ``"f1"``, ``"ctrl+c"``, ``"K"``); text one character at a time, ``pace``
  seconds apart (0.3 is a person typing).
- ``rows()`` / ``text()``: the terminal as text rows, exactly what a user sees;
  ``status()``, ``messages()``, ``prompt()``, ``readout()``, ``transcript()``: the parts.
- ``where()``: the robot's position (the core's ``Where``: xyz, oat, joints, config,
  clamp) as data; ``simulator`` and ``session`` for anything else.
- The clock: with ``animate=False`` (the default) every motion shows its last pose at once.
  With ``animate=True`` motions run at ``rate`` steps a second of the script's clock, which
  moves only when the script calls ``await sim.advance(seconds)``; ``await sim.settle()``
  runs the clock on until nothing moves.

``keys="1985"`` types as the thesis's tables do (valterm --keys 1985); ``rules`` picks the
joint-state rules ("1985" or "controller"; None: the dialect's).

Everything here uses Textual's public API (``App.run_test``, ``Pilot``,
``App.export_screenshot``); the screen text is read back from the same picture a
screenshot shows.
"""

from __future__ import annotations

import html
import math
import re
import time
from pathlib import Path
from types import TracebackType
from typing import Any, Self

from textual import events

__all__ = ["ScriptClock", "Simulation", "screen_rows"]


TAKE_LIMIT = 30.0  # seconds a key press waits for the app to take it (a guard on a loaded machine)
_CHARACTERS = {"space": " ", "enter": "\r", "tab": "\t", "escape": "\x1b", "backspace": "\x7f",
               "question_mark": "?", "plus": "+", "minus": "-", "comma": ",", "full_stop": ".",
               "ctrl+c": "\x03"}


def _character(key: str) -> str | None:
    """The character a key types (None for keys that type nothing: arrows, F-keys)."""
    if len(key) == 1:
        return key
    return _CHARACTERS.get(key)


class ScriptClock:
    """The animation clock, moved only by the script (``advance``)."""

    def __init__(self, start: float = 1000.0) -> None:
        self.t = start

    def __call__(self) -> float:
        return self.t

    def advance(self, seconds: float) -> None:
        self.t += seconds


_TEXT = re.compile(
    r'<text class="[^"]*" x="([\d.]+)" y="[\d.]+" textLength="([\d.]+)" '
    r'clip-path="url\(#[^)]*-line-(\d+)\)">(.*?)</text>')


def screen_rows(app: Any) -> list[str]:
    """The running app's terminal as text rows (trailing blanks removed).

    Read from ``App.export_screenshot()`` (public): each run of text there carries its row
    and its column in cell widths.
    """
    width, height = app.size
    grid = [[" "] * width for _ in range(height)]
    cell = 0.0
    for x, length, line, raw in _TEXT.findall(app.export_screenshot()):
        text = html.unescape(raw).replace("\xa0", " ")
        if not text:
            continue
        if not cell:
            cell = float(length) / len(text)  # the width of one terminal cell in the picture
        row, column = int(line), round(float(x) / cell)
        if not 0 <= row < height:
            continue
        for i, char in enumerate(text):
            if 0 <= column + i < width:
                grid[row][column + i] = char
    return ["".join(row).rstrip() for row in grid]


class Simulation:
    """The app, headless, for a script (an async context manager)."""

    def __init__(self, workspace: str | Path, setup: str | None = "PROCESS", *,
                 size: tuple[int, int] = (80, 24), animate: bool = False, rate: float = 10.0,
                 ascii: bool = False, robot: str | None = None, keys: str | None = None,
                 rules: str | None = None) -> None:
        from valterm.ui.app import ValtermApp

        self.clock = ScriptClock()
        self.app = ValtermApp(workspace, setup, ascii=ascii, clock=self.clock,
                              motion_rate=rate if animate else math.inf, robot=robot, keys=keys,
                              rules=rules)
        self.size = size
        self._context: Any = None
        self.pilot: Any = None

    async def __aenter__(self) -> Self:
        self._context = self.app.run_test(size=self.size)
        self.pilot = await self._context.__aenter__()
        await self.pilot.pause()
        return self

    async def __aexit__(self, kind: type[BaseException] | None, error: BaseException | None,
                        trace: TracebackType | None) -> None:
        await self._context.__aexit__(kind, error, trace)

    # -- keys ------------------------------------------------------------------------
    async def press(self, *keys: str, pace: float = 0.0) -> None:
        """Press keys by name, ``pace`` seconds apart (real time)."""
        for key in keys:
            await self.pilot.press(key)
            await self.pilot.pause(pace or None)
            await self._taken()

    async def burst(self, *keys: str) -> None:
        """Queue keys all at once, as a fast typist or a paste does, then wait for the app.

        Much faster than ``press`` (one wait for the lot); keys by the same names.
        """
        for key in keys:
            self.app.post_message(events.Key(key, _character(key)))
        await self.pilot.pause()
        await self._taken()

    async def paste(self, text: str) -> None:
        """Paste ``text`` (bracketed paste) into whatever has the focus."""
        target = self.app.focused or self.screen
        target.post_message(events.Paste(text))
        await self.pilot.pause()
        await self._taken()

    async def _taken(self) -> None:
        """Until the app has taken the keys: the screen on top mounted (a key may have opened
        it) and the last key handed on handled. One Pilot pause is not always enough on a
        loaded machine, and a script would then read a screen not yet built."""
        queue = getattr(self.app, "key_queue", None)
        end = time.monotonic() + TAKE_LIMIT
        while queue is not None and self.app.is_running and queue.changing and time.monotonic() < end:
            await self.pilot.pause(0.01)

    async def type(self, text: str, *, enter: bool = False, pace: float = 0.0) -> None:
        """Type ``text`` a character at a time (then RETURN when ``enter``)."""
        await self.press(*text, *(("enter",) if enter else ()), pace=pace)

    # -- the clock ---------------------------------------------------------------------
    @property
    def moving(self) -> bool:
        return bool(getattr(self.app, "moving", False))

    async def advance(self, seconds: float) -> None:
        """Move the animation clock on and let the app draw what is due."""
        self.clock.advance(seconds)
        await self.pilot.pause(0.12)  # the motion timer polls the clock ten times a second
        await self.pilot.pause()

    async def settle(self, step: float = 1.0, limit: int = 600) -> None:
        """Run the clock on until no motion plays (at most ``limit`` steps)."""
        for _ in range(limit):
            if not self.moving:
                break
            await self.advance(step)
        await self.pilot.pause()

    # -- what is on the screen -----------------------------------------------------------
    def rows(self) -> list[str]:
        """The terminal as text rows."""
        return screen_rows(self.app)

    def text(self) -> str:
        return "\n".join(self.rows())

    @property
    def screen(self) -> Any:
        return self.app.screen

    def _widget_text(self, selector: str) -> str:
        found = self.screen.query(selector)
        if not found:
            return ""
        widget = found.first()
        text = getattr(widget, "text", None)
        if isinstance(text, str):
            return text
        return str(widget.render())

    def status(self) -> str:
        """The status line: set-up and saved state, SPEED, checks, faces, axes, configurations."""
        return self._widget_text("#status")

    def messages(self) -> list[str]:
        """The message lines under the menu, top to bottom (those scrolled out of view too)."""
        log = self.screen.query("#messages")
        if log:
            text: str = log.first().text
            return text.splitlines()
        message = getattr(self.screen, "message", "")
        return str(message).splitlines()

    def prompt(self) -> str:
        """The open question, or "" when the screen waits at its menu."""
        prompt = self.screen.query("#prompt")
        if prompt and prompt.first().has_class("-active"):
            return str(prompt.first().question)
        return str(getattr(self.screen, "prompt", "") or "") if not prompt else ""

    def readout(self) -> list[str]:
        """The readout under the menu (Fig. 2-8 or Fig. 4-2) as lines; [] when none shows."""
        found = self.screen.query("#readout")
        if not found or found.first().has_class("-hidden"):
            return []
        return str(found.first().render()).splitlines()

    def transcript(self) -> list[str]:
        """The VAL-II transcript (VAL-II mode), else the message lines."""
        transcript = getattr(self.screen, "transcript", None)
        if transcript is not None:
            return [str(line) for line in transcript]
        return self.messages()

    # -- the model as data ---------------------------------------------------------------
    @property
    def session(self) -> Any:
        return self.app.session

    @property
    def simulator(self) -> Any:
        return self.app.simulator

    def where(self, point: int = 1) -> Any:
        """The clamp position, orientation, joints and indicators (the core's ``Where``)."""
        return self.simulator.where(point)
