"""VAL-II mode's keyboard (issue 17 item 2): the command line stays open between commands,
every printable key typed there is text (READY, WHERE, MOVE, DEPART, CLOSEI are commands, not
menu keys), nothing typed is lost, ESC at every prompt leads to the VAL-II menu and from there
to MAIN; the menu pages are reachable at 80x24 and the model is toggled there."""

from __future__ import annotations

import pytest

from pathlib import Path

import numpy as np
from app_helpers import FakeClock, make_app, screen_text, sync, until

from valterm.core import resources
from valterm.core.render.raster import Frame
from valterm.ui.screens.main_menu import MainMenuScreen
from valterm.ui.screens.valmode import WIDE, Mode, ValModeScreen, wrap_menu
from valterm.ui.widgets.menus import VAL_MENU_2

# one harmless line for every command of COMMAND.DAT (assignment needs no command word)
TYPED = {
    "HERE": "HERE P1", "WHERE": "WHERE", "BASE": "BASE 0, 0, 0, 0", "SET": "SET P2=P1",
    "SHIFT": "SHIFT P2 BY 10, 0, 0", "POINT": "POINT P3", "MOVE": "MOVE P1", "MOVES": "MOVES P1",
    "ALIGN": "ALIGN", "APPRO": "APPRO P1, 50", "APPROS": "APPROS P1, 50", "DEPART": "DEPART 10",
    "DEPARTS": "DEPARTS 10", "DRIVE": "DRIVE 1, 10, 50", "DRAW": "DRAW 0, 0, 10", "READY": "READY",
    "DELAY": "DELAY 0", "OPEN": "OPEN", "OPENI": "OPENI 50", "CLOSE": "CLOSE", "CLOSEI": "CLOSEI 50",
    "GRASP": "GRASP 50", "GOTO": "GOTO 10", "CALL": "CALL T1", "RETURN": "RETURN", "PAUSE": "PAUSE",
    "STOP": "STOP", "HALT": "HALT", "DO": "DO", "UNTIL": "UNTIL X == 1", "IF": "IF X == 1 THEN",
    "ELSE": "ELSE", "END": "END", "ENDIF": "ENDIF", "WHILE": "WHILE X == 1 DO",
    "EXECUTE": "EXECUTE T1, 1", "PROCEED": "PROCEED", "RIGHTY": "RIGHTY", "LEFTY": "LEFTY",
    "ABOVE": "ABOVE", "BELOW": "BELOW", "FLIP": "FLIP", "NOFLIP": "NOFLIP", "SPEED": "SPEED 50",
    "TYPE": "TYPE X=", "STATUS": "STATUS", "HELP": "HELP MOVE", "LISTP": "LISTP T1",
    "LISTF": "LISTF", "LISTL": "LISTL", "EDIT": "EDIT T1",
    # the debugger's monitor commands (issue 13)
    "BPT": "BPT T1, 1", "XSTEP": "XSTEP", "SSTEP": "SSTEP", "WATCH": "WATCH X", "TRACE": "TRACE OFF",
    "AUTOCONFIG": "AUTOCONFIG OFF",
    # the robot's state (issue 22)
    "STOREL": "STOREL T1", "LOAD": "LOAD T1", "RULES": "RULES 1985",
}


def command_names() -> list[str]:
    lines = resources.data_path("COMMAND.DAT").read_text().splitlines()
    return [line.split()[0] for line in lines if line.strip() and not line.startswith(";")]


async def open_valmenu(app, pilot) -> ValModeScreen:  # type: ignore[no-untyped-def]
    """From MAIN: V shows the VAL-II menu."""
    await pilot.pause()
    await pilot.press("v")
    await pilot.pause()
    screen = app.screen
    assert isinstance(screen, ValModeScreen) and screen.mode == Mode.MENU
    return screen


async def open_valmode(app, pilot) -> ValModeScreen:  # type: ignore[no-untyped-def]
    """From MAIN: V shows the VAL-II menu, V opens the command line."""
    screen = await open_valmenu(app, pilot)
    await pilot.press("v")
    await pilot.pause()
    assert screen.mode == Mode.COMMAND
    return screen


async def type_slowly(pilot, text: str, *, pause_each: bool = True) -> None:  # type: ignore[no-untyped-def]
    """One key at a time, everything the app does in between done (a slow typist).

    Each press already waits until the app is idle; ``pause_each`` adds a pause after every
    key (else after the first only, where keys used to be lost): presses cost ~0.1 s each."""
    for at, char in enumerate(text):
        await pilot.press("space" if char == " " else char)
        if pause_each or at == 0:
            await pilot.pause()
    await pilot.press("enter")
    await pilot.pause()


def echoes(screen: ValModeScreen) -> list[str]:
    return [line for line in screen.transcript if line.startswith(". ")]


async def back_to_the_line(app, pilot, screen: ValModeScreen) -> None:  # type: ignore[no-untyped-def]
    """Close what a command opened (HELP's screen, the editor, POINT's line)."""
    while app.screen is not screen:
        app.pop_screen()
        await pilot.pause()
    if screen.mode != Mode.COMMAND:
        await pilot.press("escape")
        assert screen.mode == Mode.MENU
        await pilot.press("v")
        await pilot.pause()
    assert screen.mode == Mode.COMMAND


@pytest.mark.slow  # CI runs it (pytest -m slow); the default run stays under 5 minutes
@sync
async def test_every_command_typed_key_by_key_is_echoed_exactly(tmp_path: Path) -> None:
    names = command_names()
    assert set(names) == set(TYPED), "a command of COMMAND.DAT has no typed line here"
    app = make_app(tmp_path)
    (tmp_path / "T1.DAT").write_text("    TYPE T1 RAN\n")
    async with app.run_test(size=(80, 24)) as pilot:
        screen = await open_valmode(app, pilot)
        for line in [TYPED[name] for name in names] + ["X=1"]:
            await type_slowly(pilot, line, pause_each=False)
            assert app.screen is screen or line in ("HELP MOVE", "EDIT T1"), line
            assert echoes(screen)[-1] == f". {line}"  # every key arrived, none was a menu key
            await back_to_the_line(app, pilot, screen)
        assert "T1 RAN" in screen.transcript
        assert not (tmp_path / "ADY.DAT").exists()


@sync
async def test_the_issue_recipes(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(80, 24)) as pilot:
        screen = await open_valmode(app, pilot)
        await type_slowly(pilot, "BELOW")
        assert screen.simulator.config.elbow == -1
        # LE RETURN then AB RETURN: A is not lost after the result
        await type_slowly(pilot, "LE")
        await type_slowly(pilot, "AB")
        assert echoes(screen)[-2:] == [". LE", ". AB"]
        assert not any("AMBIGUOUS" in line for line in screen.transcript)
        assert (screen.simulator.config.arm, screen.simulator.config.elbow) == (-1, 1)
        await type_slowly(pilot, "RIGHTY")
        await type_slowly(pilot, "LEFTY")
        assert echoes(screen)[-1] == ". LEFTY" and screen.simulator.config.arm == -1
        # READY is a command: R does not return, E does not open the editor
        await type_slowly(pilot, "READY")
        assert app.screen is screen and screen.mode == Mode.COMMAND
        assert echoes(screen)[-1] == ". READY"
        assert not list(tmp_path.glob("ADY*"))
        # WHERE prints where the robot is: W does not wipe
        await type_slowly(pilot, "WHERE")
        assert echoes(screen) == [". BELOW", ". LE", ". AB", ". RIGHTY", ". LEFTY", ". READY", ". WHERE"]
        assert screen.transcript[-4].startswith(("OPENED", "CLOSED"))
        # fast typing (no pause between keys) loses nothing either
        await pilot.press(*"MOVES P1", "enter")
        await pilot.pause()
        assert echoes(screen)[-1] == ". MOVES P1"


@sync
async def test_keys_typed_while_a_program_runs_wait_in_the_line(tmp_path: Path) -> None:
    clock = FakeClock()
    app = make_app(tmp_path, rate=10.0, clock=clock)
    (tmp_path / "SLOW.DAT").write_text('    DELAY 5\n    TYPE "DONE"\n')
    async with app.run_test(size=(160, 50)) as pilot:
        screen = await open_valmode(app, pilot)
        await type_slowly(pilot, "EXEC SLOW")
        assert screen.mode == Mode.RUNNING
        await type_slowly(pilot, "WHERE")  # typed ahead: waits for the program
        await type_slowly(pilot, "STATUS")
        await pilot.press(*"REA")  # and a line being typed when it ends stays in the line
        assert echoes(screen)[-1] == ". EXEC SLOW"
        clock.t += 6.0
        await until(pilot, lambda: screen.mode == Mode.COMMAND and echoes(screen)[-1] == ". STATUS",
                    "the lines typed ahead run")
        lines = list(screen.transcript)
        assert lines.index("PROGRAM SLOW COMPLETED: 1 LOOP") < lines.index(". WHERE") < lines.index(". STATUS")
        assert screen.query_one("#val-line").value == "REA"
        await pilot.press("D", "Y", "enter")
        assert echoes(screen)[-1] == ". READY"


async def escape_to_menu(pilot, screen: ValModeScreen) -> None:  # type: ignore[no-untyped-def]
    await pilot.press("escape")
    await pilot.pause()
    assert screen.mode == Mode.MENU, screen.mode
    assert "VAL-II MENU" in screen_text(screen.app)
    await pilot.press("v")  # and the line works again: never stranded
    await pilot.pause()
    assert screen.mode == Mode.COMMAND


@sync
async def test_escape_at_every_prompt_leads_to_the_menu_then_main(tmp_path: Path) -> None:
    clock = FakeClock()
    app = make_app(tmp_path, rate=10.0, clock=clock)
    (tmp_path / "WAIT.DAT").write_text("    PAUSE\n    STOP\n")
    (tmp_path / "SLOW.DAT").write_text("    DELAY 100\n")
    async with app.run_test(size=(80, 24)) as pilot:
        screen = await open_valmode(app, pilot)
        await pilot.press(*"MOVE A")  # a half-typed line
        await escape_to_menu(pilot, screen)
        assert screen.query_one("#val-line").value == ""
        await pilot.press("ctrl+t")  # D_DEFINE: data file or point?
        assert screen.mode == Mode.DEFINE
        await escape_to_menu(pilot, screen)
        await pilot.press("ctrl+t", "d")  # the .LOC file name
        assert screen.mode == Mode.DEFINE_FILE
        await escape_to_menu(pilot, screen)
        await pilot.press("ctrl+t", "p")  # a POINT typed in
        assert screen.mode == Mode.POINT
        await escape_to_menu(pilot, screen)
        await type_slowly(pilot, "POINT Q")  # POINT as a command opens the same line
        assert screen.mode == Mode.POINT and screen.query_one("#val-line").value == "Q, "
        await escape_to_menu(pilot, screen)
        # A / R / E for a location (typed while the robot moves there), ESC while it moves
        await type_slowly(pilot, "LEFTY")  # A is out of reach RIGHTY
        await pilot.press("ctrl+t", "d")
        await type_slowly(pilot, "PROCESS.LOC")
        assert screen.mode == Mode.RUNNING  # moving to A
        await pilot.press("a")  # answered ahead
        clock.t += 100.0
        await until(pilot, lambda: "A ACCEPTED" in screen.transcript, "A accepted")
        assert screen.mode == Mode.RUNNING and screen.transcript[-1].startswith("POINT B")  # moving to B
        await escape_to_menu(pilot, screen)
        assert sorted(screen.simulator.locations) == ["A"]
        assert "LOCATIONS DEFINED: A" in screen.transcript
        # a running and a paused program are aborted
        await type_slowly(pilot, "EXEC SLOW")
        assert screen.mode == Mode.RUNNING
        await escape_to_menu(pilot, screen)
        assert not screen.interpreter.running
        await type_slowly(pilot, "EXEC WAIT")
        assert screen.mode == Mode.PAUSED
        await escape_to_menu(pilot, screen)
        assert not screen.interpreter.running
        # the model alone: ESC brings the text back, then the menu
        await pilot.press("f8")
        assert screen.model_only
        await pilot.press("escape")
        assert not screen.model_only and screen.mode == Mode.COMMAND
        await escape_to_menu(pilot, screen)
        # the thesis's letters act on the menu: W wipes and opens the line, R returns
        await pilot.press("escape", "w")
        assert screen.mode == Mode.COMMAND and not screen.query_one("#val-log").lines
        await pilot.press("escape", "r")
        await pilot.pause()
        assert isinstance(app.screen, MainMenuScreen)
        screen = await open_valmode(app, pilot)
        await pilot.press(*"DEP", "ctrl+n")  # CTRL-N: the VAL-II menu from the line, again: its other page
        assert screen.mode == Mode.MENU and screen.page == 1
        await pilot.press("ctrl+n")
        assert screen.page == 2 and "VAL-II MENU CONTINUED" in screen.menu_text
        await pilot.press("v", *"DEP", "f9")  # F9: MAIN from the line
        await pilot.pause()
        assert isinstance(app.screen, MainMenuScreen)
        await open_valmode(app, pilot)
        await pilot.press("escape", "escape")
        await pilot.pause()
        assert isinstance(app.screen, MainMenuScreen)


@sync
async def test_the_menu_pages_at_80x24_and_the_model_at_both_sizes(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(80, 24)) as pilot:
        screen = await open_valmenu(app, pilot)
        assert screen.has_class("narrow")
        await pilot.press("7")  # not a key of the menu: said so, the menu stays
        assert screen.keys_text.startswith("'7' IS NOT A KEY OF THIS MENU; ? OR F1: HELP") and screen.mode == Mode.MENU
        assert "NOFLIP       - POSITIVE JOINT 5 ANGLES" not in screen_text(app)  # below the fold
        seen = ""
        for _ in range(4):  # paged through: every line of page 1 can be read
            await pilot.press("pagedown")
            await pilot.pause()
            seen += screen_text(app)
        assert "NOFLIP       - POSITIVE JOINT 5 ANGLES" in seen
        await pilot.press("n")
        await pilot.pause()
        seen = screen_text(app)
        for _ in range(3):  # page 2, paged through: every line of it can be read
            await pilot.press("pagedown")
            await pilot.pause()
            seen += screen_text(app)
        assert "HELP             - WRITES DESCRIPTION OF VAL-II COMMANDS" in seen
        await pilot.press("end")
        for _ in range(3):
            await pilot.press("pagedown")
        await pilot.pause()
        assert "D_DEFINE   : TO DEFINE ORIENTATIONS" in screen_text(app)
        # the model: hidden beside the text, the whole width when toggled
        assert screen.query_one("#val-model").size.width == 0
        await pilot.press("m")
        await pilot.pause()
        assert screen.query_one("#val-model").size.width == 80
        await pilot.press("x")  # any key brings the text back
        await pilot.pause()
        assert not screen.model_only
    app = make_app(tmp_path / "wide")
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.pause()
        await pilot.press("v")
        await pilot.pause()
        screen = app.screen
        assert isinstance(screen, ValModeScreen) and not screen.has_class("narrow") and WIDE <= 160
        assert screen.query_one("#val-model").size.width >= 80
        text = screen_text(app)
        assert "NOFLIP       - POSITIVE JOINT 5 ANGLES" in text


def test_menu_lines_wrap_under_their_description() -> None:
    wrapped = wrap_menu(VAL_MENU_2, 66).splitlines()
    assert max(len(line) for line in wrapped) <= 66
    at = wrapped.index("VAR 1 = VAR 2    - SETS VAR. ON THE LEFT EQUAL TO ONE ON THE RIGHT")
    assert wrapped[at + 1] == " " * 19 + "OF EQUAL SIGN"
    assert "HELP             - WRITES DESCRIPTION OF VAL-II COMMANDS" in wrapped


def test_a_frame_of_no_columns_has_no_changed_spans() -> None:
    empty = Frame(np.zeros((3, 0), dtype=np.uint32), np.zeros((3, 0), dtype=np.uint8))
    rows, x0, x1 = empty.changed_spans(empty)
    assert len(rows) == len(x0) == len(x1) == 0


@sync
async def test_a_command_typed_at_the_menu_opens_the_line_with_it(tmp_path: Path) -> None:
    """LOAD PROCESS typed at the VAL-II menu: L is no menu key, so it opens the command line with
    the L typed, and O, A, D (D: DEFINE at the menu) go into the line."""
    app = make_app(tmp_path)
    async with app.run_test(size=(80, 24)) as pilot:
        screen = await open_valmenu(app, pilot)
        for key in "LOAD PROCESS":
            await pilot.press("space" if key == " " else key)
            await pilot.pause(0.02)
        assert screen.mode == Mode.COMMAND
        assert screen.query_one("#val-line").value == "LOAD PROCESS"


@sync
async def test_shift_up_and_down_read_the_transcript_back(tmp_path: Path) -> None:
    """A keyboard-only user reads back what scrolled away: SHIFT+UP a page back, SHIFT+DOWN on."""
    app = make_app(tmp_path)
    async with app.run_test(size=(80, 24)) as pilot:
        screen = await open_valmode(app, pilot)
        for _ in range(6):                        # more lines than the log shows
            await pilot.press(*"WHERE", "enter")
            await pilot.pause()
        log = screen.query_one("#val-log")
        end = log.scroll_y
        assert end == log.max_scroll_y > 0
        await pilot.press("shift+up")
        await pilot.pause()
        assert log.scroll_y == max(0, end - (log.scrollable_content_region.height - 1))
        await pilot.press("shift+down")
        await pilot.pause()
        assert log.scroll_y == end
        assert screen.query_one("#val-line").value == ""      # nothing typed into the line
