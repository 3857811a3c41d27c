"""Helpers of the app tests: an app on a temporary workspace, the screen as text."""

from __future__ import annotations

import asyncio
import math
from pathlib import Path

from valterm.core.session import Session
from valterm.testing import ScriptClock, screen_rows
from valterm.ui.app import ValtermApp


class FakeClock(ScriptClock):
    """The pacing clock, stepped by hand (``valterm.testing.ScriptClock``)."""


def make_app(tmp_path: Path, *, rate: float = math.inf, clock=None, start: bool = False) -> ValtermApp:  # type: ignore[no-untyped-def]
    """The app on a fresh workspace: PROCESS.SET read (MAIN MENU first) unless ``start``.

    ``rate`` inf: every motion shows its last pose at once (no timer runs)."""
    extra = {"clock": clock} if clock is not None else {}
    if start:
        return ValtermApp(tmp_path, None, motion_rate=rate, **extra)
    return ValtermApp(session=Session(workspace_root=tmp_path), motion_rate=rate, **extra)


def screen_text(app: ValtermApp) -> str:
    """What the terminal shows, as plain text (one line per row; public API only)."""
    return "\n".join(screen_rows(app))


WAIT_LIMIT = 240.0  # seconds a test waits for the app before it fails (a guard, not a timing)


async def until(pilot, condition, what: str, limit: float = WAIT_LIMIT, between=None) -> None:  # type: ignore[no-untyped-def]
    """Let the app run until ``condition()``; fail (never hang) after ``limit`` seconds. A
    program played at motion_rate inf still runs a few milliseconds a tick: on a loaded
    machine it can outlast one Pilot key press. ``between()`` runs before each wait (a
    stepped clock moved on): bounded in real time, not by a count of looks, which a loaded
    machine spends before the app has done its work."""
    import pytest

    loop = asyncio.get_running_loop()
    end = loop.time() + limit
    while not condition():
        if loop.time() > end:
            pytest.fail(f"the app never reached: {what}")
        if between is not None:
            between()
        await pilot.pause(0.02 if between is None else 0.01)


def sync(test):  # type: ignore[no-untyped-def]
    """Run an async Pilot test without an async pytest plugin (fixtures pass through)."""
    import asyncio
    import functools

    @functools.wraps(test)
    def run(*args, **kwargs) -> None:  # type: ignore[no-untyped-def]
        asyncio.run(test(*args, **kwargs))

    return run
