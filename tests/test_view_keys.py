"""The view keys on every screen that shows the model, the follow-the-clamp view, and the
playback at the real PUMA's pace (issue 12)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from app_helpers import FakeClock, make_app, screen_text, sync, until
from valterm.core.events import Motion
from valterm.core.render import views
from valterm.core.render.legend import LED_COLOUR, SEEN_COLOUR, TRACE_COLOUR
from valterm.core.session import Session
from valterm.ui.screens.main_menu import MainMenuScreen
from valterm.ui.screens.manipulation import ManipulationScreen
from valterm.ui.screens.pendant import PendantScreen
from valterm.ui.screens.valmode import ValModeScreen
from valterm.ui.view.model_view import ModelView

# keys that bring each screen up from MAIN MENU, and the screen
SCREENS = [
    ((), MainMenuScreen),
    (("P",), PendantScreen),
    (("M", "1", "enter"), ManipulationScreen),  # waits for I, K or R: the arrows still turn
    (("V",), ValModeScreen),
]


@pytest.mark.parametrize("keys, screen_type", SCREENS, ids=["main", "pendant", "manipulation", "valmode"])
@sync
async def test_arrows_turn_the_view_and_never_the_world(tmp_path: Path, keys, screen_type) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.press(*keys)
        await pilot.pause()
        assert isinstance(app.screen, screen_type)
        view = app.screen.query_one(ModelView)
        assert views.angles(app.view_transform) == pytest.approx(views.preset_angles("iso"))
        world = [o.vertices.copy() for o in app.session.simulator.cell.objects]
        joints = app.session.simulator.joints
        before = view.frame.text()
        await pilot.press("right", "up")
        await pilot.pause()
        az, el = views.preset_angles("iso")
        assert views.angles(app.view_transform) == pytest.approx((az + 15, el + 15))
        assert view.view is app.view_transform and view.frame.text() != before
        await pilot.press("plus")
        assert app.view_transform.scale == pytest.approx(views.ZOOM_STEP)
        await pilot.press("greater_than_sign")  # (VAL-II mode's F-keys are its own: F6 is its menu)
        assert app.player.factor == 0.5
        assert view.caption == f"AZ {az + 15:.0f} EL {el + 15:.0f}  TIME x0.5"
        assert screen_text(app).count("TIME x0.5") >= 1  # the status line on the screen
        if screen_type is ValModeScreen:
            return  # F2 there wipes the log (docs/VALMODE_KEYS.md); the presets are tested elsewhere
        await pilot.press("f2")  # a turned view -> iso, then side: the thesis's view
        assert views.angles(app.view_transform) == pytest.approx((az, el))
        await pilot.press("f2")
        assert views.angles(app.view_transform) == pytest.approx((0.0, 0.0))
        await pilot.press("plus", "f3")  # the whole cell again, still from the side
        assert app.view_transform.scale == 1.0 and views.angles(app.view_transform) == pytest.approx((0.0, 0.0))
        await pilot.press("f5")
        assert not app.show_trace
        assert isinstance(app.screen, screen_type)  # no key reached the screen's menu
        assert all(np.array_equal(a.vertices, b) for a, b in zip(app.session.simulator.cell.objects, world))
        assert app.session.simulator.joints == joints


@sync
async def test_orient_keeps_its_arrows(tmp_path: Path) -> None:
    """KEYBOARD -> ORIENT: the arrows pan, as the thesis has it (the view keys wait)."""
    app = make_app(tmp_path)
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.press("K", "O")
        angles = views.angles(app.view_transform)
        await pilot.press("right")
        assert views.angles(app.view_transform) == pytest.approx(angles)
        assert app.view_transform.pan[0] > 0


def _cells(frame, colour: int) -> np.ndarray:  # type: ignore[no-untyped-def]
    return np.argwhere(frame.colours == colour)


@sync
async def test_follow_the_clamp_shows_whether_the_led_line_crosses_the_part(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(160, 50)) as pilot:
        sim = app.session.simulator
        app.session.load_locations("PROCESS")
        for command in ("LEFTY", "MOVE A"):  # A: the clamp around part 1 (PROCESS.DAT)
            app.run_events(app.session.command(command))
            app.skip_motion()
        await pilot.press("f4")
        await pilot.pause()
        assert app.follow_clamp and sim.led_part() == 1
        frame = app.screen.query_one(ModelView).frame
        seen, led = _cells(frame, SEEN_COLOUR), _cells(frame, LED_COLOUR)
        assert len(seen) > 10 and len(led) > 0  # the part is big in the picture: zoomed on it
        # the LED line (across the finger gap) runs through the part's rows and columns
        middle = led.mean(axis=0)
        assert (seen.min(axis=0) <= middle).all() and (middle <= seen.max(axis=0)).all()

        app.run_events(app.session.command("DEPART 150"))
        app.skip_motion()
        await pilot.pause()
        frame = app.screen.query_one(ModelView).frame
        assert sim.led_part() is None and not len(_cells(frame, SEEN_COLOUR))  # nothing seen
        led = _cells(frame, LED_COLOUR)
        part_rows = _cells(frame, 16)[:, 0]  # part 1's own colour again
        assert len(led) and led[:, 0].max() < part_rows.min()  # the line is above the part
        assert (frame.colours == TRACE_COLOUR).any()  # and the clamp's path shows the way up


async def _motion_seconds(command: str, factor: float, tmp_path: Path) -> tuple[float, float]:
    """Play ``command`` on the test's clock; (seconds it took, the cycle-time estimate)."""
    estimate = Session(workspace_root=tmp_path / "probe")
    estimate.load_locations("PROCESS")
    expected = sum(e.seconds for e in estimate.command(command) if isinstance(e, Motion))
    clock = FakeClock()
    app = make_app(tmp_path / "ws", rate=10.0, clock=clock)
    async with app.run_test(size=(80, 24)) as pilot:
        app.session.load_locations("PROCESS")
        app.player.set_factor(factor)
        start = clock.t
        app.run_events(app.session.command(command))
        step = 0.05  # the test's frame
        for _ in range(400):
            if not app.player.playing:
                break
            clock.t += step
            ticks = app.player.ticks
            # the next tick sees the new time (bounded in real time: 100 looks of 5 ms were
            # not always a tick on a loaded machine, and two steps then made one)
            await until(pilot, lambda seen=ticks: app.player.ticks > seen or not app.player.playing,
                        "the next tick")
        assert not app.player.playing
        return clock.t - start, expected


@pytest.mark.parametrize("factor", [1.0, 0.25])
@sync
async def test_a_move_lasts_the_real_robots_time_times_the_factor(tmp_path: Path, factor: float) -> None:
    took, expected = await _motion_seconds("MOVE B", factor, tmp_path)
    assert expected > 0.3
    assert expected * factor <= took <= expected * factor + 0.05 + 1e-9  # within a frame


def test_the_playback_factor_steps_through_x0_25_to_x8(tmp_path: Path) -> None:
    from valterm.ui.playback import FACTORS, Player

    player = Player(None, clock=FakeClock())  # type: ignore[arg-type]
    assert player.factor == 1.0
    assert [player.change_factor(1) for _ in range(4)] == [2.0, 4.0, 8.0, 8.0]
    assert [player.change_factor(-1) for _ in range(6)] == [4.0, 2.0, 1.0, 0.5, 0.25, 0.25]
    assert FACTORS[0] == 0.25 and FACTORS[-1] == 8.0
    with pytest.raises(ValueError):
        player.set_factor(math.inf)


@sync
async def test_on_the_val_ii_command_line_printable_keys_type_and_f_keys_turn(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.press("V", "V")  # VAL-II mode, then its command line
        await pilot.pause()
        line = app.screen.query_one("#val-line")
        assert line.has_focus
        az, el = views.preset_angles("iso")
        await pilot.press("plus", "minus", "left", "up")
        assert line.value == "+-" and app.view_transform.scale == 1.0  # typed, not zoomed
        assert views.angles(app.view_transform) == pytest.approx((az, el + 15))  # LEFT: the cursor
        await pilot.press("pageup")
        assert app.view_transform.scale == pytest.approx(views.ZOOM_STEP)  # PAGE UP zoomed
        assert views.angles(app.view_transform) == pytest.approx((az, el + 15))  # UP turned it
