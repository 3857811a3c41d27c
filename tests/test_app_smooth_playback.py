"""Smooth playback (issue 25): the app draws poses between a motion's own poses, each joint
along its shortest turn, while the simulator, the verdicts and the transcript stay those of
the motion's poses (the same lines as ``valterm run``)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from app_helpers import FakeClock, make_app, sync
from test_app_playback import Host, _transcript_of_run, run_until, typed, valmode
from valterm.core.kinematics import joints_between, wrap180
from valterm.core.session import Session
from valterm.ui.app import ValtermApp
from valterm.ui.screens.valmode import Mode
from valterm.ui.view.model_view import ModelView


async def next_tick(pilot, app: ValtermApp) -> None:  # type: ignore[no-untyped-def]
    """Until the player's next tick has seen the clock the test moved (or the motion ended):
    a fixed pause held none on a loaded machine, and two steps of the clock made one picture."""
    ticks = app.player.ticks
    await run_until(pilot, lambda: app.player.ticks > ticks or not app.moving)


def test_joints_between_turns_the_short_way() -> None:
    start, end = (179.0, -10.0, 0.0, 90.0, -179.5, 20.0), (-179.0, 10.0, 0.0, 100.0, 179.5, 20.0)
    assert joints_between(start, end, 0.0) == start
    half = joints_between(start, end, 0.5)
    assert half == pytest.approx((180.0, 0.0, 0.0, 95.0, -180.0, 20.0))  # 2 and 1 degree turns
    end_again = joints_between(start, end, 1.0)
    assert [wrap180(a - b) for a, b in zip(end_again, end)] == pytest.approx([0.0] * 6)


def _nearest_mm(points: np.ndarray, cloud: np.ndarray) -> float:
    """The largest distance from one of ``points`` to the nearest point of ``cloud``."""
    return float(np.sqrt(((points[:, None, :] - cloud[None, :, :]) ** 2).sum(-1)).min(axis=1).max())


@sync
async def test_a_drawn_in_between_pose_lies_between_its_neighbours(tmp_path: Path) -> None:
    clock = FakeClock()
    app = make_app(tmp_path, rate=40.0, clock=clock)
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.press("K")
        simulator = app.session.simulator
        start = tuple(simulator.joints)
        app.run_events(simulator.drive(1, 60.0))  # 5 poses of 12 degrees, in the PUMA's time
        await pilot.pause()
        player = app.player
        motion = player._motion
        assert motion is not None and round(simulator.joints[0]) == 12
        interval = 1.0 / motion.rate
        clock.t += 2.5 * interval  # the third pose (36) due, half way to the fourth
        await pilot.pause(0.1)
        assert round(simulator.joints[0]) == 36  # the simulator is at the motion's own pose
        drawn = player.drawn(simulator.joints)
        # the picture half way from the pose before (24) to the pose shown (36): one step behind
        assert drawn is not None and drawn[0] == pytest.approx(30.0)
        assert drawn[1:] == pytest.approx(start[1:])
        # the picture is the robot at the drawn pose, not at the simulator's
        model = simulator.model
        scene = app.screen.query_one(ModelView).scene
        fingers_drawn = model.place(drawn, simulator.gap, simulator.base)[-1].vertices
        fingers_pose = simulator.robot_polyhedra()[-1].vertices
        assert _nearest_mm(fingers_drawn, scene.vertices) < 1e-6
        assert _nearest_mm(fingers_pose, scene.vertices) > 1.0
        readout = str(app.session.simulator.where().joints[0])
        assert readout.startswith("36")  # WHERE says the pose, not the picture
        clock.t += 10.0
        await run_until(pilot, lambda: not app.moving)
        assert player.drawn(simulator.joints) is None and round(simulator.joints[0]) == 60


@sync
async def test_an_in_between_pose_across_180_degrees_turns_2_degrees(tmp_path: Path) -> None:
    clock = FakeClock()
    app = make_app(tmp_path, rate=40.0, clock=clock)
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.press("K")
        simulator = app.session.simulator
        simulator.stand_at([*simulator.joints[:5], 170.0])
        app.changed()
        await pilot.pause()
        assert app.player.drawn(simulator.joints) is None  # at rest: the simulator's pose
        app.run_events(simulator.drive(6, 20.0))  # 170 -> 190, kept as -170 by the 1985 rules
        await pilot.pause()
        motion = app.player._motion
        assert motion is not None
        seen = []
        for _ in range(40):
            clock.t += 0.25 / motion.rate
            await next_tick(pilot, app)
            drawn = app.player.drawn(simulator.joints)
            if drawn is not None:
                seen.append(drawn[5])
            if not app.moving:
                break
        assert simulator.joints[5] == pytest.approx(-170.0)
        assert len(seen) >= 4
        # every picture's JT6 is on the short arc from 170 through 180 to 190 (-170)
        assert all(169.9 <= value <= 190.1 or -180.0 <= value <= -169.9 for value in seen)


def test_paced_playback_prints_what_run_prints(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """PROCESS played at the real PUMA's pace on a stepped clock, pictures drawn between the
    poses: the same transcript as ``valterm run``, and the robot ends where run leaves it."""
    by_run = _transcript_of_run(tmp_path, capsys)
    session = Session(workspace_root=tmp_path / "app", setup="PROCESS")
    session.load_locations("PROCESS")
    headless = Session(workspace_root=tmp_path / "headless", setup="PROCESS")
    headless.load_locations("PROCESS")
    for _ in headless.interpreter.execute("PROCESS"):
        pass
    clock = FakeClock()
    app = Host(session, motion_rate=40.0, clock=clock)
    seen: list[str] = []
    counts = {"between": 0, "poses": 0}

    async def body() -> None:
        async with app.run_test(size=(120, 40)) as pilot:
            screen = await valmode(app, pilot)
            view = screen.query_one(ModelView)
            await typed(pilot, "EXECUTE PROCESS")
            drawn = app.player.drawn

            def counted(joints):  # type: ignore[no-untyped-def]
                between = drawn(joints)
                counts["between"] += between is not None
                return between

            app.player.drawn = counted  # type: ignore[method-assign]
            before, ticks = view.redraws, app.player.ticks
            for _ in range(50_000):
                if screen.mode == Mode.COMMAND:
                    break
                if app.player.ticks != ticks:  # the player saw the last step of the clock
                    clock.t += 0.05
                    ticks = app.player.ticks
                await pilot.pause(0.005)
            assert screen.mode == Mode.COMMAND
            counts["poses"] = view.redraws - before
            seen.extend(screen.transcript)

    sync(body)()
    assert seen[1:] == by_run
    assert session.simulator.joints == headless.simulator.joints
    assert counts["between"] > 100 and counts["poses"] > 181  # PROCESS has 181 poses


@sync
async def test_in_between_pictures_redraw_the_model_alone(tmp_path: Path) -> None:
    """A picture between two poses redraws the model view only: the readouts and the status
    line are redrawn once a pose (they say the poses', and each redraw costs a layout)."""
    clock = FakeClock()
    app = make_app(tmp_path, rate=40.0, clock=clock)
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.press("K")
        screen = app.screen
        view = screen.query_one(ModelView)
        counts = {"redraw": 0, "picture": 0}
        redraw, update_scene = screen.redraw, view.update_scene

        def counted_redraw() -> None:
            counts["redraw"] += 1
            redraw()

        def counted_update(scene) -> None:  # type: ignore[no-untyped-def]
            counts["picture"] += 1
            update_scene(scene)

        screen.redraw = counted_redraw  # type: ignore[method-assign]
        view.update_scene = counted_update  # type: ignore[method-assign]
        app.run_events(app.session.simulator.drive(1, 60.0))  # 5 poses
        await pilot.pause()
        motion = app.player._motion
        assert motion is not None
        for _ in range(5 * 8):  # eight looks at the clock a pose
            clock.t += 1.0 / motion.rate / 8
            await next_tick(pilot, app)
        await run_until(pilot, lambda: not app.moving)
        pictures_alone = counts["picture"] - counts["redraw"]
        assert counts["redraw"] <= 5 + 2, counts  # the poses (and the end)
        assert pictures_alone >= 10, counts  # the in-between pictures, each the model alone


@sync
async def test_the_first_picture_starts_where_the_robot_is(tmp_path: Path) -> None:
    """The robot moved without a pose or a redraw (JT1 set to 40): the next motion's first
    in-between picture lies between 40 and its first pose, not between an older picture's."""
    clock = FakeClock()
    app = make_app(tmp_path, rate=40.0, clock=clock)
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.press("K")
        simulator = app.session.simulator
        simulator.stand_at([40.0, *simulator.joints[1:]])  # no redraw: the last picture still shows JT1 at 0
        app.run_events(simulator.drive(1, 24.0))  # poses at 52 and 64
        await pilot.pause()
        motion = app.player._motion
        assert motion is not None and round(simulator.joints[0]) == 52
        clock.t += 0.5 / motion.rate  # half way to the second pose
        await pilot.pause(0.1)
        drawn = app.player.drawn(simulator.joints)
        assert drawn is not None and 40.0 < drawn[0] < 52.0, drawn
        clock.t += 10.0
        await run_until(pilot, lambda: not app.moving)
