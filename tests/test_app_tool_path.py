"""The tool path (F5) is the clamp's path through every pose of a motion, as ``valterm render
--trace`` draws it: never chords between the poses a frame happened to show."""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from app_helpers import make_app, sync

from valterm.core.events import Event, PoseEvent
from valterm.core.render.overlays import Trace, clamp_point
from valterm.core.session import Session


def headless_path(tmp_path: Path, command: str) -> np.ndarray:
    """The tool path as the headless renderer builds it: the start, then each pose's clamp."""
    session = Session(workspace_root=tmp_path / "headless")
    session.load_locations("PROCESS")
    sim = session.simulator
    trace = Trace([clamp_point(sim)])
    for event in session.command(command):
        if isinstance(event, PoseEvent):
            trace.add(clamp_point(sim))
    return trace.points()


def late_first(events: Iterator[Event], seconds: float) -> Iterator[Event]:
    """The stream with its first event late (a busy machine), as the player pulls it."""
    for i, event in enumerate(events):
        if i == 0:
            time.sleep(seconds)
        yield event


@pytest.mark.parametrize("late", [0.0, 0.05])
@sync
async def test_the_tool_path_goes_through_every_pose_of_the_motion(tmp_path: Path, late: float) -> None:
    expected = headless_path(tmp_path, "MOVE B")
    assert len(expected) > 10  # a joint motion of many poses: a chord would be two points
    app = make_app(tmp_path / "app")
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.pause()
        app.session.load_locations("PROCESS")
        app.run_events(late_first(app.session.command("MOVE B"), late))
        app.skip_motion()
        await pilot.pause()
        drawn = app.trace.points()
    assert drawn.shape == expected.shape
    assert np.allclose(drawn, expected)
