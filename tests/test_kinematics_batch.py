"""The fast paths of issue 15 agree with the full computations: tool-only FK batch, one-pose
link frames on floats, chunked IK batch (more poses than one chunk)."""

from __future__ import annotations

import numpy as np

from valterm.core.kinematics import (
    BATCH_CHUNK, Config, fk, fk_batch, ik, ik_batch, indicators_batch, link_frames, link_frames_batch, robot_geometry,
)


def _poses(n: int, seed: int = 15) -> np.ndarray:
    stops = robot_geometry().stops_array
    return np.random.default_rng(seed).uniform(stops[:, 0], stops[:, 1], (n, 6))


def test_fk_batch_is_the_tool_frame_of_link_frames_batch():
    q = _poses(2 * BATCH_CHUNK + 17)
    geometry = robot_geometry()
    tool = link_frames_batch(q)[:, 6]
    for point in (1, 2, 3):
        xyz, rot = fk_batch(q, point)
        assert np.abs(rot - tool[:, :3, :3]).max() < 1e-12
        assert np.abs(xyz - (tool[:, :3, 3] + geometry.point_offset(point) * tool[:, :3, 2])).max() < 1e-9
    for row in (0, BATCH_CHUNK, len(q) - 1):   # and the scalar fk, chunk edges included
        pose = fk(list(q[row]), 1)
        assert np.abs(pose.xyz - fk_batch(q, 1)[0][row]).max() < 1e-9


def test_one_pose_link_frames_match_the_batch():
    for q in _poses(500, seed=3):
        assert np.abs(link_frames(q) - link_frames_batch(q)[0]).max() < 1e-12


def test_the_thesis_arms_frames_are_the_same_numbers_one_by_one_and_together():
    """Bit for bit: the swept check's moments take a few poses one by one, more together."""
    from valterm.core.cell.workcell import WorkCell
    from valterm.core.simulator import Simulator

    sim = Simulator(WorkCell(objects=[]))
    q = np.concatenate([_poses(300, seed=5), np.random.default_rng(5).uniform(-400.0, 400.0, (300, 6))])
    assert np.array_equal(np.array([link_frames(row) for row in q]), link_frames_batch(q))
    for n in (1, 2, 3, 6, 7):
        for at in range(0, 40, n):
            assert np.array_equal(sim._frames_batch(q[at: at + n]), link_frames_batch(q[at: at + n]))


def test_model_link_frames_batch_is_link_frames_pose_by_pose():
    """Both robots (the thesis's and a DH robot file's), with and without a BASE frame: the
    batch gives the one-pose frames (the swept check of a whole path relies on it)."""
    from valterm.core.simulator import robot_model

    base = np.eye(4)
    base[:3, :3] = [[0.6, -0.8, 0.0], [0.8, 0.6, 0.0], [0.0, 0.0, 1.0]]
    base[:3, 3] = (120.0, -35.5, 10.0)
    for name in (None, "PUMA560"):
        model = robot_model(name)
        q = _poses(200, seed=7)
        for b in (None, base):
            batch = model.link_frames_batch(q, b)
            assert batch.shape == (200, 7, 4, 4)
            one = np.array([model.link_frames(list(row), b) for row in q])
            assert np.abs(batch - one).max() < 1e-12


def test_ik_batch_in_chunks_round_trips_and_matches_ik():
    q = _poses(BATCH_CHUNK + 500, seed=9)
    xyz, rot = fk_batch(q)
    cfg = indicators_batch(q)
    joints, status = ik_batch(xyz, rot, cfg)
    ok = status == 0
    assert ok.mean() > 0.9
    back_xyz, back_rot = fk_batch(joints[ok])
    assert np.abs(back_xyz - xyz[ok]).max() < 1e-6 and np.abs(back_rot - rot[ok]).max() < 1e-9
    for row in np.flatnonzero(ok)[[0, -1]]:        # the scalar path, numpy arguments on entry
        single = ik(xyz[row], rot[row], Config(*(int(v) for v in cfg[row])))
        assert np.abs(np.array(fk_batch(np.array(single))[0][0]) - xyz[row]).max() < 1e-6
    # a (3,) configuration broadcasts to every pose, chunked the same way
    one = ik_batch(xyz, rot, np.array([1, 1, 1]))[0]
    assert one.shape == joints.shape


def test_ik_fast_path_gives_what_fit_to_stops_gives():
    """ik() skips fit_to_stops when every angle is well inside its stops with no equivalent
    inside: the answer must be the general one, for any current pose."""
    import math

    from valterm.core.kinematics import IKError, fit_to_stops, ik_fast, indicators, wrap180

    geometry = robot_geometry()
    rng = np.random.default_rng(21)
    shortcut = 0
    for q in _poses(2000, seed=21):
        current = [float(v) for v in q + rng.normal(0.0, 40.0, 6)]
        pose = fk(list(q))
        config = indicators(list(q))
        radians = ik_fast(*pose.xyz.tolist(), pose.rotation.tolist(), config.arm, config.elbow, config.wrist,
                          math.radians(current[3]), geometry)
        wrapped = [wrap180(math.degrees(v)) for v in radians]
        try:
            expected: object = fit_to_stops(wrapped, current, geometry)
        except IKError as error:
            expected = str(error)
        try:
            got: object = ik(pose.xyz, pose.rotation, config, current)
        except IKError as error:
            got = str(error)
        assert got == expected
        shortcut += got == wrapped
    assert 200 < shortcut < 2000     # both ways taken
