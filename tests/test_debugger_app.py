"""The debugger in the app's VAL-II mode (Pilot): the paused step highlighted beside the
transcript, the watched variables, CTRL-O XSTEP and CTRL-P PROCEED from the legend."""

from __future__ import annotations

import asyncio
import math
from pathlib import Path

from rich.text import Text

from app_helpers import screen_text, until
from valterm.core.session import Session
from valterm.ui.app import ValtermApp
from valterm.ui.screens.valmode import ValModeScreen
from valterm.ui.widgets.debugpanel import DebugPanel


class Host(ValtermApp):
    """The app on a session with PROCESS.SET and PROCESS.LOC; the test pushes VAL-II mode."""

    def __init__(self, root: Path) -> None:
        session = Session(root)
        session.load_locations("PROCESS")
        super().__init__(session=session, motion_rate=math.inf)

    def on_mount(self) -> None:
        pass


async def typed(pilot, text: str) -> None:  # type: ignore[no-untyped-def]
    await pilot.press(*text, "enter")


def highlighted(panel: DebugPanel) -> list[str]:
    """The panel's lines drawn highlighted."""
    content = panel.content
    assert isinstance(content, Text)
    return [content.plain[span.start:span.end].strip() for span in content.spans if "reverse" in str(span.style)]


def test_a_breakpoint_shows_the_listing_xstep_and_proceed_keys_and_the_watched_values(tmp_path: Path) -> None:
    async def body() -> None:
        app = Host(tmp_path / "ws")
        async with app.run_test(size=(150, 45)) as pilot:
            screen = ValModeScreen(show_menu=False)
            await app.push_screen(screen)
            await pilot.pause()
            panel = screen.query_one(DebugPanel)
            await typed(pilot, "BPT PROCESS,8")
            await typed(pilot, "EXEC PROCESS")
            assert screen.mode == "paused"
            assert screen.transcript[-1] == "BREAKPOINT BEFORE PROCESS STEP 8: MOVE A"
            assert "PROCESS     7  TYPE PICK UP THE FIRST PART" in screen.transcript
            assert "PROCESS     8  MOVE A" not in screen.transcript
            assert panel.display and panel.border_title == "PROCESS STEP 8"
            assert highlighted(panel) == [">   8      MOVE A"]
            assert "^P PROCEED" in screen.keys_text and "^O XSTEP" in screen.keys_text
            assert "MOVE A" in screen_text(app) and "CLOSEI 50" in screen_text(app)  # beside the log

            await pilot.press("ctrl+o")  # XSTEP: exactly step 8
            assert screen.mode == "paused"
            assert list(screen.transcript)[-2:] == ["PROCESS     8  MOVE A",
                                                    "XSTEP: PAUSED BEFORE PROCESS STEP 9: CLOSEI 50"]
            assert highlighted(panel) == [">   9      CLOSEI 50"]

            await typed(pilot, "WATCH N")
            assert "N = UNDEFINED" in panel.text
            await typed(pilot, "N=7")
            assert "N = 7" in panel.text

            await pilot.press("ctrl+p")  # PROCEED
            await until(pilot, lambda: not app.moving, "the end of PROCESS")
            assert screen.mode == "command"  # the command line stays open (issue 17)
            assert "WATCH N: UNDEFINED -> 7 (TYPED)" in screen.transcript
            assert screen.transcript[-1] == "PROGRAM PROCESS COMPLETED: 1 LOOP"
            assert not panel.display or panel.has_class("hidden")
            await typed(pilot, "LISTP PROCESS")  # the steps numbered as BPT takes them
            assert "   8.     MOVE A" in screen.transcript

    asyncio.run(body())
