"""KEYBOARD, PENDANT and MANIPULATION modes driven key by key; motion pacing and CTRL-C."""

from __future__ import annotations

from pathlib import Path

from app_helpers import FakeClock, make_app, screen_text, sync

from valterm.core.cycletime import joint_motion_seconds
from valterm.ui.screens.keyboard import KeyboardScreen
from valterm.ui.screens.main_menu import MainMenuScreen
from valterm.ui.widgets.menus import KEYBOARD_MENU, MANIPULATION_MENU, PENDANT_MENU


def readout_values(text: str, label: str) -> list[float]:
    """The numbers on the readout line that starts with ``label``."""
    for line in text.splitlines():
        if line.strip().startswith(label):
            return [float(v) for v in line.split()[1:7]]
    raise AssertionError(f"no readout line {label!r} in\n{text}")


@sync
async def test_keyboard_menu_listings(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.press("K")
        text = screen_text(app)
        assert "L_LIST - THEN TYPE LISTP PROG. NAME: VAL-II FILE LISTING" in text
        await pilot.press("L", *"LISTF", "enter")
        assert "PROCESS.DAT" in screen_text(app) and "CONV1.DAT" in screen_text(app)
        await pilot.press("space")
        assert "KEYBOARD MENU" in screen_text(app)
        await pilot.press("L", *"LISTL", "enter")
        assert "PROCESS.LOC" in screen_text(app)
        await pilot.press("space")
        await pilot.press("L", *"LISTP PROCESS", "enter")
        text = screen_text(app)
        assert "PROGRAM PROCESS.DAT" in text and "APPRO A" in text
        await pilot.press("space")
        await pilot.press("L", *"LISTP NOSUCH", "enter")
        assert "NOSUCH" in screen_text(app) and "KEYBOARD MENU" in screen_text(app)
        # LOAD typed at the menu: its L is LIST, and the message says so (not only "OAD")
        await pilot.press(*"LOAD PROCESS", "enter")
        text = " ".join(screen_text(app).split())
        assert "OAD IS NOT LISTP, LISTF OR LISTL (L IS LIST HERE: V FIRST TO TYPE A VAL-II COMMAND)" in text, text


@sync
async def test_keyboard_position_and_switches(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.press("K")
        for line in KEYBOARD_MENU.splitlines():
            assert line in screen_text(app)
        await pilot.press("P", "1")
        text = screen_text(app)
        assert "XW" in text and "JT 1" in text and "POSITION 1: TCS ORIGIN" in text
        assert readout_values(text, "NOFLIP") == [0.0, -90.0, 90.0, 0.0, 0.0, 0.0]
        assert readout_values(text, app.session.simulator.where().config["arm"])[:3] == [0.0, 158.75, 990.6]
        await pilot.press("S")
        assert app.session.simulator.collision_checks and "COLLISION CHECKS ON" in screen_text(app)
        await pilot.press("F")
        assert app.back_faces and app.screen.model_view.back_faces
        assert "HIDDEN SURFACES NOT REMOVED" in screen_text(app)
        await pilot.press("A")
        assert app.axes and "COORDINATE FRAMES ON" in screen_text(app)
        await pilot.press("R")
        assert isinstance(app.screen, MainMenuScreen)
        assert app.screen.model_view.back_faces and app.screen.model_view.axes  # kept for every view


@sync
async def test_keyboard_orient_changes_the_view_not_the_world(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(120, 40)) as pilot:
        before = app.session.simulator.cell.objects[0].vertices.copy()
        key0 = app.view_transform.key()
        await pilot.press("K", "O")
        assert "ORIENT1" in screen_text(app)
        await pilot.press("x", "+", "left")
        assert app.view_transform.key() != key0
        assert app.view_transform.scale > 1.0
        assert (app.session.simulator.cell.objects[0].vertices == before).all()
        await pilot.press("h")
        await pilot.press("R")
        assert isinstance(app.screen, KeyboardScreen)
        assert "KEYBOARD MENU" in screen_text(app)
        await pilot.press("O", "q")  # no ORIENT1 key: said; ESC back to the KEYBOARD MENU, not MAIN
        assert "ORIENT1: + - ARROWS X Y Z H OR R" in screen_text(app)
        await pilot.press("escape")
        assert isinstance(app.screen, KeyboardScreen) and "KEYBOARD MENU" in screen_text(app)


@sync
async def test_keyboard_val_command(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.press("K", "V", *"DRIVE 1,30,100", "enter")
        await pilot.pause()
        assert round(app.session.simulator.joints[0], 6) == 30.0
        await pilot.press("P", "1")
        assert readout_values(screen_text(app), "NOFLIP")[0] == 30.0


@sync
async def test_pendant_jogging_changes_the_readout(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.press("P")
        text = screen_text(app)
        for line in PENDANT_MENU.splitlines():
            assert line in text
        assert readout_values(text, "NOFLIP")[0] == 0.0
        await pilot.press("1")
        await pilot.pause()
        assert readout_values(screen_text(app), "NOFLIP")[0] == 8.0
        await pilot.press("I", "1")
        await pilot.pause()
        assert readout_values(screen_text(app), "NOFLIP")[0] == 24.0
        assert "INCREMENT +16.00 DEG" in screen_text(app)
        await pilot.press("N", "2")
        await pilot.pause()
        assert readout_values(screen_text(app), "NOFLIP")[1] == -106.0
        await pilot.press("C")
        await pilot.pause()
        assert "CLOSED" in screen_text(app) and app.session.simulator.clamp_closed
        await pilot.press("O")
        await pilot.pause()
        assert "OPENED" in screen_text(app)


@sync
async def test_pendant_world_move_at_ready_is_refused(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.press("P", "W", "X")
        await pilot.pause()
        text = screen_text(app)
        assert "MOTION REFUSED" in text
        assert "REACH" in text or "SINGULARITY" in text
        assert list(app.session.simulator.joints) == [0.0, -90.0, 90.0, 0.0, 0.0, 0.0]


@sync
async def test_pendant_narrow_shows_the_model_when_it_moves(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.press("P")
        assert "PENDANT MODE" in screen_text(app)
        await pilot.press("3")
        await pilot.pause()
        assert app.screen.model_shown
        assert readout_values(screen_text(app), "NOFLIP")[2] == 98.0
        await pilot.press("M")
        assert "PENDANT MODE" in screen_text(app)


@sync
async def test_manipulation_keyboard_moves_part_up_and_saves(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.press("M")
        assert "ENTER PART NUMBER TO BE MOVED" in screen_text(app)
        await pilot.press("1", "enter")
        assert "I_NCREMENTS" in screen_text(app) and "K_EYBOARD" in screen_text(app)
        await pilot.press("K")
        text = screen_text(app)
        for line in MANIPULATION_MENU.splitlines():
            assert line in text
        assert "WORLD COORDINATES FOR PART NO. 1" in text
        reference = app.session.simulator.cell.objects[0].reference.copy()
        await pilot.press("U")
        text = screen_text(app)
        lines = text.splitlines()
        world = next(i for i, line in enumerate(lines) if "WORLD COORDINATES FOR PART NO. 1" in line)
        xw, yw, zw = (float(v) for v in lines[world + 1].split())
        assert (xw, yw, zw) == (round(reference[0], 2), round(reference[1], 2), round(reference[2] + 5.0, 2))
        x, y, z = (float(v) for v in lines[world + 3].split())
        assert (x, y, z) == (yw, round(zw + 26.0, 2), xw)
        await pilot.press("F", "R")
        moved = app.session.simulator.cell.objects[0].reference
        assert list(moved - reference) == [5.0, 5.0, 5.0]
        await pilot.press("S")
        assert "MOVE ANOTHER PART" in screen_text(app)
        await pilot.press("N", "Y")
        assert "ENTER SET-UP FILE NAME" in screen_text(app)
        await pilot.press(*"TOO_LONG_NAME", "enter")
        assert "NOT A VALID NAME" in screen_text(app)
        await pilot.press(*"NEWCELL", "enter")
        await pilot.pause()
        assert isinstance(app.screen, MainMenuScreen)
    assert (tmp_path / "NEWCELL.SET").is_file()
    assert app.session.setup_name == "NEWCELL"


@sync
async def test_manipulation_increments_dialogue(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(80, 24)) as pilot:
        reference = app.session.simulator.cell.objects[1].reference.copy()
        await pilot.press("M", "2", "enter", "I")
        assert "COORDINATE AXES DISPLAY ON" in screen_text(app)
        await pilot.press("Y")
        assert app.axes
        await pilot.press("Y", *"0,0,300", "enter")  # screen Z = world X
        await pilot.press("N")  # no rotation: done with this part (Table C-1)
        assert "MOVE ANOTHER PART" in screen_text(app)
        await pilot.press("N")  # no other part
        assert "SAVE THE NEW SET-UP FILE" in screen_text(app)
        await pilot.press("N")
        await pilot.pause()
        assert isinstance(app.screen, MainMenuScreen)
        moved = app.session.simulator.cell.objects[1].reference
        assert list(moved - reference) == [300.0, 0.0, 0.0]


@sync
async def test_motion_is_paced_by_the_clock_and_ctrl_c_aborts(tmp_path: Path) -> None:
    clock = FakeClock()
    app = make_app(tmp_path, rate=10.0, clock=clock)
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.press("K")
        simulator = app.session.simulator
        seconds = joint_motion_seconds(simulator.joints, [60.0, *simulator.joints[1:]], simulator.speed)
        app.run_events(simulator.drive(1, 60.0))  # 5 steps of 12 degrees, in the real PUMA's time
        await pilot.pause()
        assert app.moving and round(simulator.joints[0]) == 12
        clock.t += 2 * seconds / 5 + 1e-6  # the third pose is due (the first shows at once)
        await pilot.pause(0.15)  # the driver's timer polls the clock every 0.1 s
        assert round(simulator.joints[0]) == 36
        await pilot.press("ctrl+c")
        assert not app.moving
        await pilot.pause()
        assert "ABORTED" in screen_text(app)
        assert round(simulator.joints[0]) == 36
        app.run_events(simulator.ready())
        clock.t += 100.0
        await pilot.pause(0.15)
        assert not app.moving and round(simulator.joints[0]) == 0


@sync
async def test_manipulation_another_part_goes_on_with_increments(tmp_path: Path) -> None:
    """Table C-1's part transfer: part 1 up 300 and turned, then part 2, then save."""
    app = make_app(tmp_path)
    async with app.run_test(size=(80, 24)) as pilot:
        cell = app.session.simulator.cell
        first, second = cell.objects[0].reference.copy(), cell.objects[1].reference.copy()
        await pilot.press("M", "1", "enter", "I", "Y")
        await pilot.press("Y", *"0,0,300", "enter", "Y", *"0,0,45", "enter")
        assert "CONTINUE MOVING PART 1" in screen_text(app)  # asked after a rotation
        await pilot.press("N", "Y", "2", "enter")
        assert "TRANSLATE THE PART" in screen_text(app)
        await pilot.press("Y", *"0,0,-200", "enter", "N")  # no rotation: done with part 2
        await pilot.press("N", "Y", *"TEST", "enter")  # no other part; save as TEST
        await pilot.pause()
        assert isinstance(app.screen, MainMenuScreen)
        assert list(cell.objects[1].reference - second) == [-200.0, 0.0, 0.0]
        assert cell.objects[0].reference[0] != first[0]
    assert (tmp_path / "TEST.SET").is_file()
