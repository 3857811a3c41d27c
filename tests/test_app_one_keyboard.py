"""Issue 27: the key sequences that ended the app, and the keys it dropped, as Pilot tests.

Each presses the issue's keys with the motion clock stepped by hand (0.3 s a key, as a
person types) and reads the screen back."""

from __future__ import annotations

import asyncio
import math
from pathlib import Path
from typing import Any

import pytest
from app_helpers import FakeClock, screen_text, sync, until

from valterm.core.events import Message
from valterm.ui.app import ValtermApp

KEY_GAP = 0.3  # seconds between keys, as in the issue


async def press_slowly(pilot, clock: FakeClock, *keys: str) -> None:  # type: ignore[no-untyped-def]
    """Press ``keys`` 0.3 s apart on the motion clock (the app works between them)."""
    for key in keys:
        await pilot.press(key)
        clock.advance(KEY_GAP)
        await pilot.pause(0.01)


async def settle(pilot, app: ValtermApp, clock: FakeClock) -> None:  # type: ignore[no-untyped-def]
    """Let what moves finish on the stepped clock (0.5 s a look; bounded in real time: a
    count of looks ran out on a loaded machine before the app had done its work)."""
    await until(pilot, lambda: not app.moving and not getattr(app, "keys_waiting", 0), "the motion's end",
                between=lambda: clock.advance(0.5))
    await pilot.pause(0.02)


@sync
async def test_pendant_jog_then_return_before_the_drawing_ends(tmp_path: Path) -> None:
    """--setup DEMO3, P I I I 3 R: the move says ARM CONFIGURATION CHANGED after R left."""
    clock = FakeClock()
    app = ValtermApp(tmp_path, "DEMO3", clock=clock, motion_rate=10.0)
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause()
        await press_slowly(pilot, clock, "p", "i", "i", "i", "3", "r")
        await settle(pilot, app, clock)
        assert app.is_running and app.crash is None and not app.survived
        assert type(app.screen).__name__ == "MainMenuScreen"  # R waited for the drawing, then left
        assert "ARM LAN" in screen_text(app)  # joint 3 moved 8 increments: the elbow went below


@sync
async def test_a_screen_gone_mid_motion_hands_its_messages_to_the_screen_on_top(tmp_path: Path) -> None:
    """The pendant closed by other means than a key while its move is drawn: the player's
    lines and the configuration change reach MAIN, nothing asks the closed pendant."""
    clock = FakeClock()
    app = ValtermApp(tmp_path, "DEMO3", clock=clock, motion_rate=10.0)
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause()
        await press_slowly(pilot, clock, "p", "i", "i", "i")
        pendant = app.screen

        def move_then_say():  # type: ignore[no-untyped-def]
            yield from app.simulator.pendant_joint(3)
            yield Message("SAID AFTER THE MOVE")

        app.run_events(move_then_say(), pendant)
        clock.advance(KEY_GAP)
        await pilot.pause(0.01)
        assert app.moving
        await app.pop_screen()
        await settle(pilot, app, clock)
        assert app.is_running and app.crash is None and not app.survived
        assert "SAID AFTER THE MOVE" in screen_text(app) and "MAIN MENU" in screen_text(app)


@sync
async def test_kiosk_idle_reset_over_help_on_the_pendant() -> None:
    """valterm demo --kiosk, at MAIN: x, Esc, Esc, p, ?, then nothing: the idle reset
    closes HELP and the pendant with no session left, and the demo starts again."""
    from test_demo import HELD, until

    from valterm.core.files.demokeys import parse_demo
    from valterm.ui.demo import DemoApp

    app = DemoApp(parse_demo(HELD), speed=10, idle=600, kiosk=True, motion_rate=math.inf)
    async with app.run_test(size=(80, 24)) as pilot:
        await until(pilot, lambda: app.axes and not app.moving
                    and type(app.screen).__name__ == "MainMenuScreen", "the short script played")
        await pilot.press("x", "escape", "escape", "p", "question_mark")
        await until(pilot, lambda: type(app.screen).__name__ == "HelpScreen", "HELP over the pendant")
        app.idle = 0.2
        await until(pilot, lambda: app.rounds == 2, "the idle reset")
        await until(pilot, lambda: app.session is not None, "the second round reads PROCESS")
        await asyncio.sleep(0.2)
        assert app.is_running and app.return_code is None and app.crash is None and not app.survived


async def _define_from_process_loc(pilot: Any, clock: FakeClock) -> None:
    """VAL-II mode's D_DEFINE of PROCESS.LOC started (V, D, D, the file's name): the robot
    moves to A, its first location."""
    await pilot.pause()
    await press_slowly(pilot, clock, "v", "d", "d")
    await pilot.press(*"PROCESS.LOC", "enter")


@sync
async def test_table_c1_define_answers_typed_while_the_robot_moves_all_count(tmp_path: Path) -> None:
    """V, D, D, PROCESS.LOC, then Table C-1's A, A,A,A,A, E at 0.3 s/key while the robot moves
    to each location: all six are defined (three were, when answers overwrote each other)."""
    clock = FakeClock()
    app = ValtermApp(tmp_path, "PROCESS", clock=clock, motion_rate=10.0)
    async with app.run_test(size=(160, 50)) as pilot:
        await _define_from_process_loc(pilot, clock)
        await press_slowly(pilot, clock, "a", "a", "a", "a", "a", "e")
        await settle(pilot, app, clock)
        assert set("ABCDEF") <= set(app.session.simulator.locations)
        assert app.is_running and not app.survived
        assert "LOCATIONS DEFINED: A, B, C, D, E, F" in "\n".join(app.screen.transcript)


@sync
async def test_define_answers_that_reach_the_screen_while_the_robot_moves_are_kept_in_order(
        tmp_path: Path) -> None:
    """Two answers handed to VAL-II mode while the robot still moves to B (a key goes on
    between a motion's end and its stream's when a loaded machine cuts the tick there): B is
    rejected, C accepted, in that order (one slot kept only the last: A's, for B)."""
    from valterm.ui.screens.valmode import Mode

    clock = FakeClock()
    app = ValtermApp(tmp_path, "PROCESS", clock=clock, motion_rate=10.0)
    async with app.run_test(size=(160, 50)) as pilot:
        await _define_from_process_loc(pilot, clock)
        await settle(pilot, app, clock)
        screen = app.screen
        await pilot.press("a")  # A accepted: the robot moves to B
        assert screen.mode == Mode.RUNNING and app.player.drawing
        screen.action_define_each("R")  # as the key binding calls it
        screen.action_define_each("A")
        await settle(pilot, app, clock)
        await press_slowly(pilot, clock, "e")
        await settle(pilot, app, clock)
        shown = "\n".join(screen.transcript)
        assert "A ACCEPTED\n" in shown and "B REJECTED\n" in shown and "C ACCEPTED\n" in shown
        assert "LOCATIONS DEFINED: A, C, D" in shown


@sync
async def test_editor_refuses_a_too_deep_line_and_keeps_the_program(tmp_path: Path) -> None:
    """EDITOR, X = 124 '(' 1 124 ')': refused with the limit named; the app and the edits stay."""
    app = ValtermApp(tmp_path, "PROCESS", motion_rate=math.inf)
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.pause()
        await pilot.press("e", *"DEEP", "enter")
        await pilot.pause()
        await pilot.press("c", *"TYPE 1", "enter")
        deep = "X = " + "(" * 124 + "1" + ")" * 124
        app.screen.query_one("#editor-line").value = deep
        await pilot.press("enter")
        await pilot.pause()
        assert app.is_running and app.crash is None and not app.survived
        assert "NESTED DEEPER THAN 32" in screen_text(app).upper()
        assert "TYPE 1" in app.screen.listing


@sync
async def test_a_bug_in_a_screen_leaves_the_app_running_with_the_log_named(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from valterm.ui.screens.pendant import PendantScreen

    monkeypatch.setenv("XDG_STATE_HOME", str(tmp_path / "state"))

    def broken(self: PendantScreen) -> None:
        raise RuntimeError("a bug in O")

    monkeypatch.setattr(PendantScreen, "action_open", broken)
    app = ValtermApp(tmp_path / "ws", "PROCESS", motion_rate=math.inf)
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.pause()
        await pilot.press("p", "o")
        await pilot.pause()
        assert app.is_running and app.crash is None
        shown = " ".join(screen_text(app).split())
        assert "INTERNAL ERROR (RUNTIMEERROR: A BUG IN O)" in shown
        assert list((tmp_path / "state" / "valterm").glob("crash-*.log"))
        await pilot.press("c", "r")  # the pendant still takes keys
        await pilot.pause()
        assert type(app.screen).__name__ == "MainMenuScreen"


@sync
async def test_one_meaning_per_key_view_keys_help_and_the_wrong_key_answer(tmp_path: Path) -> None:
    """F2-F8 mean the same on MAIN, PENDANT and VAL-II mode's line; ? and F1 open HELP on the
    VAL-II menu and F1 on its line; a wrong key gets the one answer everywhere."""
    from valterm.ui.screens.help import HelpScreen
    from valterm.ui.screens.valmode import Mode

    app = ValtermApp(tmp_path, "PROCESS", motion_rate=math.inf)
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause()
        await pilot.press("7")
        assert "'7' IS NOT A KEY OF THIS MENU; ? OR F1: HELP" in screen_text(app)
        for keys, screen_name in ((("p",), "PendantScreen"), (("r", "v", "v"), "ValModeScreen")):
            await pilot.press(*keys)
            await pilot.pause()
            screen = app.screen
            assert type(screen).__name__ == screen_name
            factor = app.player.factor
            await pilot.press("f7")  # faster, as on MAIN
            assert app.player.factor == factor / 2
            await pilot.press("f6")
            assert app.player.factor == factor
            model = "model-only" if screen_name == "ValModeScreen" else "-model"
            shown = screen.has_class(model)
            await pilot.press("f8")  # the model alone / the text again (80 columns: one or the other)
            assert screen.has_class(model) != shown
            if not shown:
                await pilot.press("f2")  # the next preset view, as on MAIN
                said = screen_text(app) + "\n".join(getattr(screen, "transcript", []))
                assert "VIEW: " in said, said
            await pilot.press("f8")
            assert screen.has_class(model) == shown
        assert screen.mode == Mode.COMMAND
        await pilot.press("question_mark")  # in the line: text
        assert screen.query_one("#val-line").value == "?"
        await pilot.press("f1")  # on the line: HELP
        await pilot.pause()
        assert isinstance(app.screen, HelpScreen)
        while isinstance(app.screen, HelpScreen):
            await pilot.press("escape")
            await pilot.pause()
        assert app.screen is screen
        if screen.mode != Mode.MENU:
            await pilot.press("escape")  # the VAL-II menu
        await pilot.pause()
        assert screen.mode == Mode.MENU
        await pilot.press("7")
        assert screen.keys_text.startswith("'7' IS NOT A KEY OF THIS MENU; ? OR F1: HELP")
        await pilot.press("question_mark")
        await pilot.pause()
        assert isinstance(app.screen, HelpScreen)


# -- item 5: traps and clutter --------------------------------------------------------------
@sync
async def test_a_refusal_goes_with_the_next_good_move_and_lists_are_short(tmp_path: Path) -> None:
    app = ValtermApp(tmp_path, "PROCESS", motion_rate=math.inf)
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.pause()
        await pilot.press("p", "w", "x")  # refused at READY
        await pilot.pause()
        assert "MOTION REFUSED" in screen_text(app)
        await pilot.press("1")  # a good move that says nothing
        await pilot.pause()
        assert "MOTION REFUSED" not in screen_text(app)
        # the one-line POINT of HELP POINT, then LISTL, both from the pendant's V line
        await pilot.press("v", *"POINT X1, 400, 100, 300.123456789, 0, 90, 0", "enter")
        await pilot.pause()
        assert "POINT X1 DEFINED" in screen_text(app)
        assert app.session.simulator.locations["X1"].xyz[2] == pytest.approx(300.123456789)
        await pilot.press("v", *"LISTL", "enter")
        await pilot.pause()
        assert "LOCATIONS: X1" in screen_text(app) and "LOCATION FILES: CONV  PROCESS" in screen_text(app)
        await pilot.press("r", "v", "v", *"LISTL", "enter")  # VAL-II mode: two decimals, as WHERE
        await pilot.pause()
        assert "POINT X1, 400.00, 100.00, 300.12, 0.00, 90.00, 0.00" in app.screen.transcript


@sync
async def test_escape_at_the_save_question_keeps_manipulation_and_asks_again(tmp_path: Path) -> None:
    app = ValtermApp(tmp_path, "PROCESS", motion_rate=math.inf)
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause()
        await pilot.press("m", "2", "enter", "k", "u", "s", "n")
        assert "SAVE THE NEW SET-UP FILE" in screen_text(app)
        await pilot.press("escape")
        assert type(app.screen).__name__ == "ManipulationScreen" and "NOT SAVED" in screen_text(app)
        await pilot.press("r")  # asks again
        assert "SAVE THE NEW SET-UP FILE" in screen_text(app)
        await pilot.press("y", *"MOVED", "enter")
        await pilot.pause()
        assert (tmp_path / "MOVED.SET").exists() and not app.setup_modified


@sync
async def test_kiosk_main_menu_does_not_offer_s_to_exit() -> None:
    from test_demo import HELD, until

    from valterm.core.files.demokeys import parse_demo
    from valterm.ui.demo import DemoApp

    app = DemoApp(parse_demo(HELD), speed=10, idle=600, kiosk=True, motion_rate=math.inf)
    async with app.run_test(size=(80, 24)) as pilot:
        await until(pilot, lambda: app.axes and not app.moving
                    and type(app.screen).__name__ == "MainMenuScreen", "the short script played")
        await pilot.press("x", "escape")
        await pilot.pause()
        assert "THIS IS THE MAIN MENU: ? OR F1 FOR HELP" in screen_text(app)
        assert "S TO EXIT" not in screen_text(app)


@sync
async def test_at_80x24_the_robot_is_on_screen_while_a_program_moves_it(tmp_path: Path) -> None:
    from valterm.ui.screens.valmode import Mode

    clock = FakeClock()
    app = ValtermApp(tmp_path, "PROCESS", clock=clock, motion_rate=10.0)
    (tmp_path / "JOG.DAT").write_text("    DRIVE 1,-60,50\n    TYPE \"DONE\"\n")
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause()
        await pilot.press("v", "v", *"EXEC JOG", "enter")
        clock.advance(0.3)
        await pilot.pause(0.05)
        screen = app.screen
        assert screen.mode == Mode.RUNNING and app.moving
        assert screen.model_only  # the robot, not the transcript, while it moves
        await settle(pilot, app, clock)
        assert not screen.model_only and screen.mode == Mode.COMMAND  # the text again after
        assert "DONE" in screen.transcript


@sync
async def test_the_editor_at_80x24_gives_the_listing_the_width(tmp_path: Path) -> None:
    app = ValtermApp(tmp_path, "PROCESS", motion_rate=math.inf)
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause()
        await pilot.press("e", *"PROCESS", "enter")
        await pilot.pause()
        assert "26.     TYPE PROCESS THE SECOND PART" in screen_text(app)  # one row, not three
        assert "C CONTINUE  I INSERT  D DELETE  S SAVE  E EXIT" in screen_text(app)


# -- the keymap file and the generated key table -------------------------------------------
def test_keyboard_doc_lists_the_bindings_as_they_are() -> None:
    from valterm.ui.bindings import binding_ids, current_doc

    # the repository's docs (beside tests/): the installed package has none (the sdist's suite)
    text = (Path(__file__).resolve().parent.parent / "docs" / "KEYBOARD.md").read_text(encoding="utf-8")
    assert current_doc(text) == text, "run: python -m valterm.ui.bindings"
    assert {"main.pendant", "view.model", "valmode.define", "pendant.joint3"} <= binding_ids()


def test_a_bad_keymap_file_is_named_with_its_line(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from valterm.core.files.errors import FileProblem
    from valterm.ui.bindings import load_user_keymap

    keymap = tmp_path / "keymap.toml"
    monkeypatch.setenv("VALTERM_KEYMAP", str(keymap))
    keymap.write_text('# mine\n"main.pendant" = "j"\n"main.nothing" = "x"\n')
    with pytest.raises(FileProblem, match=r"keymap.toml:3: main.nothing is no binding id"):
        load_user_keymap()
    keymap.write_text('"main.pendant" = \n')
    with pytest.raises(FileProblem, match=r"keymap.toml:1: not a keymap"):
        load_user_keymap()
    keymap.write_text('[keymap]\n"main.pendant" = "j, J"\n')
    assert load_user_keymap() == {"main.pendant": "j,J"}


@sync
async def test_a_keymap_file_rebinding_one_key_is_honoured_on_every_screen(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """view.model on F12 instead of F8: MAIN, PENDANT, KEYBOARD, MANIPULATION and VAL-II mode
    all take it, F8 no longer; main.pendant on J."""
    keymap = tmp_path / "keymap.toml"
    keymap.write_text('"view.model" = "f12"\n"main.pendant" = "j"\n')
    monkeypatch.setenv("VALTERM_KEYMAP", str(keymap))
    app = ValtermApp(tmp_path / "ws", "PROCESS", motion_rate=math.inf)
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause()
        for enter, leave, name in ((("j",), ("r",), "PendantScreen"), (("k",), ("r",), "KeyboardScreen"),
                                   ((), (), "MainMenuScreen"), (("v", "v"), ("escape", "escape"), "ValModeScreen")):
            await pilot.press(*enter)
            await pilot.pause()
            screen = app.screen
            assert type(screen).__name__ == name
            model = "model-only" if name == "ValModeScreen" else "-model"
            shown = screen.has_class(model)
            await pilot.press("f8")
            assert screen.has_class(model) == shown  # F8 is no longer the model key
            await pilot.press("f12")
            assert screen.has_class(model) != shown, name
            await pilot.press("f12")
            await pilot.press(*leave)
            await pilot.pause()
        assert type(app.screen).__name__ == "MainMenuScreen"
        await pilot.press("p")  # P is no longer PENDANT
        assert type(app.screen).__name__ == "MainMenuScreen"


@sync
async def test_a_bad_keymap_is_said_and_the_default_keys_stay(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    keymap = tmp_path / "keymap.toml"
    keymap.write_text('"main.nothing" = "j"\n')
    monkeypatch.setenv("VALTERM_KEYMAP", str(keymap))
    app = ValtermApp(tmp_path / "ws", "PROCESS", motion_rate=math.inf)
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.pause()
        assert "KEYMAP: KEYMAP.TOML:1: MAIN.NOTHING IS NO BINDING ID" in screen_text(app)
        await pilot.press("p")
        assert type(app.screen).__name__ == "PendantScreen"


# -- the thesis's keys (valterm --keys 1985) -------------------------------------------------
def table_keys(rows: list[str]) -> list[str]:
    """A table's INPUT column as keys: quoted text is typed and ended with RETURN (the tables
    leave it out after "LE", "AB", "EXEC PROCESS,1"), single keys are comma-separated."""
    keys: list[str] = []
    for row in rows:
        if row.startswith('"'):
            keys += [*row.strip('"'), "enter"]
        else:
            keys += ["enter" if key.strip() == "RETURN" else key.strip().lower() for key in row.split(",")]
    return keys


@pytest.mark.slow  # CI runs it (pytest -m slow); the default run stays under 5 minutes
@sync
async def test_keys_1985_tables_c1_to_c3_typed_as_printed_replay(tmp_path: Path) -> None:
    """--keys 1985 from MAIN with PROCESS.SET: the EDITOR rows of Tables C-1/C-2, then V, V,
    "LE", "AB", D,D, "PROCESS.LOC", A, A,A,A,A, E,W, "EXEC PROCESS,1", R at 0.3 s a key: TEST.DAT
    as the tables write it, all six locations, PROCESS completed, back at MAIN."""
    clock = FakeClock()
    app = ValtermApp(tmp_path, "PROCESS", clock=clock, motion_rate=10.0, keys="1985")
    editor = ["E", '"EDIT TEST.DAT"', "C", '" MOVE A"', '" MOVE B"', '" CLOSE I 50"', '" STOP"',
              "D,3, RETURN", "I,3,RETURN", '" MOVE E"', "S,E"]
    valmode = ["V", "V", '"LE"', '"AB"', "D,D", '"PROCESS.LOC"', "A", "A,A,A,A", "E,W", '"EXEC PROCESS,1"', "R"]
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.pause()
        await press_slowly(pilot, clock, *table_keys(editor))
        await settle(pilot, app, clock)
        steps = [line.strip() for line in (tmp_path / "TEST.DAT").read_text().splitlines() if line.strip()]
        assert steps == ["MOVE A", "MOVE B", "MOVE E", "STOP"], steps
        await press_slowly(pilot, clock, *table_keys(valmode[:-1]))
        await settle(pilot, app, clock)
        screen = app.screen
        assert set("ABCDEF") <= set(app.session.simulator.locations)
        assert "PROGRAM PROCESS COMPLETED: 1 LOOP" in screen.transcript, list(screen.transcript)[-5:]
        assert screen.keys_text.startswith("THEN PRESS: C CONTINUE")  # Fig. C-13, the transcript in sight
        assert "PROGRAM PROCESS COMPLETED: 1 LOOP" in screen_text(app)
        await press_slowly(pilot, clock, "r")
        await settle(pilot, app, clock)
        assert type(app.screen).__name__ == "MainMenuScreen" and not app.survived


def test_the_keyboard_is_chosen_by_option_or_setting(monkeypatch: pytest.MonkeyPatch) -> None:
    from valterm.cli import build_parser
    from valterm.ui.app import keyboard_of

    monkeypatch.delenv("VALTERM_KEYS", raising=False)
    assert keyboard_of(None) == "modern" and keyboard_of("1985") == "1985"
    monkeypatch.setenv("VALTERM_KEYS", "1985")
    assert keyboard_of(None) == "1985" and keyboard_of("modern") == "modern"
    monkeypatch.setenv("VALTERM_KEYS", "1984")
    assert keyboard_of(None) == "modern"  # an unknown setting: the app still starts
    assert build_parser().parse_args(["--keys", "1985"]).keys == "1985"


@sync
async def test_ctrl_c_stops_the_motion_and_drops_the_keys_typed_ahead(tmp_path: Path) -> None:
    """A jog key held down queues moves; CTRL-C stops the one drawn and the rest with it."""
    clock = FakeClock()
    app = ValtermApp(tmp_path, "PROCESS", clock=clock, motion_rate=10.0)
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.pause()
        await pilot.press("p", "1")
        assert app.moving
        await pilot.press("1", "1", "1", "1")
        assert app.keys_waiting >= 4
        await pilot.press("ctrl+c")
        await settle(pilot, app, clock)
        assert app.keys_waiting == 0
        assert app.session.simulator.joints[0] < 16.0  # one jog at most, not five
