"""Issue 17 ("never trap, never lose"): each recipe of the issue replayed with valterm.testing."""

from __future__ import annotations

import asyncio
import os
import stat
from pathlib import Path


from valterm.testing import Simulation
from valterm.ui.screens.editor import EditorScreen
from valterm.ui.screens.main_menu import MainMenuScreen
from valterm.ui.screens.manipulation import ManipulationScreen
from valterm.ui.screens.quit import QuitScreen


def run(coro) -> None:  # type: ignore[no-untyped-def]
    asyncio.run(coro)


# -- item 1: MANIPULATION dead ends ---------------------------------------------------------
def test_manipulation_keyboard_stop_escape_is_no_dead_end(tmp_path: Path) -> None:
    async def body() -> None:
        async with Simulation(tmp_path, size=(80, 24)) as sim:
            await sim.press("M")
            await sim.type("1", enter=True)
            await sim.press("K", "U", "S")
            assert "MOVE ANOTHER PART" in sim.prompt()
            await sim.press("escape")
            # back at the part's menu, a question is open: never a screen that takes no key
            assert sim.prompt() == "ENTER COMMAND# (I, K OR R):"
            before = sim.simulator.cell.object(1).reference[2]
            await sim.press("K", "U")
            assert sim.simulator.cell.object(1).reference[2] == before + 5.0  # U still moves it
            await sim.press("escape")  # ESC in K_EYBOARD is S_TOP
            assert "MOVE ANOTHER PART" in sim.prompt()
            await sim.press("escape", "escape")
            assert "SAVE THE NEW SET-UP FILE" in sim.prompt()
            await sim.press("escape")  # not now: the question goes, MANIPULATION stays (issue 27)
            assert sim.prompt() == "ENTER COMMAND# (I, K OR R):"
            assert "NOT SAVED" in sim.text()
            await sim.press("R")  # R asks again: MAIN has no save key
            assert "SAVE THE NEW SET-UP FILE" in sim.prompt()
            await sim.press("N")  # N leaves; the moved layout stays in the session, NOT SAVED
            assert isinstance(sim.screen, MainMenuScreen)
            assert "NOT SAVED" in sim.text()

    run(body())


def test_manipulation_increments_escape_is_no_dead_end(tmp_path: Path) -> None:
    async def body() -> None:
        async with Simulation(tmp_path, size=(80, 24)) as sim:
            await sim.press("M")
            await sim.type("1", enter=True)
            await sim.press("I")
            assert "COORDINATE AXES DISPLAY ON" in sim.prompt()
            await sim.press("escape")
            assert sim.prompt() == "ENTER COMMAND# (I, K OR R):"
            await sim.press("I", "N", "Y")
            await sim.press("escape")  # the typed increments: cancelled, the part's menu again
            assert sim.prompt() == "ENTER COMMAND# (I, K OR R):"
            await sim.press("R")
            assert isinstance(sim.screen, MainMenuScreen)

    run(body())


# -- item 3: the editor keeps its line open ----------------------------------------------------
def test_editor_typed_program_lines_are_never_menu_keys(tmp_path: Path) -> None:
    async def body() -> None:
        async with Simulation(tmp_path, size=(80, 24)) as sim:
            await sim.press("E")
            await sim.type("EDIT NEWPROG", enter=True)
            await sim.press("C")
            # lines that begin with menu keys (M, P, S, E, D, I) typed one after another
            lines = [" MOVE A", " PAUSE", " SPEED 50", " CLOSEI 50", " DEPART 50", " STOP"]
            for line in lines:
                assert sim.prompt().startswith("S. ")
                await sim.type(line, enter=True)
            screen = sim.screen
            assert isinstance(screen, EditorScreen)
            assert [s.text for s in screen.editor.steps] == [line.strip() for line in lines]
            assert screen.prompt == "S. 7>"  # the next prompt is already up
            await sim.press("escape")  # the line closes: the editor menu
            assert screen.mode == "menu"
            await sim.press("S")
            assert "NEWPROG.DAT SAVED" in screen.message

    run(body())


# -- item 5: quitting, DATFILER, the set-up's name, file modes ------------------------------------
def test_ctrl_q_with_unsaved_work_asks_first(tmp_path: Path) -> None:
    async def body() -> None:
        async with Simulation(tmp_path, size=(80, 24)) as sim:
            await sim.press("M")
            await sim.type("1", enter=True)
            await sim.press("K", "U", "ctrl+q")
            assert isinstance(sim.screen, QuitScreen)
            assert "EXIT WITHOUT SAVING (Y/N) ?" in sim.text()
            await sim.press("N")
            assert isinstance(sim.screen, ManipulationScreen)
            await sim.press("ctrl+q", "Y")
            await sim.pilot.pause()
            assert sim.app.return_code == 0 and not sim.app.is_running

    run(body())


def test_ctrl_q_without_unsaved_work_leaves_at_once(tmp_path: Path) -> None:
    async def body() -> None:
        async with Simulation(tmp_path, size=(80, 24)) as sim:
            await sim.press("ctrl+q")
            await sim.pilot.pause()
            assert not sim.app.is_running

    run(body())


def test_program_never_saved_leaves_datfiler(tmp_path: Path) -> None:
    async def body() -> None:
        async with Simulation(tmp_path, size=(80, 24)) as sim:
            await sim.press("E")
            await sim.type("EDIT GHOST", enter=True)
            assert "GHOST" in sim.session.workspace.programs_directory()  # §5.1, while editing
            await sim.press("C")
            await sim.type(" MOVE A", enter=True)
            await sim.press("escape", "E", "N")  # exit, do not save
            assert isinstance(sim.screen, MainMenuScreen)
            assert "GHOST" not in sim.session.workspace.list_programs()
            await sim.press("K", "L")
            await sim.type("LISTF", enter=True)
            assert "GHOST" not in sim.text()

    run(body())


def test_main_shows_the_new_setup_name_after_save_as(tmp_path: Path) -> None:
    async def body() -> None:
        async with Simulation(tmp_path, size=(80, 24)) as sim:
            await sim.press("M")
            await sim.type("1", enter=True)
            await sim.press("K", "U", "S", "N", "Y")
            await sim.type("NEWCELL", enter=True)
            await sim.pilot.pause()
            assert isinstance(sim.screen, MainMenuScreen)
            assert "SETUP FILE NEWCELL.SET" in sim.text()
            assert "NEWCELL.SET" in sim.status() and "NOT SAVED" not in sim.text()

    run(body())


def test_saved_setup_file_mode_follows_the_umask(tmp_path: Path) -> None:
    """Saved files are 0644 under umask 022 (the safe write path creates its temporary 0666 & ~umask)."""
    async def body() -> None:
        async with Simulation(tmp_path, size=(80, 24)) as sim:
            await sim.press("M")
            await sim.type("1", enter=True)
            await sim.press("K", "U", "S", "N", "Y")
            await sim.type("MODECELL", enter=True)
            await sim.pilot.pause()

    old = os.umask(0o022)
    try:
        run(body())
    finally:
        os.umask(old)
    mode = stat.S_IMODE((tmp_path / "MODECELL.SET").stat().st_mode)
    assert mode == 0o644, oct(mode)


# -- item 6: the status line and the help hint ------------------------------------------------
def test_status_line_on_every_screen(tmp_path: Path) -> None:
    async def body() -> None:
        async with Simulation(tmp_path, size=(160, 50)) as sim:
            status = sim.status()
            for word in ("PROCESS.SET SAVED", "SPEED 100", "COLLISION CHECKS OFF", "BACK FACES OFF",
                         "AXES OFF", "CONFIG RIGHTY ABOVE NOFLIP", "ARM ", "? OR F1: HELP"):
                assert word in status, (word, status)
            await sim.press("K", "S", "F", "A")
            status = sim.status()
            assert "COLLISION CHECKS ON" in status and "BACK FACES ON" in status and "AXES ON" in status
            assert status in sim.text()
            await sim.press("V")
            await sim.type("SPEED 30", enter=True)
            assert "SPEED 30" in sim.status()
            for screen in ("R", "P", "question_mark", "escape", "R", "E"):
                await sim.press(screen)
                assert sim.status() and sim.status() in sim.text(), screen

    run(body())


def test_unknown_keys_are_answered_and_question_mark_helps(tmp_path: Path) -> None:
    async def body() -> None:
        async with Simulation(tmp_path, size=(80, 24)) as sim:
            await sim.press("Q")
            assert "'Q' IS NOT A KEY OF THIS MENU; ? OR F1: HELP" in sim.messages()
            await sim.press("P", "f12")
            assert "'F12' IS NOT A KEY OF THIS MENU; V FIRST TO TYPE A VAL-II COMMAND; ? OR F1: HELP" in sim.messages()
            await sim.press("question_mark")
            assert "KEYS OF THE PENDANT MODE SCREEN" in sim.text()
            await sim.press("escape")
            await sim.press("W", "Q")
            assert any("IS NOT AN ANSWER: PRESS X, Y, Z" in line for line in sim.messages())
            await sim.press("escape", "escape", "K", "7")     # at the KEYBOARD menu: the hint names V
            assert ("'7' IS NOT A KEY OF THIS MENU; V FIRST TO TYPE A VAL-II COMMAND; ? OR F1: HELP"
                    in sim.messages())

    run(body())


def test_a_command_typed_at_the_keyboard_menu_without_v_is_taken_whole(tmp_path: Path) -> None:
    """HERE P1 typed at the KEYBOARD menu, as at the real terminal: H is no menu key, so it
    opens V's command line with the H in it and the rest is typed there (R and E are not taken
    as RETURN and the editor)."""
    async def body() -> None:
        async with Simulation(tmp_path, size=(80, 24)) as sim:
            await sim.press("K")
            await sim.type("HERE P1", enter=True, pace=0.05)
            assert type(sim.screen).__name__ == "KeyboardScreen"     # not MAIN, not the editor
            assert sim.messages() == ["    HERE P1", "LOCATION P1 TAUGHT HERE (0.00, 158.75, 990.60) RIGHTY ABOVE NOFLIP"]
            assert "P1" in sim.simulator.locations
            await sim.type("DRIVE 1,10,1", pace=0.05)
            assert sim.prompt() == "VAL-II COMMAND:"
            assert sim.screen.query_one("#answer").value == "DRIVE 1,10,1"
            await sim.press("escape")                     # ESC cancels the line: nothing runs
            assert not sim.prompt() and not sim.moving
            assert type(sim.screen).__name__ == "KeyboardScreen"

    run(body())


# -- item 7: messages replace, at most three lines -------------------------------------------
def test_messages_replace_and_refusal_is_cleared(tmp_path: Path) -> None:
    async def body() -> None:
        async with Simulation(tmp_path, size=(80, 24)) as sim:
            await sim.press("P", "W", "X")
            assert any("MOTION REFUSED" in line for line in sim.messages())
            await sim.press("3")  # a joint move that succeeds
            assert not any("MOTION REFUSED" in line for line in sim.messages())
            for _ in range(6):
                await sim.press("I")
            assert len(sim.messages()) <= 3
            assert sim.messages() == ["ROTATIONAL INCREMENT +56.00 DEG (WORLD/TOOL STEP +70.00 MM)"]  # 1985: I adds 8

    run(body())


def test_collision_pair_not_repeated_every_step(tmp_path: Path) -> None:
    async def body() -> None:
        async with Simulation(tmp_path, size=(160, 50)) as sim:
            log = sim.screen.messages
            log.new_turn()
            for _ in range(5):
                log.say("COLLISION BETWEEN LINK 6 AND PART 3", "warning")
            assert log.text.splitlines() == ["COLLISION BETWEEN LINK 6 AND PART 3"]
            log.say("error in lower case", "error")
            assert "ERROR IN LOWER CASE" in log.text

    run(body())


# -- item 8: 80x24 menus reachable, the model toggled -----------------------------------------
def test_80x24_menus_page_and_model_toggles(tmp_path: Path) -> None:
    async def body() -> None:
        async with Simulation(tmp_path, size=(80, 24)) as sim:
            await sim.press("K", "O")  # ORIENT1 fits; the long KEYBOARD MENU pages when short
            await sim.press("R", "R")
            await sim.press("R")  # MAIN: R shows the model instead of the menu
            assert sim.screen.model_shown
            assert "MAIN MENU" not in sim.text()
            assert any(set(row) & set("⣿⡇⠉⣀") for row in sim.rows())
            await sim.press("R")
            assert "MAIN MENU" in sim.text()

    run(body())


def test_menu_pages_when_it_does_not_fit(tmp_path: Path) -> None:
    async def body() -> None:
        async with Simulation(tmp_path, size=(80, 16)) as sim:
            await sim.press("P")
            text = sim.text()
            assert "-- MORE: PGDN (PGUP BACK) --" in text
            assert "V VAL-II : BEFORE ENTERING A VAL COMMAND" not in text
            await sim.press("pagedown", "pagedown", "pagedown")
            assert "V VAL-II : BEFORE ENTERING A VAL COMMAND" in sim.text()
            await sim.press("pageup", "pageup", "pageup")
            assert "- 1 - (JOINT 1) TO ROTATE ABOUT WAIST" in sim.text()

    run(body())


# -- item 9: teaching ------------------------------------------------------------------------------
def test_world_jog_at_ready_gives_a_hint_and_mm(tmp_path: Path) -> None:
    async def body() -> None:
        async with Simulation(tmp_path, size=(160, 50)) as sim:
            await sim.press("P")
            assert "WORLD/TOOL STEP +10.00 MM" in sim.text()
            await sim.press("W")
            assert "WORLD MODE (+10.00 MM)" in sim.prompt()
            await sim.press("X")
            assert any(line.startswith("HINT:") for line in sim.messages())
            for key in ("3", "3", "5", "5"):
                await sim.press(key)
            before = sim.where().xyz
            await sim.press("W", "X")
            assert abs(sim.where().xyz[0] - before[0] - 10.0) < 0.5

    run(body())


def test_here_confirms_and_configuration_change_is_announced(tmp_path: Path) -> None:
    async def body() -> None:
        async with Simulation(tmp_path, size=(160, 50)) as sim:
            await sim.press("P", "V")
            await sim.type("HERE SPOT", enter=True)
            assert any(line.startswith("LOCATION SPOT TAUGHT HERE (") for line in sim.messages())
            sim.simulator.stand_at([0.0, -60.0, *sim.simulator.joints[2:]])  # shoulder forward: RIGHTY at a joint move away
            before = sim.status()
            await sim.press("N")
            for _ in range(12):
                await sim.press("2")
                if sim.status() != before:
                    break
            assert sim.status() != before
            assert any(line.startswith("ARM CONFIGURATION CHANGED: ") for line in sim.messages())

    run(body())


def test_long_listing_lines_wrap_not_cut(tmp_path: Path) -> None:
    long_step = "TYPE " + "A VERY LONG MESSAGE " * 4
    (tmp_path / "LONG.DAT").write_text(f" {long_step.strip()}\n STOP\n")

    async def body() -> None:
        async with Simulation(tmp_path, size=(80, 24)) as sim:
            await sim.press("K", "L")
            await sim.type("LISTP LONG", enter=True)
            text = " ".join(row.strip() for row in sim.rows())
            assert " ".join(long_step.split()) in " ".join(text.split())
            assert all(len(row) <= 80 for row in sim.rows())

    run(body())


def test_a_refused_answer_s_message_goes_when_the_next_answer_is_taken(tmp_path: Path) -> None:
    """MANIPULATION: 99 is no part number (said); 3 is taken and says nothing itself, so the
    refusal must not stay on screen beside part 3's coordinates."""
    async def body() -> None:
        async with Simulation(tmp_path, size=(80, 24)) as sim:
            await sim.press("M")
            await sim.type("99", enter=True)
            assert sim.messages() == ["99 IS NOT A PART NUMBER (1-14)"]
            await sim.type("3", enter=True)
            assert "PART NO. 3" in sim.text()
            assert sim.messages() == []

    run(body())
