"""Every screen on one base (issue 27 Build 1): VAL-II mode's menu and the editor's keys are
bindings with ids, switched on per state in one place, rebindable by the keymap file; keys
typed between RETURN and the screen taking the line are kept."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from app_helpers import screen_text, sync
from textual.binding import Binding
from textual.widgets import Input

from valterm.ui.app import ValtermApp
from valterm.ui.bindings import all_bindings
from valterm.ui.screens.changed import FileChangedScreen
from valterm.ui.screens.editor import EditorScreen
from valterm.ui.screens.help import HelpScreen
from valterm.ui.screens.keyed import KeyedScreen, action_name
from valterm.ui.screens.main_menu import MainMenuScreen
from valterm.ui.screens.quit import QuitScreen
from valterm.ui.screens.signals import SignalsScreen
from valterm.ui.screens.start import StartScreen
from valterm.ui.screens.valmode import Mode, ValModeScreen


def test_every_screen_is_a_keyed_screen() -> None:
    for screen in (MainMenuScreen, StartScreen, ValModeScreen, EditorScreen, HelpScreen, QuitScreen,
                   SignalsScreen, FileChangedScreen):
        assert issubclass(screen, KeyedScreen), screen


def test_the_states_name_only_actions_the_screen_binds() -> None:
    """STATES is the one place: each action it names is bound on that screen (no dead rows)."""
    for screen in (ValModeScreen, EditorScreen, HelpScreen, FileChangedScreen):
        bound = {action_name(b) for b in screen.BINDINGS if isinstance(b, Binding)}
        assert set(screen.STATES) <= bound, (screen, set(screen.STATES) - bound)


def test_the_val_ii_menu_and_editor_keys_have_ids() -> None:
    ids = {str(binding.id) for _, binding in all_bindings()}
    assert {"valmode.menu.page", "valmode.menu.line", "valmode.menu.return", "valmode.define.file",
            "valmode.each.accept", "editor.create", "editor.save_yes", "quit.yes", "help.yes",
            "changed.overwrite"} <= ids


@sync
async def test_a_rebound_val_ii_menu_key_and_editor_key_are_honoured(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """valmode.menu.wipe on X instead of W; editor.create on K instead of C: the new keys work,
    the old ones are wrong keys (the editor saves and says so, §5.2)."""
    keymap = tmp_path / "keymap.toml"
    keymap.write_text('"valmode.menu.wipe" = "x,X"\n"editor.create" = "k,K"\n')
    monkeypatch.setenv("VALTERM_KEYMAP", str(keymap))
    app = ValtermApp(tmp_path / "ws", "PROCESS", motion_rate=math.inf)
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.pause()
        await pilot.press("v")  # VAL-II mode, its menu
        await pilot.pause()
        screen = app.screen
        assert isinstance(screen, ValModeScreen) and screen.mode == Mode.MENU
        await pilot.press("x")  # the rebound wipe: the log cleared, the line open
        await pilot.pause()
        assert screen.mode == Mode.COMMAND
        await pilot.press("escape", "w")  # W is no menu key now: it opens the line with W typed
        await pilot.pause()
        assert screen.mode == Mode.COMMAND and screen.query_one("#val-line", Input).value == "W"
        await pilot.press("ctrl+a", "ctrl+k", *"EDIT T1", "enter")
        await pilot.pause()
        editor = app.screen
        assert isinstance(editor, EditorScreen) and editor.mode == "menu"
        await pilot.press("c")
        await pilot.pause()
        assert editor.mode == "menu" and "'C' IS NOT AN EDITOR COMMAND" in editor.message
        await pilot.press("k", *"MOVE A", "enter")
        await pilot.pause()
        assert editor.editor is not None and [s.text for s in editor.editor.steps] == ["MOVE A"]


@sync
async def test_define_keys_work_only_in_their_state(tmp_path: Path) -> None:
    """A (accept) is no key at the D_DEFINE question: the one wrong-key message; P is."""
    app = ValtermApp(tmp_path / "ws", "PROCESS", motion_rate=math.inf)
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.pause()
        await pilot.press("v", "v", "ctrl+t")
        await pilot.pause()
        screen = app.screen
        assert isinstance(screen, ValModeScreen) and screen.mode == Mode.DEFINE
        await pilot.press("a")
        await pilot.pause()
        assert screen.mode == Mode.DEFINE
        assert "'A' IS NOT A KEY OF THIS MENU; ? OR F1: HELP" in screen.keys_text
        await pilot.press("p")
        await pilot.pause()
        assert screen.mode == Mode.POINT


@sync
async def test_keys_typed_between_return_and_the_screen_taking_the_line_are_kept(tmp_path: Path) -> None:
    """RETURN posts the line; a key typed before the screen takes it starts the next line."""
    app = ValtermApp(tmp_path / "ws", "PROCESS", motion_rate=math.inf)
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.pause()
        await pilot.press("v", "v")  # VAL-II mode's menu, then its line
        await pilot.pause()
        screen = app.screen
        assert isinstance(screen, ValModeScreen) and screen.mode == Mode.COMMAND
        field = screen.query_one("#val-line", Input)
        field.value = "WHERET"  # RETURN after WHERE, then T typed before the screen took WHERE
        field.post_message(Input.Submitted(field, "WHERE"))
        await pilot.pause()
        assert field.value == "T"
        assert ". WHERE" in screen.transcript


@sync
async def test_here_typed_at_the_pendant_without_v_is_one_command(tmp_path: Path) -> None:
    """HERE P2 at the PENDANT: H is no pendant key, so the command line opens with it typed and
    takes the rest (R and E did return to MAIN and open the editor)."""
    app = ValtermApp(tmp_path / "ws", "PROCESS", motion_rate=math.inf)
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.pause()
        await pilot.press("p", *"HERE P2", "enter")
        await pilot.pause()
        assert type(app.screen).__name__ == "PendantScreen"
        assert "P2" in app.session.simulator.locations
        assert "LOCATION P2 TAUGHT HERE" in screen_text(app)


@sync
async def test_a_menu_screens_mount_handled_after_its_widgets_went_does_nothing(tmp_path: Path) -> None:
    """A screen never reaches for a widget that may be gone: CI saw KEYBOARD's mount handled
    as the kiosk test's app closed, its widgets already removed (NoMatches '#model')."""
    from valterm.ui.screens.keyboard import KeyboardScreen

    app = ValtermApp(tmp_path / "ws", "PROCESS", motion_rate=math.inf)
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause()
        gone = KeyboardScreen()  # composed never: no model view, as after the removal
        gone.on_mount()
        assert not app.survived and app.crash is None
