"""Issues 35 (build 6) and 37 (build 2): every key legend is built from the live bindings.

A keymap file rebinds a key and every menu, HELP key table, status hint and wrong-key answer
teaches the new key; F1, ? and ESC are bindings with ids like the rest; the status line says
which keyboard (--keys 1985) and which rules are in force; letters typed while a command
plays under --keys 1985 reach the command line."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from app_helpers import FakeClock, screen_text, sync, until
from test_app_one_keyboard import settle

from valterm.ui.app import ValtermApp


def keymap_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, text: str) -> None:
    keymap = tmp_path / "keymap.toml"
    keymap.write_text(text)
    monkeypatch.setenv("VALTERM_KEYMAP", str(keymap))


def status_line(app: ValtermApp) -> str:
    return screen_text(app).splitlines()[-1]


@sync
async def test_a_rebound_main_menu_key_is_taught_everywhere(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """main.pendant = "j": MAIN MENU shows J_PENDANT, J opens PENDANT, P is no key, HELP's
    table says J."""
    keymap_file(tmp_path, monkeypatch, '"main.pendant" = "j"\n')
    app = ValtermApp(tmp_path / "ws", "PROCESS", motion_rate=math.inf)
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.pause()
        text = screen_text(app)
        assert "J_PENDANT : TO PENDANT MODE" in text and "P_PENDANT" not in text
        await pilot.press("p")
        await pilot.pause()
        assert "'P' IS NOT A KEY OF THIS MENU" in screen_text(app)
        assert type(app.screen).__name__ == "MainMenuScreen"
        await pilot.press("question_mark")
        await pilot.pause()
        assert type(app.screen).__name__ == "HelpScreen"
        rows = [" ".join(line.split()) for line in screen_text(app).splitlines()]
        assert any(row.startswith("J PENDANT") for row in rows), rows[:30]
        assert not any(row.startswith("P PENDANT") or row.startswith("P/") for row in rows)
        await pilot.press("escape")
        await pilot.pause()
        await pilot.press("J")  # the capital works as P did
        await pilot.pause()
        assert type(app.screen).__name__ == "PendantScreen"


@sync
async def test_help_lists_only_the_keys_that_work_now(tmp_path: Path) -> None:
    """KEYBOARD's ORIENT1: HELP lists ORIENT1's keys, not the KEYBOARD MENU's L, P, S ..."""
    app = ValtermApp(tmp_path / "ws", "PROCESS", motion_rate=math.inf)
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.pause()
        await pilot.press("k", "o")
        await pilot.pause()
        await pilot.press("f1")
        await pilot.pause()
        screen = app.screen
        assert type(screen).__name__ == "HelpScreen"
        whats = {what for _, what in screen.keys}
        assert "BACK TO THE KEYBOARD MENU" in whats and "SCALE UP" in whats
        assert "LIST" not in whats and "POSITION" not in whats


@sync
async def test_the_help_key_and_esc_are_rebound_and_shown(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """screen.help on F12, menu.cancel on CTRL-B: F12 helps, ? is no key, CTRL-B goes back, and
    the status line, the wrong-key answer and HELP's table say so."""
    keymap_file(tmp_path, monkeypatch, '"screen.help" = "f12"\n"menu.cancel" = "ctrl+b"\n')
    app = ValtermApp(tmp_path / "ws", "PROCESS", motion_rate=math.inf)
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.pause()
        assert "KEYMAP" not in screen_text(app)  # the ids are known
        assert "F12 HELP" in status_line(app) and "?" not in status_line(app)
        await pilot.press("p")
        await pilot.pause()
        assert type(app.screen).__name__ == "PendantScreen"
        await pilot.press("question_mark")
        await pilot.pause()
        assert "'?' IS NOT A KEY OF THIS MENU" in screen_text(app) and "F12: HELP" in screen_text(app)
        await pilot.press("f12")
        await pilot.pause()
        assert type(app.screen).__name__ == "HelpScreen"
        keys = dict(app.screen.keys)
        assert keys.get("CTRL-B") == "CANCEL THE PROMPT; AT THE MENU: BACK" and "ESC" not in keys and "F12" in keys, keys
        await pilot.press("escape")  # HELP's own return is still ESC
        await pilot.pause()
        await pilot.press("escape")  # PENDANT's back is CTRL-B now
        await pilot.pause()
        assert type(app.screen).__name__ == "PendantScreen"
        await pilot.press("ctrl+b")
        await pilot.pause()
        assert type(app.screen).__name__ == "MainMenuScreen"


@pytest.mark.parametrize("size", [(80, 24), (160, 50)])
@sync
async def test_the_status_line_says_the_keyboard_and_the_rules(tmp_path: Path, size: tuple[int, int]) -> None:
    app = ValtermApp(tmp_path / "ws", "PROCESS", motion_rate=math.inf, keys="1985", rules="controller")
    async with app.run_test(size=size) as pilot:
        await pilot.pause()
        line = status_line(app)
        assert ("KEYS 1985" in line and "RULES CONTROLLER" in line) or ("K 1985" in line and "R CONT" in line), line
        assert line.endswith("HELP"), line
    app = ValtermApp(tmp_path / "ws", "PROCESS", motion_rate=math.inf)
    async with app.run_test(size=size) as pilot:
        await pilot.pause()
        assert "1985" in status_line(app) and "KEYS" not in status_line(app).replace("K 1985", "")


@sync
async def test_keys_1985_ready_typed_during_a_command_reaches_the_line(tmp_path: Path) -> None:
    """--keys 1985: READY typed while DRIVE plays is the next command, not R (MAIN), E (the
    editor) and ADY.DAT."""
    clock = FakeClock()
    app = ValtermApp(tmp_path, "PROCESS", clock=clock, motion_rate=10.0, keys="1985")
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.pause()
        await pilot.press("v", "v", *"DRIVE 1,30,100", "enter")
        await pilot.pause()
        assert app.moving
        await pilot.press(*"READY", "enter")
        await settle(pilot, app, clock)
        screen = app.screen
        assert type(screen).__name__ == "ValModeScreen", type(screen).__name__
        assert ". READY" in screen.transcript, list(screen.transcript)[-5:]
        assert not (tmp_path / "ADY.DAT").exists()
        # READY plays on the stepped clock (settle may look before it starts)
        await until(pilot, lambda: screen.keys_text.startswith("THEN PRESS: C CONTINUE"), "the menu after READY",
                    between=lambda: clock.advance(0.5))
        assert screen.keys_text.startswith("THEN PRESS: C CONTINUE")  # READY ran: the menu again
        await pilot.press("r")  # typed at the menu now: R is RETURN
        await settle(pilot, app, clock)
        assert type(app.screen).__name__ == "MainMenuScreen"


@sync
async def test_a_rebound_esc_stops_a_motion_without_waiting_for_it(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """valmode.escape on CTRL-B: CTRL-B during DRIVE aborts it (it does not wait behind the
    motion, as ESC does not), the key line says CTRL-B, and ESC is no key of VAL-II mode."""
    keymap_file(tmp_path, monkeypatch, '"valmode.escape" = "ctrl+b"\n')
    clock = FakeClock()
    app = ValtermApp(tmp_path / "ws", "PROCESS", clock=clock, motion_rate=10.0)
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.pause()
        await pilot.press("v")
        await pilot.pause()
        screen = app.screen
        assert "R/CTRL-B RETURN" in screen.keys_text, screen.keys_text
        await pilot.press("v", *"DRIVE 1,90,100", "enter")
        await pilot.pause()
        assert app.moving and "CTRL-C OR CTRL-B: ABORT" in screen.keys_text, screen.keys_text
        start = app.session.simulator.joints[0]
        await pilot.press("ctrl+b")
        await settle(pilot, app, clock)
        assert abs(app.session.simulator.joints[0] - start) < 45.0  # stopped short of 90 degrees
        assert screen.mode == "menu" and type(app.screen).__name__ == "ValModeScreen"
        await pilot.press("escape")
        await pilot.pause()
        assert type(app.screen).__name__ == "ValModeScreen"
        assert "'ESCAPE' IS NOT A KEY OF THIS MENU" in screen.keys_text, screen.keys_text


@sync
async def test_questions_and_the_editor_name_their_keys_as_bound(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """menu.cancel on CTRL-B: a wrong answer says CTRL-B CANCELS; editor.create on K: the
    editor's key line says K CONTINUE."""
    keymap_file(tmp_path, monkeypatch, '"menu.cancel" = "ctrl+b"\n"editor.create" = "k"\n')
    app = ValtermApp(tmp_path / "ws", "PROCESS", motion_rate=math.inf)
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.pause()
        await pilot.press("s", "q")
        await pilot.pause()
        assert "'Q' IS NOT AN ANSWER: PRESS Y, N (CTRL-B CANCELS)" in screen_text(app)
        await pilot.press("ctrl+b", "e", *"T1", "enter")
        await pilot.pause()
        assert type(app.screen).__name__ == "EditorScreen"
        assert "K CONTINUE  I INSERT  D DELETE  S SAVE  E EXIT  ? HELP" in screen_text(app)
        assert "PRESS K TO TYPE THE FIRST STEP" in screen_text(app)


@sync
async def test_a_command_typed_at_the_keyboard_menu_names_list_and_val_as_bound(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """keyboard.list on J, keyboard.val on X: a word typed after LIST's key that is no listing
    says J IS LIST HERE and X FIRST for a VAL-II command, not L and V."""
    keymap_file(tmp_path, monkeypatch, '"keyboard.list" = "j"\n"keyboard.val" = "x"\n')
    app = ValtermApp(tmp_path / "ws", "PROCESS", motion_rate=math.inf)
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.pause()
        await pilot.press("K")
        await pilot.pause()
        await pilot.press("j", *"OAD PROCESS", "enter")
        await pilot.pause()
        text = " ".join(screen_text(app).split())
        assert "OAD IS NOT LISTP, LISTF OR LISTL (J IS LIST HERE: X FIRST TO TYPE A VAL-II COMMAND)" in text, text
