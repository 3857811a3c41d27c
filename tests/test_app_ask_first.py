"""Nothing dropped without a word (issue 35 item 4): MAIN's I_INITIALIZE and B_BEGIN ask
first, naming the taught locations no .LOC file holds and saying what goes back to its
start (SPEED, collision checks, LEFTY ...), ESC losing nothing; a command typed at the
VAL-II line while a program runs is echoed as queued and runs after it, or is said to be
discarded when the program is aborted."""

from __future__ import annotations

from pathlib import Path

from app_helpers import FakeClock, make_app, screen_text, sync, until

from valterm.core.kinematics import Config
from valterm.ui.screens.main_menu import MainMenuScreen
from valterm.ui.screens.quit import QuitScreen
from valterm.ui.screens.start import StartScreen
from valterm.ui.screens.valmode import Mode, ValModeScreen


def teach(app) -> None:  # type: ignore[no-untyped-def]
    """Two locations taught and not stored; SPEED, collision checks and LEFTY changed."""
    session = app.session
    sim = session.simulator
    session.define_location("P1", sim.here_location())
    session.define_location("PICK", sim.here_location())
    sim.set_speed(50)
    sim.collision_checks = True
    sim.config = Config(-1, 1, 1)


def question_text(app) -> str:  # type: ignore[no-untyped-def]
    return screen_text(app)


@sync
async def test_initialize_asks_naming_the_unsaved_locations_and_escape_keeps_them(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause()
        teach(app)
        before = app.session
        await pilot.press("I")
        await pilot.pause()
        assert isinstance(app.screen, QuitScreen)
        text = question_text(app)
        assert "2 LOCATIONS (P1, PICK)" in text
        assert "SPEED 50" in text and "COLLISION CHECKS ON" in text and "LEFTY" in text
        assert "INITIALIZE WITHOUT SAVING (Y/N) ?" in text
        await pilot.press("escape")
        await pilot.pause()
        assert isinstance(app.screen, MainMenuScreen)
        assert app.session is before  # nothing lost, nothing reset
        assert sorted(app.session.simulator.locations) == ["P1", "PICK"]
        assert app.session.simulator.speed == 50 and app.session.simulator.config.words[0] == "LEFTY"
        assert "INITIALIZE CANCELLED: NOTHING LOST, NOTHING RESET" in screen_text(app)
        await pilot.press("I")
        await pilot.pause()
        await pilot.press("N")  # N is no too
        await pilot.pause()
        assert app.session is before
        await pilot.press("I")
        await pilot.pause()
        await pilot.press("Y")
        await pilot.pause()
        assert isinstance(app.screen, MainMenuScreen)
        sim = app.session.simulator
        assert app.session is not before and not sim.locations
        assert sim.speed == 100 and not sim.collision_checks and sim.config.words[0] == "RIGHTY"
        shown = screen_text(app)
        assert "INITIALIZED WITH PROCESS.SET" in shown
        assert "SPEED 50 BACK TO 100" in shown and "LEFTY BACK TO RIGHTY" in shown


@sync
async def test_initialize_with_nothing_unsaved_goes_on_and_says_what_was_reset(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.pause()
        app.session.simulator.set_speed(30)
        await pilot.press("I")
        await pilot.pause()
        assert isinstance(app.screen, MainMenuScreen)  # no question: nothing would be lost
        assert app.session.simulator.speed == 100
        assert "INITIALIZED WITH PROCESS.SET: SPEED 30 BACK TO 100" in screen_text(app)


@sync
async def test_begin_asks_first_and_escape_keeps_the_session(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.pause()
        teach(app)
        before = app.session
        await pilot.press("B")
        await pilot.pause()
        assert isinstance(app.screen, QuitScreen)
        text = question_text(app)
        assert "2 LOCATIONS (P1, PICK)" in text and "BEGIN WITHOUT SAVING (Y/N) ?" in text
        assert "SPEED 50" in text
        await pilot.press("escape")
        await pilot.pause()
        assert isinstance(app.screen, MainMenuScreen) and app.session is before
        assert sorted(app.session.simulator.locations) == ["P1", "PICK"]
        await pilot.press("B")
        await pilot.pause()
        await pilot.press("Y")
        await pilot.pause()
        assert isinstance(app.screen, StartScreen)
        assert "SPEED 50 BACK TO 100" in screen_text(app)  # what the next set-up starts without


# -- typed while a program runs ---------------------------------------------------------------
async def run_slow(app, pilot) -> ValModeScreen:  # type: ignore[no-untyped-def]
    """VAL-II mode, a program running (DELAY 5), WHERE and LISTL typed meanwhile."""
    from test_app_valkeys import open_valmode, type_slowly

    screen = await open_valmode(app, pilot)
    await type_slowly(pilot, "EXEC SLOW")
    assert screen.mode == Mode.RUNNING
    await type_slowly(pilot, "WHERE")
    await type_slowly(pilot, "LISTL")
    return screen


def slow_program(tmp_path: Path) -> None:
    (tmp_path / "SLOW.DAT").write_text('    DELAY 5\n    TYPE "DONE"\n')


@sync
async def test_a_command_typed_while_a_program_runs_is_echoed_as_queued_then_runs(tmp_path: Path) -> None:
    clock = FakeClock()
    app = make_app(tmp_path, rate=10.0, clock=clock)
    slow_program(tmp_path)
    async with app.run_test(size=(120, 40)) as pilot:
        screen = await run_slow(app, pilot)
        assert list(screen.transcript)[-2:] == ["QUEUED: WHERE", "QUEUED: LISTL"]
        assert "QUEUED: LISTL" in screen_text(app)
        clock.t += 6.0
        await until(pilot, lambda: screen.mode == Mode.COMMAND and ". LISTL" in screen.transcript,
                    "the queued commands run")
        lines = list(screen.transcript)
        assert lines.index("QUEUED: LISTL") < lines.index("PROGRAM SLOW COMPLETED: 1 LOOP") \
            < lines.index(". WHERE") < lines.index(". LISTL")


@sync
async def test_queued_commands_are_said_to_be_discarded_when_the_program_is_aborted(tmp_path: Path) -> None:
    clock = FakeClock()
    app = make_app(tmp_path, rate=10.0, clock=clock)
    slow_program(tmp_path)
    async with app.run_test(size=(80, 24)) as pilot:
        screen = await run_slow(app, pilot)
        await pilot.press("ctrl+c")
        await until(pilot, lambda: screen.mode == Mode.COMMAND, "the abort ends the program")
        assert "2 QUEUED COMMANDS DISCARDED: WHERE, LISTL" in screen.transcript
        clock.t += 6.0
        await pilot.pause()
        assert ". WHERE" not in screen.transcript and ". LISTL" not in screen.transcript


@sync
async def test_escape_aborting_a_program_says_the_queued_command_is_discarded(tmp_path: Path) -> None:
    from test_app_valkeys import open_valmode, type_slowly

    clock = FakeClock()
    app = make_app(tmp_path, rate=10.0, clock=clock)
    slow_program(tmp_path)
    async with app.run_test(size=(120, 40)) as pilot:
        screen = await open_valmode(app, pilot)
        await type_slowly(pilot, "EXEC SLOW")
        await type_slowly(pilot, "WHERE")
        await pilot.press("escape")
        await until(pilot, lambda: screen.mode == Mode.MENU, "ESC aborts to the VAL-II menu")
        assert "1 QUEUED COMMAND DISCARDED: WHERE" in screen.transcript


@sync
async def test_under_the_1985_keyboard_initialize_acts_at_once_and_says_what_it_dropped(tmp_path: Path) -> None:
    """--keys 1985: Tables C-1..C-3 typed as printed have no answer to a question, so I acts
    at once as the 1985 program did, and the message names the locations it dropped."""
    from valterm.ui.app import ValtermApp

    app = ValtermApp(tmp_path, "PROCESS", motion_rate=float("inf"), keys="1985")
    async with app.run_test(size=(80, 24)) as pilot:
        await until(pilot, lambda: isinstance(app.screen, MainMenuScreen) and app.session is not None, "MAIN MENU")
        teach(app)
        before = app.session
        await pilot.press("I")
        await pilot.pause()
        assert isinstance(app.screen, MainMenuScreen)  # no question
        assert app.session is not before and app.session.simulator.locations == {}
        text = screen_text(app)
        assert "2 LOCATIONS (P1, PICK) DISCARDED" in text and "SPEED 50 BACK TO 100" in text
