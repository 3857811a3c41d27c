"""Demonstration mode (museum use): the app replays valterm/data/DEMO.KEYS at a watchable pace,
with the table's EXPLANATION as a caption. Any key hands control to the visitor; an idle
minute restarts the demo from a fresh copy of the thesis's files.
"""

from __future__ import annotations

import asyncio
import shutil
import tempfile
import time
from pathlib import Path

from textual import events

from valterm.commands.demo import DemoItem, load_demo
from valterm.ui.app import ValtermApp

KEY_GAP = 0.6    # seconds between single keys (before --speed)
CHAR_GAP = 0.09  # seconds between typed characters
IDLE_RESTART = 60.0
RESTART = 2      # the app's return value that asks run_demo for another round


class DemoApp(ValtermApp):
    """ValtermApp driven by the key script until a visitor presses a key."""

    def __init__(self, workspace: str | Path, items: list[DemoItem], *, speed: float = 1.0,
                 idle_restart: float = IDLE_RESTART) -> None:
        super().__init__(workspace)
        self.items = [item for item in items if not item.replay_only]
        self.speed = speed
        self.idle_restart = idle_restart
        self.demo_running = True
        self.caption = ""
        self._injecting = False
        self._last_key = time.monotonic()

    def on_mount(self) -> None:
        super().on_mount()
        self.sub_title = "DEMONSTRATION: PRESS ANY KEY TO TAKE OVER"
        self.run_worker(self._play(), exclusive=True, group="demo")
        self.set_interval(5.0, self._check_idle, name="demo-idle")

    async def _play(self) -> None:
        await asyncio.sleep(1.5 / self.speed)
        for item in self.items:
            if not self.demo_running:
                return
            if item.kind == "caption":
                self.caption = item.value
                self.sub_title = f"DEMO: {item.value}"
                continue
            if item.kind == "pause":
                await asyncio.sleep(item.seconds / self.speed)
                continue
            gap = CHAR_GAP if item.kind == "text" else KEY_GAP
            for key in item.keys():
                if not self.demo_running:
                    return
                self._injecting = True
                try:
                    await self._press_keys([key])
                finally:
                    self._injecting = False
                await asyncio.sleep(gap / self.speed)
        await asyncio.sleep(3.0 / self.speed)
        if self.demo_running:
            self.exit(RESTART)

    async def on_event(self, event: events.Event) -> None:
        if isinstance(event, events.Key) and not self._injecting:
            self._last_key = time.monotonic()
            if self.demo_running:
                # the visitor takes over where the demo stands
                self.demo_running = False
                self.sub_title = "YOUR TURN: AFTER A MINUTE WITHOUT A KEY THE DEMO STARTS AGAIN"
                self.workers.cancel_group(self, "demo")
        await super().on_event(event)

    def _check_idle(self) -> None:
        if not self.demo_running and time.monotonic() - self._last_key > self.idle_restart:
            self.exit(RESTART)


def run_demo(speed: float = 1.0, once: bool = False, workspace: str | Path | None = None) -> int:
    """Loop the demo, each round in a fresh temporary workspace (visitors' files vanish)."""
    items = load_demo()
    while True:
        folder = Path(tempfile.mkdtemp(prefix="valterm-demo-"))
        try:
            app = DemoApp(folder / "ws", items, speed=speed)
            result = app.run()
        finally:
            shutil.rmtree(folder, ignore_errors=True)
        if result != RESTART or once:
            return 0 if result in (None, RESTART) else int(result)
