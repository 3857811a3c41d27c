"""The collision bench's scenes are what they say (issue 40 item 3), and the batched swept
check answers as the moment-by-moment one. No timing here: ``valterm bench`` times them."""

from __future__ import annotations

import fcl
import numpy as np
import pytest

from valterm.bench.collision_scenes import (CLEAR_TO, PLATE, CellScene, DenseOracle, FclPeer, crowded_cell,
                                            heavy_cell, valterm_contacts)
from valterm.core.cell.workcell import WorkCell
from valterm.core.collision import arrays
from valterm.core.collision.frames import RobotScene
from valterm.core.simulator import Simulator


@pytest.fixture(scope="module")
def crowded() -> CellScene:
    return crowded_cell(30)


@pytest.fixture(scope="module")
def heavy() -> CellScene:
    return heavy_cell(30)


def _nearest_at_poses(scene: CellScene) -> np.ndarray:
    """Each part's least distance from the arm over the program's poses (fcl, pose by pose)."""
    peer = FclPeer(scene)
    nearest = np.full(len(scene.parts), np.inf)
    for q in scene.poses[1:]:
        rot, at = peer._placements([float(v) for v in q])
        for obj, r, t in zip(peer.links, rot, at):
            obj.setTransform(fcl.Transform(r, t))
        for i, part in enumerate(peer.parts):
            for obj in peer.links:
                d = fcl.distance(obj, part, fcl.DistanceRequest(), fcl.DistanceResult())
                nearest[i] = min(nearest[i], d)
    return nearest


def test_the_crowded_cell_is_cleared_with_every_part_close_by(crowded: CellScene) -> None:
    """No part met along the program (valterm, fcl per pose, fcl + CCD), every part within
    CLEAR_TO mm of the arm at one of the poses at least, some within 10 mm."""
    ours, poses = valterm_contacts(crowded)
    assert poses == len(crowded.poses) - 1 > 200
    peer = FclPeer(crowded)
    assert ours == {} and peer.per_pose() == {} and peer.with_ccd() == {}
    nearest = _nearest_at_poses(crowded)
    assert (nearest > 0.0).all()
    assert (nearest < CLEAR_TO + 10.0).all()    # the nearest approach may fall between poses
    assert nearest.min() < 10.0 and np.median(nearest) < CLEAR_TO


def test_the_heavy_cell_is_met_often_and_the_plate_only_between_poses(heavy: CellScene) -> None:
    ours, _ = valterm_contacts(heavy)
    plain = FclPeer(heavy).per_pose()
    assert len(plain) >= 40 and len(ours) >= len(plain)
    plate = str(heavy.plate)
    assert arrays.thickness(heavy.parts[-1].vertices, 4) == pytest.approx(PLATE)
    assert plate not in {part for _, part in plain}                 # at no pose
    found = {link: k for (link, part), k in ours.items() if part == plate}
    assert "FINGER" in found and found["FINGER"] == heavy.plate_step
    assert DenseOracle(heavy).meets("FINGER", plate, heavy.plate_step)  # the finger's way goes through it


def test_the_scenes_are_the_same_every_run(crowded: CellScene) -> None:
    again = crowded_cell(30)
    assert all(np.array_equal(a.vertices, b.vertices) for a, b in zip(crowded.parts, again.parts))
    assert np.array_equal(crowded.poses, again.poses)


def _moments_about(heavy: CellScene, seed: int) -> tuple[Simulator, RobotScene, np.ndarray, np.ndarray,
                                                         np.random.Generator]:
    """The heavy cell's scene, the links' frames at 199 poses about its path and, per pose, a
    random half of the scene's pairs (the moments and rows ``collisions_at`` takes)."""
    sim = Simulator(WorkCell(objects=list(heavy.parts)))
    scene: RobotScene = sim._collision_scene()
    sim.stand_at([float(v) for v in heavy.poses[0]])
    list(sim.check_collisions())
    pairs = scene._pairs_now
    assert pairs is not None
    rng = np.random.default_rng(seed)
    joints = heavy.poses[1:200] + rng.normal(0.0, 3.0, (199, 6))
    frames = sim.model.link_frames_batch(joints, sim.base)
    rows = rng.random((len(joints), len(pairs.moving))) < 0.5
    return sim, scene, frames, rows, rng


def test_moments_checked_together_find_what_each_moment_finds(heavy: CellScene) -> None:
    """``RobotScene.collisions_at`` (every moment's pairs in one batch) against
    ``collisions_between`` moment by moment, on poses about the heavy cell's path."""
    sim, scene, frames, rows, _ = _moments_about(heavy, 40)
    together = scene.collisions_at(frames, rows)
    assert together is not None
    alone = [scene.collisions_between(f, sim.cell.objects, np.flatnonzero(r)) for f, r in zip(frames, rows)]
    assert together == alone
    assert sum(map(len, alone)) > 50


def test_moments_in_rounds_say_what_every_moment_says(heavy: CellScene) -> None:
    """With the moments' steps given, a pair found at one moment of a step is not looked for
    at its later ones: each step still says the same collisions, first said in the same order."""
    _, scene, frames, rows, rng = _moments_about(heavy, 41)
    steps = np.sort(rng.integers(0, 25, len(frames)))
    every, rounds = scene.collisions_at(frames, rows), scene.collisions_at(frames, rows, steps)
    assert every is not None and rounds is not None
    said = [[list(dict.fromkeys(f for k in np.flatnonzero(steps == s) for f in found[k])) for s in range(25)]
            for found in (every, rounds)]
    assert said[0] == said[1] and sum(map(len, said[0])) > 20
    assert sum(map(len, rounds)) < sum(map(len, every))        # later moments not looked at again


def test_the_goals_table_has_the_scenes_and_says_where_the_checkers_differ() -> None:
    from valterm.bench.suite import GOALS, PEERS, markdown

    table = markdown({"machine": "test", "collision_crowded_vs_fcl_x_30parts": 3.3,
                      "collision_crowded_fcl_us_30parts": 41.5,
                      "notes": ["heavy cell, 30 parts: FINGER x part 30 (the 0.5 mm plate): found between poses"]})
    assert "| `collision_crowded_vs_fcl_x_30parts` | 3.3 | <= 4 | yes | python-fcl per pose, µs per pose: 41.5" in table
    assert "Where the checkers differ:\n\n- heavy cell, 30 parts: FINGER x part 30" in table
    assert GOALS["collision_crowded_vs_ccd_x_100parts"] == ("<=", 0.5)
    assert PEERS["collision_heavy_vs_ccd_x_30parts"][0] == "collision_heavy_ccd_us_30parts"


def test_a_findings_kept_hash_stays_in_its_process() -> None:
    """A Finding keeps its hash (a crowded cell asks for it many times a pose); a pickled one
    (sent to a grading worker) carries none: another process hashes strings differently."""
    import pickle

    from valterm.core.collision.world import Finding

    found = Finding("near", "CLAMP", 10)
    assert hash(found) == hash(("near", "CLAMP", 10)) and "_hash" in vars(found)
    again = pickle.loads(pickle.dumps(found))
    assert again == found and "_hash" not in vars(again) and {again} == {found}
