"""What the glancing check keeps to cost less (issue 40, its cost) keeps its answers: a pose by
pose step whose poses clear a pair (at least ``d0`` and ``d1`` apart there, ``d0 + d1`` more
than the pair's travel) looks no further, taking ``d0`` from what the step before kept; a
clipped corner is still found in its step that way, and what is kept is never more than the
distance (fcl's)."""

from __future__ import annotations

import fcl
import numpy as np
import pytest

from valterm.bench.collision_scenes import (CellScene, DenseOracle, FclPeer, _diagonal_to, _links_placed, _simulator,
                                            crowded_cell, glancing_cell, valterm_contacts)
from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.cell.workcell import WorkCell
from valterm.core.events import Collision
from valterm.core.simulator import Simulator


def _collisions_pose_by_pose(scene: CellScene) -> list[int]:
    """The steps the simulator says a collision in, each step checked from the pose before."""
    sim = Simulator(WorkCell(objects=list(scene.parts)))
    poses = [[float(v) for v in pose] for pose in scene.poses]
    said = []
    for i in range(1, len(poses)):
        said += [i for event in sim.check_collisions(poses[i - 1], at=poses[i]) if isinstance(event, Collision)]
    return said


@pytest.mark.parametrize("at", [0.13, 0.5, 0.9])
def test_pose_by_pose_a_corner_clipped_between_poses_is_found_in_its_step(at: float) -> None:
    scene, k = glancing_cell(at, 2.7)
    assert _collisions_pose_by_pose(scene)[:1] == [k]


def _wide_corner(at: float, depth: float, side: float = 400.0) -> tuple[CellScene, int]:
    """``glancing_cell`` with a cube wider than a finger moves in a step (``side`` mm): the step
    needs no moments for the part's width, only the glancing check looks between its poses."""
    scene, k = glancing_cell(at, depth)
    sim = _simulator([])
    v = _links_placed(sim, (scene.poses[k - 1] + at * (scene.poses[k] - scene.poses[k - 1]))[None])[0]
    far = v[int(np.hypot(v[:, 0], v[:, 1]).argmax())]
    u = np.array([far[0], far[1], 0.3 * np.hypot(far[0], far[1])])
    u /= np.linalg.norm(u)
    corner = v[int((v @ u).argmax())]
    cube = Polyhedron.box(np.zeros(3), np.full(3, side), "1")
    return CellScene("wide", [cube.transformed(_diagonal_to(u), corner - depth * u)], scene.goals, scene.poses), k


@pytest.mark.parametrize("at", [0.3, 0.7])
def test_pose_by_pose_a_corner_of_a_wide_part_clipped_between_poses_is_found_in_its_step(at: float) -> None:
    """A step the part's width needs no moments in: only the glancing check (``poses_clear``
    first, which must not clear it) finds the corner between its poses."""
    scene, k = _wide_corner(at, 2.7)
    oracle = DenseOracle(scene, 400)
    assert oracle.meets("FINGER", "1", k) and not oracle.meets("FINGER", "1", k - 1)
    assert FclPeer(scene).per_pose() == {}
    assert _collisions_pose_by_pose(scene)[:1] == [k]
    assert valterm_contacts(scene)[0] == {("FINGER", "1"): k}          # and as a program's path


def test_what_a_pose_by_pose_step_keeps_of_how_far_apart_is_never_more_than_the_distance() -> None:
    """The distances kept for the next step (measured, the pose's fine test's face planes, or the
    step before's less the pair's travel) against fcl's, on the crowded cell's first 120 poses."""
    scene = crowded_cell(30)
    peer = FclPeer(scene)
    sim = Simulator(WorkCell(objects=list(scene.parts)))
    robot = sim._collision_scene()
    poses = [[float(v) for v in pose] for pose in scene.poses[:120]]
    kept = 0
    for i in range(1, len(poses)):
        list(sim.check_collisions(poses[i - 1], at=poses[i]))
        now = robot.apart_kept().get(sim._pose_key(poses[i]), {})
        pairs, nl = robot._pairs_now, len(robot._link_ks)
        assert pairs is not None
        frames = sim._frames_at(poses[i])
        for pair, apart in now.items():
            link, part = int(pairs.moving[pair]), int(pairs.stationary[pair]) - nl
            rot, shift = frames[robot.owners[link], :3, :3], frames[robot.owners[link], :3, 3]
            obj = fcl.CollisionObject(peer.geoms[link], fcl.Transform(rot, rot @ peer.local_centres[link] + shift))
            true = fcl.distance(obj, peer.parts[part], fcl.DistanceRequest(), fcl.DistanceResult())
            assert apart <= max(true, 0.0) + 1e-6, (i, link, part, apart, true)
            kept += 1
    assert kept >= 50
