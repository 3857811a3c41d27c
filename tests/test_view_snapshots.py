"""Snapshots of MAIN in the oblique view after a MOVE: the clamp's path (trace) and the
target frame (ghost) visible, at 80x24 (the model shown with R) and 160x50.

Regenerate with ``pytest tests/test_view_snapshots.py --snapshot-update`` after a
deliberate change of the picture or the screen.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from app_helpers import make_app

SIZES = {(80, 24): ["r"], (160, 50): []}


@pytest.mark.parametrize("size", list(SIZES), ids=lambda s: f"{s[0]}x{s[1]}")
def test_main_after_a_move_shows_trace_and_ghost(snap_compare, tmp_path: Path, size: tuple[int, int]) -> None:  # type: ignore[no-untyped-def]
    app = make_app(tmp_path)

    async def move(pilot) -> None:  # type: ignore[no-untyped-def]
        app.session.load_locations("PROCESS")
        app.run_events(app.session.command("MOVE B"))
        app.skip_motion()
        await pilot.pause()

    assert snap_compare(app, press=SIZES[size], terminal_size=size, run_before=move)
