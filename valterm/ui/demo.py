"""Demonstration mode (museum use): the app plays assets/DEMO.KEYS, the example session
of App. C, key by key through the real screens, with a caption line saying in plain words what
happens and why. It loops forever. Any key pauses it and hands the app to the visitor; after
``idle`` seconds without a key the demo starts again from a clean state (a fresh workspace,
a fresh start screen). ``kiosk`` also turns off the keys that would end the program (Ctrl-Q,
S at the MAIN MENU), so a visitor's random keys never end it.
"""

from __future__ import annotations

import asyncio
import shutil
import sys
import tempfile
import time
import unicodedata
from collections import deque
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from rich.text import Text
from textual import events
from textual.app import ScreenStackError
from textual.dom import DOMNode
from textual.keys import _character_to_key, _get_unicode_name_from_key
from textual.message_pump import MessagePump
from textual.screen import Screen
from textual.widgets import Static

from valterm.core.errors import ValtermError
from valterm.core.events import Event
from valterm.core.files.demokeys import DemoItem, DemoScriptError, load_demo
from valterm.core.render.clock import DEFAULT_RATE
from valterm.core.render.raster import ViewTransform
from valterm.core.text.transcript import event_lines
from valterm.ui.app import ValtermApp, end_on_hangup
from valterm.ui.errors import error_text

KEY_GAP = 0.6      # seconds between single keys (before the speed factor)
CHAR_GAP = 0.09    # seconds between typed characters
START_DELAY = 1.5  # seconds before the first key of a round
IDLE_RESTART = 60.0
HANDLED_LIMIT = 10.0  # seconds a key may take to be handled (a guard, never reached)
SETTLE_LIMIT = 120.0  # seconds a motion may hold the next key back (a program that never ends)
DEMO_HINT = "Press any key to try it yourself."
QUIT_KEYS = ("ctrl+q",)  # Textual's quit; the MAIN MENU's S (STOP) is handled apart
CAPTIONS_KEPT = 1000  # a kiosk runs for months: only the last ones
STAGE_LINES_KEPT = 500  # of what one stage printed: its last lines
DEMO_TAG = "_valterm_demo"  # set on the key events the demo itself presses


def visitor_text(idle: float) -> str:
    return (f"Your turn: the menu on the screen says which key does what. "
            f"The demonstration starts again after {idle:g} s without a key.")


@dataclass(frozen=True)
class Stage:
    """One caption's stage of a round: the caption, the ``=`` claims the script makes about it,
    and what the stage printed (every line its motions and programs printed, and what the
    VAL-II transcript gained), so a test checks the caption against the run."""

    caption: str
    claims: tuple[str, ...]
    printed: tuple[str, ...]


class Caption(Static):
    """The caption line over every screen of the demo."""

    DEFAULT_CSS = """
    Caption {
        dock: top;
        height: auto;
        max-height: 3;
        padding: 0 1;
        background: $accent-darken-2;
        color: $text;
    }
    Caption.-visitor { background: $success-darken-3; }
    """


class DemoApp(ValtermApp):
    """ValtermApp driven by the key script until a visitor presses a key (its CSS_PATH,
    absolute, is the app's)."""

    def __init__(self, items: list[DemoItem], *, speed: float = 1.0, idle: float = IDLE_RESTART,
                 once: bool = False, kiosk: bool = False, motion_rate: float = DEFAULT_RATE,
                 clock: Callable[[], float] = time.monotonic, ascii: bool = False,
                 keys: str = "1985", **options: Any) -> None:
        self._folder = Path(tempfile.mkdtemp(prefix="valterm-demo-"))
        self._previous: Path | None = None
        # keys 1985: the tables typed as printed (DEMO.KEYS); a replay passes the record's
        # keyboard and set-up (``options``: the app's setup, rules, robot)
        super().__init__(self._folder / "ws", ascii=ascii, clock=clock, motion_rate=motion_rate * speed,
                         keys=keys, **options)
        self.items = [item for item in items if not item.replay_only]
        self.speed = speed
        self.idle = idle
        self.once = once
        self.kiosk = kiosk
        self.playing = False   # the demo has the keys (False: the visitor has them)
        self.rounds = 0        # rounds started
        self.caption = ""
        self.captions: deque[str] = deque(maxlen=CAPTIONS_KEPT)  # the captions shown, in order (tests)
        self.stages: deque[Stage] = deque(maxlen=CAPTIONS_KEPT)  # each caption's stage, once over (tests)
        self._printed: deque[str] = deque(maxlen=STAGE_LINES_KEPT)
        self._claims: list[str] = []
        self._stage_caption = ""
        self._transcript_at: tuple[object, int] = (None, 0)
        self._last_key = time.monotonic()
        self._leaving = False
        self._forwarded: asyncio.Future[DOMNode] | None = None

    # -- starting and looping ------------------------------------------------------
    def on_mount(self) -> None:
        super().on_mount()
        self.screen_change_signal.subscribe(self, self._screen_changed)
        self._screen_changed(self.screen)
        self.set_interval(min(1.0, max(self.idle / 4, 0.05)), self._check_idle, name="demo-idle")
        self._start_round()

    def on_unmount(self) -> None:
        for folder in (self._folder, self._previous):
            if folder is not None:
                shutil.rmtree(folder, ignore_errors=True)

    def _start_round(self) -> None:
        self.rounds += 1
        self.playing = True
        if not self.items or self.items[0].kind != "caption":
            self.show_caption(DEMO_HINT)
        self.run_worker(self._played(), group="demo", exclusive=True, exit_on_error=True)

    async def _fresh_round(self) -> None:
        """A clean state: no motion, a fresh workspace and session, the start screen."""
        from valterm.ui.screens.start import StartScreen

        if not self.is_running:
            return  # closing: its screens are going, no round starts on them
        self.workers.cancel_group(self, "demo")
        self.action_abort()
        old, self._folder = self._folder, Path(tempfile.mkdtemp(prefix="valterm-demo-"))
        self.workspace_root = self._folder / "ws"
        self.session = None
        self._workspace = None
        self.view_transform = ViewTransform()
        self.back_faces = False
        self.axes = False
        while len(self.screen_stack) > 2:
            await self.pop_screen()
        await self.switch_screen(StartScreen())
        # the last round's folder goes one round later: a program the visitor left running
        # may still write its CHECK.DAT there as it is closed
        if self._previous is not None:
            shutil.rmtree(self._previous, ignore_errors=True)
        self._previous = old
        self._start_round()

    def _round_over(self) -> None:
        if self.once:
            self.leave(0)
        else:
            self.call_later(self._fresh_round)

    def leave(self, return_code: int = 0) -> None:
        """End the demo (``--once``, or a quit key outside kiosk mode)."""
        self._leaving = True
        self.exit(return_code, return_code=return_code)

    def exit(self, result: int | None = None, return_code: int = 0, message: object = None) -> None:
        """In kiosk mode nothing a visitor does ends the program: a quit starts the demo again."""
        if self.kiosk and not self._leaving and return_code == 0:
            self.call_later(self._fresh_round)
            return
        super().exit(result, return_code, message)  # type: ignore[arg-type]

    # -- playing the script -------------------------------------------------------------
    async def _wait(self, seconds: float) -> None:
        await asyncio.sleep(seconds / self.speed)

    async def _settle(self) -> None:
        """Let a motion or a running program finish before the next key."""
        limit = time.monotonic() + SETTLE_LIMIT
        while (self.moving or self.keys_waiting) and time.monotonic() < limit:
            await asyncio.sleep(0.05)

    async def _played(self) -> None:
        """The round, ended quietly when the app closes under it (a test's run_test ends, the
        kiosk is stopped): its screens are popped while the round waits for a key to be handled,
        and the round's next look at the screen finds none. While the app runs that is a bug."""
        try:
            await self._play()
        except ScreenStackError:
            if self.is_running:
                raise

    async def _play(self) -> None:
        started = False
        for item in self.items:
            if not started and item.kind != "caption":
                await self._wait(START_DELAY)  # the first caption is read before the first key
                started = True
            if item.kind == "caption":
                await self._settle()  # the stage before it is over
                self.show_caption(item.value)
            elif item.kind == "claim":
                self._claims.append(item.value)
            elif item.kind == "pause":
                await self._settle()
                await self._wait(item.seconds)
            else:
                gap = CHAR_GAP if item.kind == "text" else KEY_GAP
                for key in item.keys():
                    await self._settle()
                    await self.press_demo_key(key)
                    await self._wait(gap)
        await self._settle()
        self._stage_over()
        await self._wait(START_DELAY)
        self._round_over()

    async def press_demo_key(self, key: str, char: str | None = "") -> None:
        """Press one key as a visitor would, marked as the demo's, and wait until it is handled
        everywhere it goes (so a key that opens a screen is done before the next key comes).
        ``char``: the character it types, "" to find it from the key's name (a record keeps
        both, as typed)."""
        if char == "":
            if len(key) == 1 and not key.isalnum():
                key = _character_to_key(key)
            try:
                char = unicodedata.lookup(_get_unicode_name_from_key(key))
            except KeyError:
                char = key if len(key) == 1 else None
        event = events.Key(key, char)
        setattr(event, DEMO_TAG, True)
        event.set_sender(self)
        forwarded = self._forwarded = asyncio.get_running_loop().create_future()
        self.post_message(event)
        await asyncio.wait([forwarded], timeout=HANDLED_LIMIT)
        if not forwarded.done():
            return  # the app is stuck elsewhere: the next key's gap gives it time
        # the key went to the focused widget (or the screen) and bubbles up to the app:
        # each queue on the way has handled it once a callback posted after it has run
        target = forwarded.result()
        self._forwarded = None  # no old screen kept alive by the last key
        for node in (target, *target.ancestors):
            await self._handled(node)

    async def _handled(self, node: MessagePump) -> None:
        done: asyncio.Future[None] = asyncio.get_running_loop().create_future()

        def reached() -> None:
            if not done.done():
                done.set_result(None)

        if node.call_later(reached):
            await asyncio.wait([done], timeout=HANDLED_LIMIT)

    # -- the visitor ----------------------------------------------------------------------
    async def on_event(self, event: events.Event) -> None:
        if isinstance(event, events.Key) and not event.is_forwarded:
            if getattr(event, DEMO_TAG, False):
                target = self.focused or self.screen  # where Textual forwards it
                await super().on_event(event)
                if self._forwarded is not None and not self._forwarded.done():
                    self._forwarded.set_result(target)
                return
            if not self._visitor_key(event):
                return
        await super().on_event(event)

    def _visitor_key(self, event: events.Key) -> bool:
        """A key of the visitor: take over from the demo; False when the key is swallowed."""
        self._last_key = time.monotonic()
        if self.playing:
            self.playing = False  # the visitor takes over where the demo stands
            self.workers.cancel_group(self, "demo")
            self.show_caption(self.visitor_caption())
            return False  # the first key only wakes the app up
        if event.key in QUIT_KEYS or self._stops_at_main_menu(event):
            if self.kiosk:
                self.show_caption("This demonstration cannot be ended from the keyboard. " + self.visitor_caption())
                return False
            if event.key in QUIT_KEYS:
                self.leave(0)
                return False
        if self.caption != self.visitor_caption():
            self.show_caption(self.visitor_caption())
        return True

    def visitor_caption(self) -> str:
        """The caption while the visitor has the keys."""
        return visitor_text(self.idle)

    def _stops_at_main_menu(self, event: events.Key) -> bool:
        """S at the MAIN MENU (no question open) is STOP: it leaves the program."""
        from valterm.ui.screens.main_menu import MainMenuScreen

        screen = self.screen
        return (event.key in ("s", "S") and isinstance(screen, MainMenuScreen)
                and not screen.asking)

    def _check_idle(self) -> None:
        if not self.is_running or self.playing or time.monotonic() - self._last_key < self.idle:
            return
        if self.once:
            self.leave(0)
            return
        self.playing = True  # no second restart while this one is under way
        self.call_later(self._fresh_round)

    # -- what each stage printed ------------------------------------------------------------
    def run_events(self, events: Iterable[Event], origin: object = None) -> None:
        super().run_events(self._recorded(events), origin)

    def _recorded(self, events: Iterable[Event]) -> Iterator[Event]:
        """The events as played, each one's lines (the one renderer's) kept for the stage."""
        source = iter(events)
        try:
            for event in source:
                self._printed.extend(event_lines(event))
                yield event
        except ValtermError as error:  # a refusal: the player shows it, the stage keeps it
            self._printed.append(error_text(error))
            raise
        finally:
            close = getattr(source, "close", None)
            if close is not None:
                close()  # an aborted motion ends where it stood, as the player would end it

    def _transcript(self) -> tuple[object, list[str]]:
        screen = self.screen if self.screen_stack else None
        lines = getattr(screen, "transcript", None)
        return screen, [str(line) for line in lines] if isinstance(lines, deque) else []

    def _stage_over(self) -> None:
        """The stage of the caption shown is over: keep what it printed."""
        screen, lines = self._transcript()
        was, length = self._transcript_at
        gained = lines[length:] if screen is was and len(lines) >= length else lines
        if self._stage_caption:
            played = set(self._printed)  # the transcript shows the events' lines again
            printed = (*self._printed, *(line for line in gained if line not in played))
            self.stages.append(Stage(self._stage_caption, tuple(self._claims), printed))
        self._stage_caption = ""
        self._printed.clear()
        self._claims = []
        self._transcript_at = (screen, len(lines))

    # -- the caption line -----------------------------------------------------------------
    def show_caption(self, text: str) -> None:
        self._stage_over()
        self._stage_caption = text if self.playing else ""  # the visitor's turn is no stage
        self.caption = text
        self.captions.append(text)
        self._update_caption(self.screen)

    def _caption_text(self) -> Text:
        text = Text(self.caption, style="bold")
        if self.playing and DEMO_HINT not in self.caption:
            text.append("  " + DEMO_HINT, style="italic")
        return text

    def _screen_changed(self, screen: Screen[object]) -> None:
        self.call_after_refresh(self._update_caption, screen)

    def _update_caption(self, screen: Screen[object]) -> None:
        """Put the caption line on ``screen`` (every screen gets its own, docked on top)."""
        if not screen.is_attached:
            return
        found = screen.query(Caption)
        if found:
            caption = found.first()
        else:
            caption = Caption(id="demo-caption")
            screen.mount(caption)
        caption.set_class(not self.playing, "-visitor")
        caption.update(self._caption_text())


def run_demo(*, speed: float = 1.0, once: bool = False, kiosk: bool = False, idle: float = IDLE_RESTART,
             script: str | Path | None = None, ascii: bool = False, headless: bool = False) -> int:
    """Run the demo until it is ended (never, in kiosk mode); 1 when it stopped on an error."""
    try:
        items = load_demo(script)
    except DemoScriptError as error:
        print(f"valterm: demo: {error}", file=sys.stderr)
        return 1
    app = DemoApp(items, speed=speed, once=once, kiosk=kiosk, idle=idle, ascii=ascii)
    return play(app, headless, "valterm: demo: the demonstration stopped on an error (shown above)")


def play(app: DemoApp, headless: bool, stopped: str) -> int:
    """Run a demo or a replay until it ends: 0, or 1 with ``stopped`` said when it stopped on
    an error. On a terminal, a hangup ends it (``end_on_hangup``)."""
    if not headless:
        end_on_hangup()
    app.run(headless=headless)
    if app.return_code:
        print(stopped, file=sys.stderr)
        return 1
    return 0
