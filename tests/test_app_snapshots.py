"""Snapshots of the MAIN, KEYBOARD, PENDANT and MANIPULATION menus at 80x24 and 120x40.

Regenerate with ``pytest tests/test_app_snapshots.py --snapshot-update`` after a deliberate
change of a screen. No motion plays (the pacing clock never runs) and no input is focused
when the picture is taken, so nothing blinks.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from app_helpers import make_app

SIZES = [(80, 24), (120, 40)]
MENUS = {
    "main": [],
    "keyboard": ["K"],
    "pendant": ["P"],
    "manipulation": ["M", "1", "enter", "K"],
}


@pytest.mark.parametrize("size", SIZES, ids=lambda s: f"{s[0]}x{s[1]}")
@pytest.mark.parametrize("menu", list(MENUS))
def test_menu_snapshot(snap_compare, tmp_path: Path, menu: str, size: tuple[int, int]) -> None:  # type: ignore[no-untyped-def]
    app = make_app(tmp_path)
    assert snap_compare(app, press=MENUS[menu], terminal_size=size)
