"""A kiosk runs for months: widgets that leave the screen must not stay in memory.

Textual 8.2 keeps every removed widget's render cache alive through an ``lru_cache`` on an
instance method (Textualize/textual#6665); the app clears it now and then
(``valterm.ui.app.release_styles_caches``). Without that, the demo's RSS grew ~10 MB a round.
"""

from __future__ import annotations

import gc
from pathlib import Path

import pytest
from app_helpers import make_app, sync
from textual._styles_cache import StylesCache
from textual.widget import Widget

import valterm.ui.app
from valterm.ui.app import release_styles_caches


def _orphaned_style_caches() -> int:
    """Render caches of widgets that no longer exist."""
    gc.collect()
    live = {id(w._styles_cache) for w in gc.get_objects() if isinstance(w, Widget)}
    return sum(1 for o in gc.get_objects() if isinstance(o, StylesCache) and id(o) not in live)


@sync
async def test_screens_that_come_and_go_leave_no_render_caches_behind(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause()
        for _ in range(12):                      # HELP's screen and its widgets, shown and gone
            await pilot.press("question_mark")
            await pilot.pause()
            await pilot.press("escape", "escape")
            await pilot.pause()
        assert _orphaned_style_caches() > 12     # what Textual's cache keeps (the bug is there)
        release_styles_caches()
        assert _orphaned_style_caches() == 0


@sync
async def test_the_app_releases_them_on_a_timer(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    calls: list[int] = []
    monkeypatch.setattr(valterm.ui.app, "RELEASE_EVERY", 0.05)
    monkeypatch.setattr(valterm.ui.app, "release_styles_caches", lambda: calls.append(1))
    app = make_app(tmp_path)
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause(0.5)
        assert calls
