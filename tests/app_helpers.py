"""Helpers of the app tests: an app on a temporary workspace, the screen as text."""

from __future__ import annotations

import math
from pathlib import Path

from valterm.core.session import Session
from valterm.ui.app import ValtermApp


class FakeClock:
    """The pacing clock, stepped by hand."""

    def __init__(self) -> None:
        self.t = 1000.0

    def __call__(self) -> float:
        return self.t


def make_app(tmp_path: Path, *, rate: float = math.inf, clock=None, start: bool = False) -> ValtermApp:  # type: ignore[no-untyped-def]
    """The app on a fresh workspace: PROCESS.SET read (MAIN MENU first) unless ``start``.

    ``rate`` inf: every motion shows its last pose at once (no timer runs)."""
    extra = {"clock": clock} if clock is not None else {}
    if start:
        return ValtermApp(tmp_path, None, motion_rate=rate, **extra)
    return ValtermApp(session=Session(workspace_root=tmp_path), motion_rate=rate, **extra)


def screen_text(app: ValtermApp) -> str:
    """What the terminal shows, as plain text (one line per row)."""
    strips = app.screen._compositor.render_strips()
    return "\n".join("".join(segment.text for segment in strip).rstrip() for strip in strips)


def sync(test):  # type: ignore[no-untyped-def]
    """Run an async Pilot test without an async pytest plugin (fixtures pass through)."""
    import asyncio
    import functools

    @functools.wraps(test)
    def run(*args, **kwargs) -> None:  # type: ignore[no-untyped-def]
        asyncio.run(test(*args, **kwargs))

    return run
