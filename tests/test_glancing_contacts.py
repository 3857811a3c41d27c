"""A link's corner that clips a part between two poses and leaves it before the next is found
in that step (issue 40 item 3): the swept check's moments are close enough that no point of a
link moves more than ``GLANCE`` mm past a part between two of them, so a contact deeper than
half of that is never missed. The path sampled finely (``DenseOracle``) says where it is."""

from __future__ import annotations

import fcl
import numpy as np
import pytest

from valterm.bench.collision_scenes import (CellScene, DenseOracle, FclPeer, _between, _links_placed, _simulator,
                                            crowded_cell, glancing_cell, valterm_contacts)
from valterm.core.cell.workcell import WorkCell
from valterm.core.collision.glance import GLANCE
from valterm.core.simulator import Simulator


def _deepest(scene: CellScene, k: int) -> float:
    """How deep the arm's vertices go into the cube on the way to pose ``k`` (mm, the path
    sampled 400 times): a vertex's depth, the distance to the nearest face from inside,
    never more than the depth the pair would have to be moved apart by."""
    cube = scene.parts[0].vertices
    lo = cube[0]
    edges = np.array([cube[i] - lo for i in range(1, len(cube))])
    axes = edges[np.argsort(np.linalg.norm(edges, axis=1))[:3]]
    side = np.linalg.norm(axes, axis=1)
    placed = _links_placed(_simulator([]), _between(scene.poses[k - 1: k + 1], 400))
    along = (placed - lo) @ (axes / side[:, None]).T                  # (samples, vertices, 3)
    inside = np.minimum(along, side - along).min(axis=2)
    return float(inside.max())


@pytest.mark.parametrize("at", [0.13, 0.37, 0.5, 0.71, 0.9])
def test_a_corner_clipped_between_poses_is_found_in_its_step(at: float) -> None:
    scene, k = glancing_cell(at, 2.7)
    oracle = DenseOracle(scene, 400)
    assert oracle.meets("FINGER", "1", k) and not oracle.meets("FINGER", "1", k - 1)
    assert FclPeer(scene).per_pose() == {}                       # at no pose
    assert GLANCE / 2.0 < _deepest(scene, k) < 2.7
    ours, _ = valterm_contacts(scene)
    assert ours == {("FINGER", "1"): k}


def test_how_far_apart_a_link_and_a_part_are_is_never_said_more_than_it_is() -> None:
    """The between-moments check advances on ``apart_at`` (boxes and face planes): a bound
    that said a pair farther apart than it is would let a contact pass. Against fcl's
    distance on link x part pairs of the crowded cell at its poses, near and far."""
    scene = crowded_cell(30)
    peer = FclPeer(scene)
    sim = Simulator(WorkCell(objects=list(scene.parts)))
    robot = sim._collision_scene()
    sim.stand_at([float(v) for v in scene.poses[0]])
    list(sim.check_collisions())
    pairs, nl = robot._pairs_now, len(robot._link_ks)
    assert pairs is not None
    rng = np.random.default_rng(40)
    p = rng.choice(np.flatnonzero((pairs.stationary >= nl) & (pairs.moving < nl)), 600)
    at = rng.integers(0, 100, 600)
    frames = sim.model.link_frames_batch(scene.poses[:100], sim.base)
    said = robot.apart_at(frames, at, p)
    true = []
    for k, pair in zip(at.tolist(), p.tolist()):
        link, part = int(pairs.moving[pair]), int(pairs.stationary[pair]) - nl
        rot, shift = frames[k, robot.owners[link], :3, :3], frames[k, robot.owners[link], :3, 3]
        obj = fcl.CollisionObject(peer.geoms[link], fcl.Transform(rot, rot @ peer.local_centres[link] + shift))
        true.append(fcl.distance(obj, peer.parts[part], fcl.DistanceRequest(), fcl.DistanceResult()))
    true_d = np.maximum(np.array(true), 0.0)
    assert (said <= true_d + 1e-6).all()
    near = true_d < 60.0
    assert near.sum() >= 10 and np.median(said[near] / np.maximum(true_d[near], 1e-9)) > 0.5   # and says much


def test_a_carried_part_keeps_the_width_spaced_moments_alone(monkeypatch: pytest.MonkeyPatch) -> None:
    """With a part carried the glancing check has only box gaps and checks its moments one by
    one: it made PROCESS (grasping, placing) 9x dearer to grade. A carried part's steps look
    between poses as before (the limit is docs/PERFORMANCE.md's), its free steps as above."""
    from valterm.core.collision.frames import RobotScene
    from valterm.core.session import Session

    calls = {"carried": 0}
    checked = RobotScene.collisions_between

    def counted(self: RobotScene, *args: object, **kwargs: object) -> object:
        calls["carried"] += 1
        return checked(self, *args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(RobotScene, "collisions_between", counted)
    session = Session(setup="PROCESS")
    session.load_locations("PROCESS")
    session.simulator.collision_checks = True
    for _ in session.interpreter.execute("PROCESS"):
        pass
    assert 0 < calls["carried"] < 1000  # 3306 with the glancing moments, 364 without
