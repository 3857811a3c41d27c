"""The Simulator: motions that yield poses, the hand, BASE, locations, pendant, manipulation."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from valterm.core.events import Grasp, Hand, Message, Motion, PoseEvent, Release
from valterm.core.files.locations import read_locations
from valterm.core.files.setup import read_setup
from valterm.core.kinematics import Location, fk
from valterm.core.motion import MotionRefused
from valterm.core.simulator import GRASP_MESSAGE, Simulator, UndefinedLocation

ROOT = Path(__file__).resolve().parent.parent  # the repository: the bundled data (cells/, programs/)
@pytest.fixture
def process() -> Simulator:
    sim = Simulator(read_setup(ROOT / "cells" / "PROCESS.SET"))
    sim.locations.update(read_locations(ROOT / "programs" / "PROCESS.LOC"))
    return sim


def drain(events) -> list:  # type: ignore[no-untyped-def]
    return list(events)


def test_every_intermediate_pose_is_yielded_then_the_motion(process: Simulator) -> None:
    process.set_indicator("LEFTY")
    events = drain(process.move("A"))
    poses = [e for e in events if isinstance(e, PoseEvent)]
    assert isinstance(events[-1], Motion) and events[-1].steps == len(poses) > 1
    assert [p.index for p in poses] == list(range(1, len(poses) + 1))
    assert process.where().xyz == pytest.approx((465.0, -45.0, -245.0), abs=1e-6)


def test_the_process_case_study_moves_both_parts(process: Simulator) -> None:
    sim = process
    drain(sim.ready())
    sim.set_indicator("LEFTY")
    sim.set_indicator("ABOVE")
    drain(sim.appro("A", -50))
    drain(sim.move("A"))
    events = drain(sim.close(immediate=True))
    assert [type(e) for e in events] == [Message, Grasp, Hand]
    assert events[0].text == GRASP_MESSAGE and events[1].part == 1
    part1_before = sim.cell.objects[0].vertices.copy()
    drain(sim.depart(100, straight=True))
    # the carried part follows the clamp exactly: DEPARTS keeps the orientation, so every
    # vertex moved by the same vector
    moved = sim.cell.objects[0].vertices - part1_before
    assert np.allclose(moved, moved[0])
    assert sim.cell.objects[0].vertices[:, 2].min() > part1_before[:, 2].min() + 90
    for step in (sim.move("E", True), sim.move("F", True), sim.depart(200, True),
                 sim.appro("C", -50, True), sim.move("C", True)):
        drain(step)
    released = [e for e in drain(sim.open(immediate=True)) if isinstance(e, Release)]
    assert released[0].part == 1
    corner = np.array(released[0].position)
    assert np.allclose(corner, sim.cell.objects[0].reference)
    # part 1 now stands on the left-hand table (top Z = -280) under C
    assert sim.cell.objects[0].vertices[:, 2].min() == pytest.approx(-280, abs=2)
    assert np.linalg.norm(sim.cell.objects[0].centre[:2] - np.array([-180, 600])) < 40
    # part 1 no longer moves with the clamp
    before = sim.cell.objects[0].vertices.copy()
    drain(sim.depart(100, True))
    assert np.array_equal(before, sim.cell.objects[0].vertices)


def test_close_latches_the_lowest_numbered_part_and_not_when_closed(process: Simulator) -> None:
    process.set_indicator("LEFTY")
    drain(process.move("A"))
    assert process.led_part() == 1
    drain(process.close())
    assert process.carried == 1
    assert drain(process.close()) == []  # already closed: nothing latches, nothing said


def test_close_over_nothing_latches_nothing(process: Simulator) -> None:
    events = drain(process.close())
    assert process.carried is None
    assert [type(e) for e in events] == [Hand]


def test_refused_motion_moves_nothing(process: Simulator) -> None:
    process.locations["FAR"] = Location((3000.0, 0.0, 0.0), (0.0, 90.0, 0.0))
    before = process.joints
    with pytest.raises(MotionRefused):
        drain(process.move("FAR"))
    assert process.joints == before
    with pytest.raises(UndefinedLocation, match="NOWHERE"):
        drain(process.move("NOWHERE"))


def test_here_set_shift(process: Simulator) -> None:
    here = process.here("p1")
    assert process.location("P1") == here
    process.set_location("P2", "P1")
    shifted = process.shift("P2", 10, -20, 30)
    assert shifted.xyz == pytest.approx(np.add(here.xyz, (10, -20, 30)))
    assert shifted.oat == here.oat


def test_base_moves_the_robot_not_the_locations(process: Simulator) -> None:
    before = process.where().xyz
    drain(process.set_base(None, None, 300, None))  # BASE ,,300,
    assert process.where().xyz == pytest.approx(np.add(before, (0, 0, 300)))
    process.set_indicator("LEFTY")
    drain(process.move("A"))
    assert process.where().xyz == pytest.approx((465.0, -45.0, -245.0), abs=1e-6)
    drain(process.set_base(0, 0, 0, 90))
    joints = list(process.joints)
    pose = fk(joints)
    assert process.where().xyz == pytest.approx((-pose.xyz[1], pose.xyz[0], pose.xyz[2]), abs=1e-6)


def test_speed_is_clamped_and_sets_the_steps(process: Simulator) -> None:
    assert process.set_speed(500) == 100 and process.set_speed(1) == 10
    process.set_speed(50)
    process.set_indicator("LEFTY")
    slow = drain(process.move("A"))[-1].steps
    drain(process.ready())
    process.set_speed(100)
    process.set_indicator("LEFTY")  # READY made the user's indicators RIGHTY ABOVE NOFLIP
    fast = drain(process.move("A"))[-1].steps
    assert slow == pytest.approx(2 * fast, abs=1)


def test_drive_one_joint(process: Simulator) -> None:
    events = drain(process.drive(1, 30, 100))
    assert events[-1].steps == 3 and process.joints[0] == pytest.approx(30)
    with pytest.raises(MotionRefused, match="joint 1 beyond its stop"):
        drain(process.drive(1, 200, 100))


def test_pendant_joint_increment_and_world_step(process: Simulator) -> None:
    drain(process.pendant_joint(2))
    assert process.joints[1] == pytest.approx(-82)
    assert process.change_pendant_increment("N") == -8
    assert process.change_pendant_increment("I") == -16
    assert process.change_pendant_increment("D") == -8
    drain(process.pendant_joint(2))
    assert process.joints[1] == pytest.approx(-90)
    # at READY the elbow is straight: WORLD moves are refused
    with pytest.raises(MotionRefused):
        drain(process.pendant_world(0))
    process.set_indicator("LEFTY")
    drain(process.move("A"))
    before = process.where().xyz
    process.pendant_increment = 8.0
    drain(process.pendant_world(2))
    assert process.where().xyz == pytest.approx(np.add(before, (0, 0, 10)), abs=1e-6)


def test_manipulation_moves_and_turns_a_part(process: Simulator) -> None:
    part = process.cell.object(1)
    before = part.vertices.copy()
    process.move_part(1, (0.0, 0.0, 5.0))
    assert np.allclose(process.cell.object(1).vertices, before + [0, 0, 5])
    centre = process.cell.object(1).centre.copy()
    process.move_part(1, axis=2, degrees=90)
    assert np.allclose(process.cell.object(1).centre, centre)
    with pytest.raises(IndexError):
        process.cell.object(99)
