"""EDIT mode on screen (Pilot): the menu of Fig. C-8, EDIT NAME, C/I/D/S/E, wrong keys."""

from __future__ import annotations

import asyncio
from pathlib import Path


from valterm.core.files.programs import read_program
from valterm.core.session import Session
from valterm.ui.app import ValtermApp
from valterm.ui.screens.editor import EditorScreen


class Host(ValtermApp):
    """The app on a session, with no screen of its own: the test pushes the editor."""

    def __init__(self, root: Path) -> None:
        super().__init__(session=Session(root))

    def on_mount(self) -> None:
        pass


async def type_text(pilot, text: str) -> None:  # type: ignore[no-untyped-def]
    await pilot.press(*text)


def run(coro) -> None:  # type: ignore[no-untyped-def]
    asyncio.run(coro)


def test_type_a_program_delete_insert_save_exit(tmp_path: Path) -> None:
    async def body() -> None:
        app = Host(tmp_path / "ws")
        async with app.run_test(size=(120, 40)) as pilot:
            screen = EditorScreen()
            await app.push_screen(screen)
            await pilot.pause()
            assert "LEGAL EDITING COMMANDS" in str(screen.query_one("#editor-menu").content)
            assert screen.prompt == "EDIT"
            await type_text(pilot, "EDIT TEST.DAT")
            await pilot.press("enter")
            assert "INPUT FILE TEST.DAT DOES NOT EXIST" in screen.message
            await pilot.press("c")
            assert screen.prompt == "S. 1>"
            for line in (" MOVE A", " MOVE B", " CLOSEI 50", " STOP"):
                await type_text(pilot, line)
                await pilot.press("enter")
            assert [s.text for s in screen.editor.steps] == ["MOVE A", "MOVE B", "CLOSEI 50", "STOP"]
            assert "   3.     CLOSEI 50" in screen.listing
            # the line stays open after each accepted step (issue 17 item 3)
            assert screen.prompt == "S. 5>"
            # a bad line is rejected and stays to be corrected
            await type_text(pilot, " FLY")
            await pilot.press("enter")
            assert "REJECTED" in screen.message
            assert screen.query_one("#editor-line").value == " FLY"
            await pilot.press("escape")
            await pilot.press("d", "3", "enter")
            assert "CLOSEI" not in screen.listing
            await pilot.press("i", "3", "enter")
            assert screen.prompt == "S. 3>"
            await type_text(pilot, " MOVE E")
            await pilot.press("enter")
            assert screen.prompt == "S. 4>"  # the next inserted line goes after it
            await pilot.press("escape")
            assert [s.text for s in screen.editor.steps] == ["MOVE A", "MOVE B", "MOVE E", "STOP"]
            # a label, TAB to column 5
            await pilot.press("c", "2", "0", "tab")
            await type_text(pilot, "TYPE DONE")
            await pilot.press("enter", "escape")
            assert screen.editor.steps[-1].label == 20
            await pilot.press("s")
            assert "TEST.DAT SAVED" in screen.message
            await pilot.press("e")
            await pilot.pause()
            assert app.screen is not screen
        saved = read_program(tmp_path / "ws" / "TEST.DAT")
        assert [s.text for s in saved.steps] == ["MOVE A", "MOVE B", "MOVE E", "STOP", "TYPE DONE"]
        assert "TEST" in app.session.workspace.programs_directory()

    run(body())


def test_wrong_key_saves_and_exit_asks(tmp_path: Path) -> None:
    async def body() -> None:
        app = Host(tmp_path / "ws")
        async with app.run_test(size=(120, 40)) as pilot:
            screen = EditorScreen(name="NEW1")
            await app.push_screen(screen)
            await pilot.pause()
            await pilot.press("c")
            await type_text(pilot, " READY")
            await pilot.press("enter", "escape")
            await pilot.press("q")
            assert "'Q' IS NOT AN EDITOR COMMAND" in screen.message
            assert (tmp_path / "ws" / "NEW1.DAT").exists()
            await pilot.press("space")  # a space starts the next step in the label columns
            await type_text(pilot, "STOP")
            await pilot.press("enter", "escape")
            await pilot.press("e")
            assert "(Y/N)" in screen.message
            await pilot.press("n")
            await pilot.pause()
            assert app.screen is not screen
        assert [s.text for s in read_program(tmp_path / "ws" / "NEW1.DAT").steps] == ["READY"]

    run(body())


def test_closing_mid_edit_loses_nothing(tmp_path: Path) -> None:
    async def body() -> None:
        app = Host(tmp_path / "ws")
        async with app.run_test(size=(120, 40)) as pilot:
            await app.push_screen(EditorScreen(name="KEEP"))
            await pilot.pause()
            await pilot.press("c")
            await type_text(pilot, " MOVE A")
            await pilot.press("enter")
        app2 = Host(tmp_path / "ws")
        async with app2.run_test(size=(120, 40)) as pilot:
            screen = EditorScreen(name="KEEP")
            await app2.push_screen(screen)
            await pilot.pause()
            assert "RECOVERED" in screen.message
            assert "MOVE A" in screen.listing

    run(body())
