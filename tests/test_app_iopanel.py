"""V+ programs of workspace .V2 files in VAL-II mode, and the I/O panel (F10) on screen (Pilot)."""

from __future__ import annotations

import asyncio
import math
from pathlib import Path

from app_helpers import until

from valterm.core.session import Session
from valterm.ui.app import ValtermApp
from valterm.ui.screens.signals import SignalsScreen, parse_input_command
from valterm.ui.screens.valmode import ValModeScreen
from valterm.core.signals import SignalPanel

CELL = """\
; two programs of one V+ file in the workspace
.PROGRAM pick.place()
    TYPE "START"
    n = 3
    CALL two.step(n)
    TYPE "BACK, N=", n
.END
.PROGRAM two.step(k)
    k = k*2
    TYPE "IN TWO.STEP ", k
.END
"""

WAITER = """\
.PROGRAM waiter()
    SIGNAL 1, 3
    WAIT SIG(1001)
    SIGNAL -1, 2
    TYPE "INPUT 1001 SEEN"
.END
"""


class Host(ValtermApp):
    """The app on a session, with no screen of its own: the test pushes VAL-II mode."""

    def __init__(self, root: Path, rate: float = math.inf, clock=None) -> None:  # type: ignore[no-untyped-def]
        extra = {"clock": clock} if clock is not None else {}
        super().__init__(session=Session(root), motion_rate=rate, **extra)

    def on_mount(self) -> None:
        pass


class Clock:
    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


async def typed(pilot, text: str) -> None:  # type: ignore[no-untyped-def]
    await pilot.press(*text, "enter")


def lamps(screen: SignalsScreen, row: int) -> dict[int, bool]:
    """Lamp row ``row`` (0, 1: outputs 1-24; 2, 3: inputs 1001-1024) read back from the screen."""
    lines = screen.lamps_text.splitlines()
    numbers = [int(word) for word in lines[2 * row].split() if word.isdigit()]
    states = lines[2 * row + 1].split()
    assert len(numbers) == len(states) == 12
    return {n: s == "*" for n, s in zip(numbers, states)}


def test_a_vplus_program_of_a_workspace_file_runs_with_its_call(tmp_path: Path) -> None:
    async def body() -> None:
        app = Host(tmp_path / "ws")
        async with app.run_test(size=(140, 45)) as pilot:
            (app.session.workspace.root / "CELL1.V2").write_text(CELL)
            screen = ValModeScreen(show_menu=False)
            await app.push_screen(screen)
            await pilot.pause()
            await typed(pilot, "LISTF")
            listing = next(line for line in screen.transcript if line.startswith("PROGRAMS:"))
            assert listing.split()[-2:] == ["PICK.PLACE", "TWO.STEP"]
            await typed(pilot, "EXECUTE pick.place")
            text = list(screen.transcript)
            assert "START" in text and "IN TWO.STEP 6" in text and "BACK, N=6" in text, "\n".join(text)
            assert "PROGRAM PICK.PLACE COMPLETED: 1 LOOP" in text, "\n".join(text)
            assert not any(line.startswith("***") for line in text), text
            await typed(pilot, "LISTP two.step")
            assert "PROGRAM TWO.STEP" in screen.transcript
            assert any(line.endswith("k = k*2") for line in screen.transcript)

    asyncio.run(body())


def test_wait_sig_waits_for_the_keyboard_and_the_panel_shows_outputs_live(tmp_path: Path) -> None:
    async def body() -> None:
        clock = Clock()

        def tick() -> None:  # a second on the program's clock
            clock.now += 1.0

        app = Host(tmp_path / "ws", rate=20.0, clock=clock)  # paced: WAIT's polls wait on the clock
        async with app.run_test(size=(140, 45)) as pilot:
            (app.session.workspace.root / "IO.V2").write_text(WAITER)
            screen = ValModeScreen(show_menu=False)
            await app.push_screen(screen)
            await pilot.pause()
            await typed(pilot, "EXECUTE waiter")
            await until(pilot, lambda: "SIGNAL 1 ON" in screen.transcript, "SIGNAL 1 ON", between=tick)
            for _ in range(5):  # five more seconds: still waiting
                tick()
                await pilot.pause(0.05)
            assert screen.mode == "running"  # waiting for input 1001
            assert "F10: I/O PANEL" in screen.keys_text
            assert "SIGNAL 1 ON" in screen.transcript and "INPUT 1001 SEEN" not in screen.transcript

            await pilot.press("f10")
            panel = app.screen
            assert isinstance(panel, SignalsScreen)
            outputs = lamps(panel, 0)
            assert outputs[1] and outputs[3] and not outputs[2]
            assert not lamps(panel, 2)[1001]
            assert "PROGRAM WAITER RUNNING" in str(panel.query_one("#io-state").content)

            await typed(pilot, "1001")  # toggles input 1001 on
            assert panel.message == "INPUT 1001 ON"
            assert lamps(panel, 2)[1001]
            # the screen's last line, not the session's state: the lines reach the screen after it
            await until(pilot, lambda: "PROGRAM WAITER COMPLETED: 1 LOOP" in screen.transcript, "the program's end",
                        between=tick)
            assert "INPUT 1001 SEEN" in screen.transcript
            assert "PROGRAM WAITER COMPLETED: 1 LOOP" in screen.transcript
            await pilot.pause(0.2)  # the panel's next look: SIGNAL -1, 2 changed the lamps
            outputs = lamps(panel, 0)
            assert not outputs[1] and outputs[2] and outputs[3]
            assert "NO PROGRAM RUNNING" in str(panel.query_one("#io-state").content)

            await typed(pilot, "1001 OFF")
            assert panel.message == "INPUT 1001 OFF" and not lamps(panel, 2)[1001]
            await typed(pilot, "7")
            assert panel.message.startswith("*** 7 IS NOT AN INPUT")

            await pilot.press("escape")
            assert app.screen is screen
            assert screen.mode == "command"
            await typed(pilot, "STATUS")
            assert "SIGNALS ON: OUTPUTS 2 3  INPUTS NONE" in screen.transcript
            assert screen.mode == "command"  # F10 opens the panel from the open line too
            await pilot.press("f10")
            assert isinstance(app.screen, SignalsScreen)
            await pilot.press("escape")
            assert app.screen is screen and screen.mode == "command"

    asyncio.run(body())


def test_ctrl_c_ends_a_wait_for_the_keyboard(tmp_path: Path) -> None:
    async def body() -> None:
        clock = Clock()

        def tick() -> None:  # a second on the program's clock
            clock.now += 1.0

        app = Host(tmp_path / "ws", rate=20.0, clock=clock)
        async with app.run_test(size=(140, 45)) as pilot:
            (app.session.workspace.root / "IO.V2").write_text(WAITER)
            screen = ValModeScreen(show_menu=False)
            await app.push_screen(screen)
            await pilot.pause()
            await typed(pilot, "EXECUTE waiter")
            clock.now += 1.0
            await pilot.pause(0.05)
            assert screen.mode == "running"
            await pilot.press("ctrl+c")
            await until(pilot, lambda: screen.mode != "running", "the abort", between=tick)
            assert screen.mode == "command"
            assert any("ABORTED" in line for line in screen.transcript), list(screen.transcript)
            assert "INPUT 1001 SEEN" not in screen.transcript

    asyncio.run(body())


def test_typed_input_commands() -> None:
    panel = SignalPanel()
    assert parse_input_command("1001", panel) == (1001, True)
    panel.set_input(1001, True)
    assert parse_input_command("1001", panel) == (1001, False)
    assert parse_input_command("input 1002 on", panel) == (1002, True)
    assert parse_input_command("1512, 0", panel) == (1512, False)
    for bad, said in (("", "TYPE AN INPUT"), ("1513", "NOT AN INPUT"), ("1001 MAYBE", "TYPE ON OR OFF"),
                      ("ONE", "TYPE AN INPUT")):
        try:
            parse_input_command(bad, panel)
        except ValueError as error:
            assert said in str(error)
        else:
            raise AssertionError(bad)


def test_the_editor_shows_a_vplus_program_and_will_not_save_it(tmp_path: Path) -> None:
    from valterm.ui.screens.editor import EditorScreen

    async def body() -> None:
        app = Host(tmp_path / "ws")
        async with app.run_test(size=(140, 45)) as pilot:
            source = app.session.workspace.root / "CELL1.V2"
            source.write_text(CELL)
            screen = ValModeScreen(show_menu=False)
            await app.push_screen(screen)
            await pilot.pause()
            await typed(pilot, "EDIT two.step")
            editor = app.screen
            assert isinstance(editor, EditorScreen)
            await pilot.pause()
            assert "EDIT TWO.STEP (CELL1.V2, READ ONLY)" in str(editor.query_one("#editor-title").content)
            assert "k = k*2" in editor.listing and "V+ PROGRAM OF CELL1.V2" in editor.message
            await pilot.press("s")
            assert "REJECTED: TWO.STEP IS A V+ PROGRAM OF CELL1.V2" in editor.message
            await typed(pilot, "    TYPE 1")
            assert "REJECTED" in editor.message
            assert source.read_text() == CELL and not (source.parent / "TWO.DAT").exists()

    asyncio.run(body())
