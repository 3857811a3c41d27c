"""A motion's collision checks worked out for its whole path at once (issue 25, round 7).

``Simulator._play`` checks a path's poses and steps together at its first checked pose and
says each pose's findings as the pose is shown. The reference is the pose-by-pose way every
other caller uses: ``check_collisions(previous)`` after each pose. The events must be the
same, in the same order, with a carried part, a stop on collision, a pause of the checks,
a motion dropped half way and a robot file's robot.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
import pytest

from valterm.bench.collision import _poses, dense_cell, move_program
from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.cell.workcell import WorkCell
from valterm.core.collision.frames import RobotScene
from valterm.core.events import Collision, Event, Motion, Near, PoseEvent
from valterm.core.motion import MotionRefused
from valterm.core.simulator import Simulator


class PoseByPose(Simulator):
    """The simulator as it played paths before: each pose checked on its own."""

    def _play(self, path: np.ndarray, kind: str) -> Iterator[Event]:
        steps = len(path)
        for index, pose in enumerate(path, start=1):
            previous = self.joints
            self.stand_at(self._settled(pose))
            self._follow_clamp()
            yield PoseEvent(tuple(self.joints), index, steps)
            if self.collision_checks:
                for finding in self.check_collisions(previous):
                    yield finding
                    if self.stop_on_collision and isinstance(finding, Collision):
                        raise MotionRefused(f"stopped on collision: {finding.text}", 0, index)
        yield Motion(kind, steps, tuple(round(j, 6) for j in self.joints), 0.0)


def _said(sim: Simulator, moves: int, seed: int = 25, pause: bool = False) -> list[str]:
    """The text of every pose and finding of ``moves`` MOVEs over the dense cell's tables."""
    goals = move_program(moves, seed=seed)
    stops = np.array(sim.arm.stops)
    goals = np.clip(goals, stops[:, 0] + 5.0, stops[:, 1] - 5.0)
    sim.stand_at([float(v) for v in goals[0]])
    out: list[str] = []
    for n, goal in enumerate(goals[1:]):
        try:
            for index, event in enumerate(sim.move_joints(goal)):
                if isinstance(event, PoseEvent):
                    out.append(f"pose {np.round(event.joints, 9).tolist()}")
                    if pause and n % 3 == 1:
                        sim.collision_checks = index % 4 != 2      # off for a pose now and then
                elif isinstance(event, (Collision, Near)):
                    out.append(event.text)
        except MotionRefused as refused:
            out.append(f"refused {refused}")
    return out


def _cell_with_a_part_in_hand(sim: Simulator) -> None:
    frame = sim.model.clamp_frame(sim.joints, sim.base)
    z = sim.geometry.d6 + sim.geometry.led_sensor
    box = Polyhedron.box(np.array([-15.0, -20.0, z - 20.0]), np.array([15.0, 20.0, z + 30.0]), "H")
    sim.cell.objects.append(box.transformed(frame[:3, :3], frame[:3, 3]))
    list(sim.close())


def _pair(robot: str | None = None, parts: int = 30) -> tuple[Simulator, Simulator]:
    sims = tuple(cls(WorkCell(objects=list(dense_cell(parts))), robot=robot) for cls in (Simulator, PoseByPose))
    for sim in sims:
        sim.collision_checks = True
    return sims  # type: ignore[return-value]


def test_a_path_checked_at_once_says_what_the_pose_by_pose_check_says():
    batched, reference = _pair()
    said = _said(batched, 150)
    assert said == _said(reference, 150)
    assert sum(" COLLIDES WITH " in s for s in said) >= 10       # the cell is met, between poses too
    assert sum(" IS NEAR " in s for s in said) > 100


def test_the_same_with_a_part_carried_and_the_robot_stopping_at_a_collision():
    batched, reference = _pair()
    for sim in (batched, reference):
        sim.stand_at([float(v) for v in move_program(1)[0]])
        _cell_with_a_part_in_hand(sim)
        assert sim.carried is not None
        sim.stop_on_collision = True
    said = _said(batched, 40, seed=7)
    assert said == _said(reference, 40, seed=7)
    assert any(s.startswith("refused stopped on collision") for s in said)
    # the carried part rode the clamp to the last pose shown
    assert np.allclose(batched.cell.objects[batched.carried - 1].vertices,
                       reference.cell.objects[reference.carried - 1].vertices)


def test_the_same_when_the_checks_pause_within_a_path():
    batched, reference = _pair()
    assert _said(batched, 30, seed=3, pause=True) == _said(reference, 30, seed=3, pause=True)


def test_a_motion_dropped_half_way_leaves_the_next_step_starting_where_it_stopped():
    batched, reference = _pair()
    goals = move_program(12, seed=11)
    out: dict[Simulator, list[str]] = {batched: [], reference: []}
    for sim in (batched, reference):
        sim.stand_at([float(v) for v in goals[0]])
        for n, goal in enumerate(goals[1:]):
            motion = sim.move_joints(goal)
            for index, event in enumerate(motion):
                if isinstance(event, (Collision, Near)):
                    out[sim].append(event.text)
                elif isinstance(event, PoseEvent):
                    out[sim].append(str(event.joints))
                if n % 2 and index == 4:
                    motion.close()                       # the user stopped the motion
                    break
            # the next step starts from the last pose checked: its name and box gaps kept as the
            # pose check left them
            ends = sim._collision_scene()._ends
            assert ends is not None
            out[sim].append(str(ends[0][:6]) + str(np.round(ends[3], 9).tolist()))
    assert out[batched] == out[reference]
    assert batched.joints == reference.joints


@pytest.mark.parametrize("parts", [100])
def test_the_same_where_the_broad_phase_picks_the_pairs(parts: int):
    batched, reference = _pair(parts=parts)
    assert _said(batched, 15, seed=5) == _said(reference, 15, seed=5)


@pytest.mark.slow  # CI runs it (pytest -m slow); the default run stays under 5 minutes
def test_the_same_on_a_robot_files_robot():
    batched, reference = _pair("PUMA560")
    said = _said(batched, 30, seed=9)
    assert said == _said(reference, 30, seed=9)
    assert any(" COLLIDES WITH " in s for s in said)


def test_only_moments_whose_boxes_meet_can_collide():
    """``RobotScene.meeting`` passes every moment where the pose check finds a collision."""
    sim = Simulator(WorkCell(objects=list(dense_cell(30))))
    scene: RobotScene = sim._collision_scene()
    rng = np.random.default_rng(4)
    goals = move_program(40, seed=13)
    sim.stand_at([float(v) for v in goals[0]])
    list(sim.check_collisions())
    pairs = scene._pairs_now
    assert pairs is not None
    joints = np.asarray(_poses(goals, sim))
    joints += rng.normal(0.0, 15.0, joints.shape)     # about the poses a path shows
    frames = sim.model.link_frames_batch(joints, sim.base)
    rows = np.ones((len(joints), len(pairs.moving)), dtype=bool)
    meet = scene.meeting(frames, rows, None)
    hits = 0
    for k, at in enumerate(frames):
        found = scene.collisions_between(at, sim.cell.objects, np.arange(len(pairs.moving)))
        hits += bool(found)
        assert meet[k] or not found
    assert hits > 20 and meet.sum() < len(meet) / 2    # most moments need no check


@pytest.mark.parametrize(("robot", "near"), [(None, 50), ("PUMA560", 0)])
def test_a_paths_poses_checked_together_are_checked_as_one_by_one(robot: str | None, near: int):
    """``RobotScene.keep_path``: the findings, box gaps and centres of a path's poses worked out
    together are those of ``check`` and ``keep_pose`` pose by pose, bit for bit, the fine
    test's poses (a near pair's boxes meet) included: their fine tests run together too."""
    sim = Simulator(WorkCell(objects=list(dense_cell(30))), robot=robot)
    scene: RobotScene = sim._collision_scene()
    joints = np.asarray(_poses(move_program(120, seed=21), sim))
    frames = sim.model.link_frames_batch(joints, sim.base)
    objects, length = sim.cell.objects, 13
    fined = said = 0
    for start in range(0, len(joints) - length, length):
        path = frames[start: start + length]
        scene.check(path[0], objects)
        together = scene.path_figures(length, "before")
        alone = scene.path_figures(length, "before")
        assert together is not None and alone is not None
        scene.keep_pose(together, path[0], 0)
        told = scene.keep_path(together, path[1:], list(range(1, length)), 100.0)
        assert told is not None and len(told) == length - 1
        for k, at in enumerate(path):
            found = scene.check(at, objects)
            scene.keep_pose(alone, at, k)
            if k:
                assert told[k - 1] == found
                said += bool(found)
                fined += scene._gaps_now is not None and bool((scene._gaps_now <= 0).any())
        assert np.array_equal(together.gaps, alone.gaps)
        assert np.array_equal(together.centres, alone.centres)
        assert together.keys == alone.keys and len(together.tables) == len(alone.tables)
        assert all(np.array_equal(a, b) for a, b in zip(together.tables, alone.tables))
    # near poses told at once, the fine test's among them (the PUMA 560's links touch each
    # other's boxes at every pose: every pose is the fine test's)
    assert said >= near and fined > 0


def test_a_path_with_a_part_carried_is_checked_pose_by_pose():
    sim = Simulator(WorkCell(objects=list(dense_cell(30))))
    sim.stand_at([float(v) for v in move_program(1)[0]])
    _cell_with_a_part_in_hand(sim)
    scene: RobotScene = sim._collision_scene()
    frames = sim.model.link_frames_batch(np.asarray([sim.joints] * 3), sim.base)
    scene.check(frames[0], sim.cell.objects, (sim.carried,))
    figures = scene.path_figures(3, None)
    assert figures is not None
    scene.keep_pose(figures, frames[0], 0)
    assert scene.keep_path(figures, frames[1:], [1, 2], 100.0) is None     # the part moves with the hand


def test_a_part_moved_between_motions_is_checked_where_it_is_now():
    """A part moved between two motions (its vertices replaced, the same object): the next
    path's checks see it where it is now (``RobotScene.path_ready`` finds the parts changed)."""
    batched, reference = _pair()
    goals = move_program(24, seed=17)
    out: dict[Simulator, list[str]] = {batched: [], reference: []}
    for sim in (batched, reference):
        sim.stand_at([float(v) for v in goals[0]])
        for n, goal in enumerate(goals[1:]):
            for event in sim.move_joints(goal):
                if isinstance(event, (Collision, Near)):
                    out[sim].append(event.text)
            # a part slid under where the hand is now: met on the way back
            tool = sim.tool_pose()[0]
            part = sim.cell.object(1 + n % len(sim.cell.objects))
            sim.move_part(_part_number(sim, part), tool - part.vertices.mean(axis=0) + [0.0, 0.0, -40.0])
            out[sim].append(f"moved {part.name}")
    assert out[batched] == out[reference]
    assert sum(" COLLIDES WITH " in s for s in out[batched]) >= 5


def _part_number(sim: Simulator, part: Polyhedron) -> int:
    return next(n for n, p in enumerate(sim.cell.objects, start=1) if p is part)
