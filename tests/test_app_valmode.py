"""VAL-II mode on screen (Pilot): the menu, define locations A/R/E, EXECUTE, CTRL-C, PAUSE."""

from __future__ import annotations

import asyncio
import math
from pathlib import Path

from app_helpers import until

from valterm.core.session import Session
from valterm.ui.app import ValtermApp
from valterm.ui.screens.editor import EditorScreen
from valterm.ui.screens.valmode import ValModeScreen


class Host(ValtermApp):
    """The app on a session, with no screen of its own: the test pushes VAL-II mode."""

    def __init__(self, root: Path) -> None:
        super().__init__(session=Session(root), motion_rate=math.inf)

    def on_mount(self) -> None:
        pass


class Clock:
    """A clock the test moves by hand."""

    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


async def typed(pilot, text: str) -> None:  # type: ignore[no-untyped-def]
    await pilot.press(*text, "enter")


def test_editor_then_define_execute_abort_and_rerun(tmp_path: Path) -> None:
    async def body() -> None:
        app = Host(tmp_path / "ws")
        clock = Clock()
        async with app.run_test(size=(140, 45)) as pilot:
            # a program typed in the editor
            editor = EditorScreen()
            await app.push_screen(editor)
            await pilot.pause()
            await typed(pilot, "EDIT PICK")
            await pilot.press("c")
            for line in (" READY", " LEFTY", " TYPE GOING TO A", " MOVE A", " CLOSEI 50", " MOVE B", " STOP"):
                await typed(pilot, line)
            await pilot.press("escape", "s", "e")  # ESC closes the step line (issue 17)
            await pilot.pause()

            screen = ValModeScreen()
            await app.push_screen(screen)
            await pilot.pause()
            assert "VAL-II MENU" in str(screen.query_one("#val-menu").content)
            await pilot.press("n")
            assert "VAL-II MENU CONTINUED" in str(screen.query_one("#val-menu").content)
            await pilot.press("v")
            assert screen.mode == "command"
            await typed(pilot, "LE")
            assert screen.mode == "command" and "^T D_DEFINE" in screen.keys_text  # the line stays open
            await pilot.press("a", "b", "enter")
            assert screen.simulator.config.elbow == 1
            # CTRL-T (D_DEFINE), D: locations from PROCESS.LOC one at a time: A accept, R reject, E accept and end
            await pilot.press("ctrl+t", "d")
            assert screen.mode == "define-file"
            await typed(pilot, "PROCESS.LOC")
            assert screen.mode == "define-each"
            await pilot.press("a")  # A
            await pilot.press("r")  # B rejected
            await pilot.press("a")  # C
            await pilot.press("e")  # D, and the end
            assert screen.mode == "command"
            assert set(screen.simulator.locations) == {"A", "C", "D"}
            assert "B REJECTED" in screen.transcript
            # B by hand
            await pilot.press("ctrl+t", "p")
            await typed(pilot, "B, 465, 120, -245, 90, 90, 0")
            assert "B" in screen.simulator.locations
            await typed(pilot, "EXEC PICK,1")
            text = "\n".join(screen.transcript)
            assert "GOING TO A" in text and "IT IS POSSIBLE TO GRASP THIS PART" in text
            assert "PICK        4  MOVE A" in screen.transcript
            assert screen.simulator.carried is not None

            # now paced by a clock the test holds: CTRL-C stops after the current step
            app.player.rate = 20.0
            app.player.clock = clock
            await pilot.press(*"EXEC PICK,5", "enter")
            assert screen.mode == "running"
            await pilot.press("ctrl+c")
            await until(pilot, lambda: screen.mode != "running", "the abort",
                        between=lambda: setattr(clock, "now", clock.now + 1.0))
            assert screen.mode == "command"
            assert any("ABORTED" in line for line in screen.transcript)
            assert not screen.interpreter.running
            # and it runs again
            app.player.rate = math.inf
            await typed(pilot, "EXEC PICK,1")
            assert "PROGRAM PICK COMPLETED: 1 LOOP" in screen.transcript
            await pilot.press("ctrl+l")
            assert screen.mode == "command"
            await typed(pilot, "WHERE")
            assert any(line.startswith(("OPENED", "CLOSED")) for line in screen.transcript)

    asyncio.run(body())


def test_pause_hands_the_line_to_the_user(tmp_path: Path) -> None:
    async def body() -> None:
        app = Host(tmp_path / "ws")
        (tmp_path / "ws").mkdir(parents=True, exist_ok=True)
        async with app.run_test(size=(140, 45)) as pilot:
            (app.session.workspace.root / "WAIT.DAT").write_text("    X=1\n    PAUSE\n    TYPE X=\n    STOP\n")
            screen = ValModeScreen(show_menu=False)
            await app.push_screen(screen)
            await pilot.pause()
            await typed(pilot, "EXEC WAIT")
            assert screen.mode == "paused"
            await typed(pilot, "X=5")
            await typed(pilot, "PROCEED")
            assert screen.mode == "command"
            assert any("5" in line and "X" in line for line in screen.transcript), screen.transcript

    asyncio.run(body())
