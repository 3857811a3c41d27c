"""``valterm replay FILE``: a session record (``valterm --record``, core/files/record.py) played
in the app through the demo's player (ui/demo.py): each key pressed as the student typed it,
at the pace they typed it (``--speed`` faster; a long pause is shortened), on the keyboard,
set-up, rules and robot the session started with, into a fresh workspace (or ``--workspace``).
A caption line says where the replay is; any key hands the app to the instructor.

A key the student typed while the app was idle is pressed once the replay's app is idle too
(its motion or program has ended), so the replay reaches the same files and transcript on a
slower or faster machine; a key typed while something played (CTRL-C, type-ahead) is pressed
at its time.
"""

from __future__ import annotations

import asyncio
import math
import sys
import time
from collections.abc import Callable
from pathlib import Path

from rich.text import Text
from textual import events

from valterm.core.files.record import Record, RecordError, read_record
from valterm.core.render.clock import DEFAULT_RATE
from valterm.core.rules import RULES
from valterm.core.val.limits import RunLimits
from valterm.ui.app import KEYBOARDS
from valterm.ui.demo import START_DELAY, DemoApp, play

LONGEST_GAP = 5.0  # seconds: a longer pause of the student's is shortened to this (before --speed)


def _clock_text(seconds: float) -> str:
    minutes, rest = divmod(int(seconds), 60)
    return f"{minutes}:{rest:02d}"


def _limits(given: object) -> RunLimits | None:
    """The session's run limits as its record says them (None: the defaults)."""
    if not isinstance(given, dict):
        return None
    values = [given.get(name) for name in ("steps", "seconds", "lines")]
    if not all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in values):
        return None
    steps, seconds, lines = values
    return RunLimits(int(steps), float(seconds), int(lines))  # type: ignore[arg-type]


class ReplayApp(DemoApp):
    """The app driven by a record's keys until the record ends or the instructor takes over."""

    def __init__(self, record: Record, name: str, *, speed: float = 1.0, once: bool = False,
                 workspace: Path | None = None, motion_rate: float = DEFAULT_RATE,
                 clock: Callable[[], float] = time.monotonic, ascii: bool = False) -> None:
        header = record.header

        def said(key: str) -> str | None:
            value = header.get(key)
            return value if isinstance(value, str) and value else None

        keys, rules = said("keys"), said("rules")
        super().__init__([], speed=speed, idle=math.inf, once=once, motion_rate=motion_rate, clock=clock,
                         ascii=ascii, keys=keys if keys in KEYBOARDS else "modern",
                         setup=said("setup"), rules=rules if rules in RULES else None, robot=said("robot"),
                         limits=_limits(header.get("limits")))
        if workspace is not None:
            self.workspace_root = workspace
        self.record = record
        self.record_name = name
        self.pressed = 0  # keys of the record pressed so far
        self.finished = False  # every key of the record pressed and handled

    async def _play(self) -> None:
        self._show_progress()
        await self._wait(START_DELAY)
        previous = 0.0
        for number, key in enumerate(self.record.keys, start=1):
            await self._wait(min(max(key.at - previous, 0.0), LONGEST_GAP))
            previous = key.at
            if not key.busy:
                await self._idle()  # typed at an idle app: pressed at an idle app
            self.pressed = number
            self._show_progress()
            if key.paste is not None:
                await self._paste(key.paste)
            else:
                await self.press_demo_key(key.key, key.char)
        await self._settle()
        self._stage_over()
        self._record_over()

    async def _paste(self, text: str) -> None:
        """Paste ``text`` as the terminal did (to the app, which hands it to the focused line)."""
        self.post_message(events.Paste(text))
        await self._handled(self)
        target = self.focused or self.screen
        for node in (target, *target.ancestors):
            await self._handled(node)

    async def _idle(self) -> None:
        """No motion, no key waiting, and every node of the screen on top has handled what it
        was sent (a screen just opened has focused its line): as Pilot waits between keys."""
        await self._settle()
        for _ in range(2):  # a second round: what the first round's messages started
            nodes = [self, *self.screen.walk_children(with_self=True)] if self.screen_stack else [self]
            await asyncio.gather(*(self._handled(node) for node in nodes))

    def exit(self, result: int | None = None, return_code: int = 0, message: object = None) -> None:
        """The student's own exit (CTRL-Q, S at MAIN MENU) is the end of the record, not of
        the replay: the instructor stays on the last screen (``--once`` and CTRL-Q leave)."""
        if self.playing and not self._leaving and return_code == 0:
            self.workers.cancel_group(self, "demo")
            self.call_later(self._record_over, "the student left the simulator here")
            return
        super().exit(result, return_code, message)

    def _record_over(self, how: str = "") -> None:
        self.finished = True
        if self.once:
            self.leave(0)
            return
        self.playing = False
        self.show_caption(f"END OF THE RECORD {self.record_name}{': ' + how if how else ''} "
                          f"({len(self.record.keys)} keys, {_clock_text(self.record.seconds)}). "
                          "The app is yours: Ctrl-Q leaves.")

    def _show_progress(self) -> None:
        at = self.record.keys[self.pressed - 1].at if self.pressed else 0.0
        self.caption = (f"REPLAY OF {self.record_name} ({self.record.header.get('started', '?')}): "
                        f"key {self.pressed} of {len(self.record.keys)}, {_clock_text(at)} of "
                        f"{_clock_text(self.record.seconds)}")
        self._update_caption(self.screen)

    def _caption_text(self) -> Text:
        text = Text(self.caption, style="bold")
        if self.playing:
            text.append("  Press any key to take over.", style="italic")
        return text

    def visitor_caption(self) -> str:
        return (f"You have the keys: the replay stopped at key {self.pressed} of {len(self.record.keys)}. "
                "Ctrl-Q leaves.")


def run_replay(path: str | Path, *, speed: float = 1.0, once: bool = False, workspace: Path | None = None,
               ascii: bool = False, headless: bool = False) -> int:
    """Replay the record at ``path``; 1 when it cannot be read or the app stopped on an error."""
    try:
        record = read_record(path)
    except RecordError as error:
        print(f"valterm: replay: {error}", file=sys.stderr)
        return 1
    app = ReplayApp(record, Path(path).name, speed=speed, once=once, workspace=workspace, ascii=ascii)
    return play(app, headless, "valterm: replay: the replay stopped on an error (shown above)")
