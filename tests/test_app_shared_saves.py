"""Two sessions on one workspace, on screen (issue 24): the editor's and MANIPULATION's saves
ask (overwrite / reload / save as) when the other session saved the file meanwhile."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from app_helpers import make_app, screen_text, sync

from valterm.core.editor import ProgramEditor
from valterm.core.files.programs import read_program
from valterm.core.files.setup import read_setup
from valterm.core.session import Session
from valterm.core.workspace import Workspace
from valterm.ui.screens.changed import FileChangedScreen
from valterm.ui.app import ValtermApp
from valterm.ui.screens.editor import EditorScreen
from valterm.ui.screens.main_menu import MainMenuScreen


class Host(ValtermApp):
    """The app on a session, with no screen of its own: the test pushes the editor."""

    def __init__(self, root: Path) -> None:
        super().__init__(session=Session(root))

    def on_mount(self) -> None:
        pass


def texts(path: Path) -> list[str]:
    return [s.text for s in read_program(path).steps]


@sync
async def test_editor_save_asks_and_each_answer_keeps_the_other_sessions_step(tmp_path: Path) -> None:
    root = tmp_path / "ws"
    app = Host(root)
    async with app.run_test(size=(120, 40)) as pilot:
        screen = EditorScreen()
        await app.push_screen(screen)
        await pilot.pause()
        await pilot.press(*"CONV2", "enter")
        original = [s.text for s in screen.editor.steps]
        other = ProgramEditor(Workspace(root), "CONV2")  # both open CONV2, each inserts a step
        await pilot.press("i", "1", "enter", *" TYPE MINE", "enter", "escape")
        other.insert(1, " TYPE THEIRS")
        other.save()
        # S: the question, not a lost step
        await pilot.press("s")
        await pilot.pause()
        assert isinstance(app.screen, FileChangedScreen)
        assert "CONV2.DAT CHANGED ON DISK" in screen_text(app)
        assert "O OVERWRITE" in app.screen.question and "SAVE AS" in app.screen.question
        assert texts(root / "CONV2.DAT") == ["TYPE THEIRS", *original]
        # A: save as a new name; both programs kept
        await pilot.press("a", *"CONV3", "enter")
        await pilot.pause()
        assert app.screen is screen
        assert "CONV3.DAT SAVED" in screen.message
        assert texts(root / "CONV3.DAT") == ["TYPE MINE", *original]
        assert texts(root / "CONV2.DAT") == ["TYPE THEIRS", *original]
        # the other session saves CONV3 too: R takes theirs
        other = ProgramEditor(Workspace(root), "CONV3")
        await pilot.press("i", "1", "enter", *" TYPE MINE2", "enter", "escape")
        other.append(" TYPE END")
        other.save()
        await pilot.press("s")
        await pilot.pause()
        await pilot.press("r")
        await pilot.pause()
        assert "RELOADED" in screen.message
        assert [s.text for s in screen.editor.steps] == ["TYPE MINE", *original, "TYPE END"]
        # E_XIT with changes: Y saves, the question comes, O overwrites, the editor closes
        await pilot.press("i", "1", "enter", *" TYPE LAST", "enter", "escape")
        other.append(" TYPE AFTER")
        other.save()
        await pilot.press("e", "y")
        await pilot.pause()
        assert isinstance(app.screen, FileChangedScreen)
        await pilot.press("o")
        await pilot.pause()
        assert app.screen is not screen
    assert texts(root / "CONV3.DAT") == ["TYPE LAST", "TYPE MINE", *original, "TYPE END"]


@sync
async def test_manipulation_save_asks_and_overwrite_or_escape(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(80, 24)) as pilot:
        other = Session(tmp_path, setup="PROCESS")
        other.simulator.cell.objects[2] = other.simulator.cell.objects[2].translated(np.array([0, 0, 40.0]))
        other.save_setup()
        theirs = (tmp_path / "PROCESS.SET").read_bytes()
        await pilot.press("M", "1", "enter", "K", "U", "S", "N", "Y")
        assert "ENTER SET-UP FILE NAME" in screen_text(app)
        await pilot.press("enter")  # the same name
        await pilot.pause()
        assert isinstance(app.screen, FileChangedScreen)
        assert "PROCESS.SET CHANGED ON DISK" in screen_text(app)
        assert (tmp_path / "PROCESS.SET").read_bytes() == theirs
        await pilot.press("escape")  # not now: nothing written, the moved part stays unsaved
        await pilot.pause()
        assert isinstance(app.screen, MainMenuScreen)
        assert (tmp_path / "PROCESS.SET").read_bytes() == theirs
        assert app.setup_modified
        await pilot.press("M", "1", "enter", "K", "U", "S", "N", "Y", "enter")
        await pilot.pause()
        assert isinstance(app.screen, FileChangedScreen)
        await pilot.press("o")
        await pilot.pause()
        assert isinstance(app.screen, MainMenuScreen) and not app.setup_modified
        mine = app.session.simulator.cell.objects[0].vertices
    saved = read_setup(tmp_path / "PROCESS.SET")
    assert np.allclose(saved.objects[0].vertices, mine, atol=0.01)
