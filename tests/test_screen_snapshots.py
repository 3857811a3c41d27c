"""Snapshots of every screen at 80x24 and 160x50 (issue 27): START, MAIN, KEYBOARD, PENDANT,
MANIPULATION, VAL-II mode (menu and line), EDITOR (and its save question), HELP, the I/O
panel and the quit question.

Regenerate with ``pytest tests/test_screen_snapshots.py --snapshot-update`` after a
deliberate change of a screen. No motion plays and no cursor blinks when the picture is
taken; the workspace is the test's own (no path of it is shown).
"""

from __future__ import annotations

from pathlib import Path

import pytest
from app_helpers import make_app, until
from textual.widgets import Input

SIZES = [(80, 24), (160, 50)]
SCREENS = {
    "start": [],
    "main": [],
    "keyboard": ["K"],
    "pendant": ["P"],
    "manipulation": ["M", "1", "enter"],
    "valmode-menu": ["V"],
    "valmode-line": ["V", "V", *"WHERE", "enter"],
    "editor": ["E", *"TEST", "enter"],
    "help": ["question_mark"],
    "io-panel": ["V", "V", "f10"],
    "editor-save": ["E", *"TEST", "enter", "C", *" MOVE A", "enter", "escape", "E"],
    "quit": ["V", "V", *"HERE P1", "enter", "ctrl+q"],
}


@pytest.mark.parametrize("size", SIZES, ids=lambda s: f"{s[0]}x{s[1]}")
@pytest.mark.parametrize("screen", list(SCREENS))
def test_screen_snapshot(snap_compare, tmp_path: Path, screen: str, size: tuple[int, int]) -> None:  # type: ignore[no-untyped-def]
    app = make_app(tmp_path / "ws", start=screen == "start")

    # The keys are pressed here, not by snap_compare's press=, so that the picture waits for
    # what they started: a command plays on the player's timer, and a slow host took the
    # picture while WHERE still played (CI, valmode-line-80x24). An Input the keys opened
    # has its blink stopped too.
    async def press_then_still(pilot) -> None:  # type: ignore[no-untyped-def]
        await pilot.pause()
        await pilot.press(*SCREENS[screen])
        await until(pilot, lambda: not app.player.playing, "the keys' command has ended")
        for field in app.screen.query(Input):
            field.cursor_blink = False
        await pilot.pause()

    assert snap_compare(app, terminal_size=size, run_before=press_then_still)
