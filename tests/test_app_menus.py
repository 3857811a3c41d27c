"""The app's menus driven key by key (Pilot), read back from the screen."""

from __future__ import annotations

from pathlib import Path

from app_helpers import make_app, screen_text, sync

from valterm.ui.screens.keyboard import KeyboardScreen
from valterm.ui.screens.main_menu import MainMenuScreen
from valterm.ui.screens.manipulation import ManipulationScreen
from valterm.ui.screens.pendant import PendantScreen
from valterm.ui.screens.start import StartScreen
from valterm.ui.widgets.menus import MAIN_MENU


@sync
async def test_start_screen_existing_file_goes_to_main_menu(tmp_path: Path) -> None:
    app = make_app(tmp_path, start=True)
    async with app.run_test(size=(80, 24)) as pilot:
        text = screen_text(app)
        assert "C COPYRIGHT Lehigh University, 1985." in text
        assert "I_GES FILE" in text and "E_XISTING FILE" in text
        await pilot.press("E")
        assert "ENTER SET-UP FILE NAME (RETURN: PROCESS):" in screen_text(app)
        await pilot.press("enter")
        await pilot.pause()
        assert isinstance(app.screen, MainMenuScreen)
        assert app.session.setup_name == "PROCESS"
        assert "K_KEYBOARD : TO KEYBOARD (MONITOR) MODE" in screen_text(app)


@sync
async def test_start_screen_reports_a_missing_setup(tmp_path: Path) -> None:
    app = make_app(tmp_path, start=True)
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.press("E", *"NOSUCH", "enter")
        await pilot.pause()
        assert isinstance(app.screen, StartScreen)
        assert "NOSUCH" in screen_text(app)
        await pilot.press("E", *"BAD/NAME", "enter")
        await pilot.pause()
        assert "NOT A VALID NAME" in screen_text(app)


@sync
async def test_start_screen_iges_transfer_errors_are_messages(tmp_path: Path) -> None:
    app = make_app(tmp_path, start=True)
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.press("I", *"NOPART.IGS", "enter")
        await pilot.pause()
        text = screen_text(app)
        assert "DOES NOT EXIST" in text
        assert "CONTINUE THE PART TRANSFER" in text
        await pilot.press("N")
        assert isinstance(app.screen, StartScreen)
        # a CAD file named as a CAD system names it: the answer says where files are read from
        await pilot.press("I", *"solidworks-chassis-wireframe.igs", "enter")
        await pilot.pause()
        said = [line for line, _ in app.screen.messages.lines]
        assert any("IS NOT A VALID NAME" in line for line in said), said
        assert (f"CAD FILES ARE READ FROM THE WORKSPACE {app.session_workspace().root} UNDER A NAME OF "
                "AT MOST 9 LETTERS OR DIGITS (E.G. CHASSIS.IGS); valterm import FILE --out NAME.SET "
                "READS ANY PATH") in said


@sync
async def test_main_menu_text_and_keys(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(120, 40)) as pilot:
        text = screen_text(app)
        for line in MAIN_MENU.splitlines():
            assert line in text
        await pilot.press("K")
        assert isinstance(app.screen, KeyboardScreen)
        await pilot.press("R")
        await pilot.press("P")
        assert isinstance(app.screen, PendantScreen)
        await pilot.press("R")
        await pilot.press("M")
        assert isinstance(app.screen, ManipulationScreen)
        await pilot.press("escape", "escape")
        assert isinstance(app.screen, MainMenuScreen)
        await pilot.press("S")
        assert "ARE YOU SURE" in screen_text(app)
        await pilot.press("N")
        assert isinstance(app.screen, MainMenuScreen)
        await pilot.press("S", "Y")
        await pilot.pause()
    assert app.return_code == 0


@sync
async def test_main_menu_r_toggles_menu_and_model_when_narrow(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(80, 24)) as pilot:
        screen = app.screen
        assert screen.has_class("-narrow")
        assert not screen.query_one("#model").display
        await pilot.press("R")
        assert screen.query_one("#model").display
        assert not screen.query_one("#menu").display
        assert any(0x2800 < ord(c) <= 0x28FF for c in screen_text(app))  # braille on screen
        await pilot.press("R")
        assert screen.query_one("#menu").display


@sync
async def test_main_menu_model_beside_menu_when_wide(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(120, 40)):
        screen = app.screen
        assert screen.has_class("-wide")
        assert screen.query_one("#model").display and screen.query_one("#menu").display
        assert screen.query_one("#model").size.width > 30


@sync
async def test_main_menu_initialize_and_begin(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(80, 24)) as pilot:
        app.session.simulator.stand_at([40.0, *app.session.simulator.joints[1:]])
        await pilot.press("I")
        await pilot.pause()
        assert app.session.simulator.joints[0] == 0.0
        assert "INITIALIZED WITH PROCESS.SET" in screen_text(app)
        await pilot.press("B")
        await pilot.pause()
        assert isinstance(app.screen, StartScreen)


@sync
async def test_hardcopy_writes_svg_and_printout_into_the_workspace(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.press("H")
        await pilot.pause()
        assert "HARDCOPY WRITTEN: HCOPY1.SVG AND HCOPY1.TXT" in screen_text(app)
    svg, txt = tmp_path / "HCOPY1.SVG", tmp_path / "HCOPY1.TXT"
    assert svg.read_text().lstrip().startswith("<svg")
    printout = txt.read_text()
    assert "SETUP FILE PROCESS.SET, 14 PARTS" in printout
    assert "JT 1" in printout and "WORLD COORDINATES FOR PART NO. 14" in printout


@sync
async def test_editor_and_val_keys_open_their_screens_or_say_so(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.press("E")
        await pilot.pause()
        if isinstance(app.screen, MainMenuScreen):
            assert "EDIT MODE IS NOT AVAILABLE YET" in screen_text(app)
        else:
            assert type(app.screen).__name__ == "EditorScreen"


@sync
async def test_generate_asks_before_replacing_polygon_files(tmp_path: Path) -> None:
    """G writes NAME.OBJ and NAME.GLB; when either is there (a mesh read with U_GII may have
    that name) it asks first: N and ESC keep the files, Y replaces them."""
    app = make_app(tmp_path)
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause()
        root = app.session.workspace.root
        await pilot.press("G")
        await pilot.pause()
        obj, glb = root / "PROCESS.OBJ", root / "PROCESS.GLB"
        assert obj.is_file() and glb.is_file()
        obj.write_text("# the user's own mesh\n")
        glb.unlink()
        for answer in ("N", "escape"):
            await pilot.press("G")
            await pilot.pause()
            said = [line for line, _ in app.screen.messages.lines]
            assert "PROCESS.OBJ EXISTS: REPLACE (Y/N) ?" in screen_text(app), said
            await pilot.press(answer)
            await pilot.pause()
            assert "POLYGON FILES KEPT" in [line for line, _ in app.screen.messages.lines]
            assert obj.read_text() == "# the user's own mesh\n" and not glb.exists()
        await pilot.press("G", "Y")
        await pilot.pause()
        assert obj.read_text().startswith("# ") and "the user's own mesh" not in obj.read_text()
        assert glb.is_file()
