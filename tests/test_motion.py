"""SPEC §3: joint-coordinated and straight-line motion, APPRO/DEPART, the pendant."""

from __future__ import annotations

import numpy as np
import pytest

from valterm.core.kinematics import Config, fk, fk_batch, ik, indicators, oat_to_rotation
from valterm.core.motion import (
    MotionRefused,
    approach_point,
    clamp_speed,
    joint_increment,
    joint_path,
    pendant_straight,
    straight_increment,
    straight_path,
    tool_displacement,
    world_displacement,
)

# a comfortable pose in front of the robot, RIGHTY ABOVE NOFLIP
START = [-20.0, -150.0, 40.0, 10.0, 50.0, 20.0]


def test_fig_2_7_two_links_to_horizontal_in_three_steps() -> None:
    path = joint_path([60, 30, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0], 20)
    assert path.shape == (3, 6)
    assert np.allclose(np.diff(np.vstack([[60, 30, 0, 0, 0, 0], path]), axis=0)[:, :2], [[-20, -10]] * 3)
    assert np.allclose(path[-1], 0)


def test_remainder_rule_last_step_proportional_to_the_remainder() -> None:
    # 25 deg at 12 deg per step: 12, 12, then the remainder 1; the second joint in proportion
    path = joint_path([0] * 6, [25, 10, 0, 0, 0, 0], 12)
    assert path.shape == (3, 6)
    assert np.allclose(path[:, 0], [12, 24, 25])
    assert np.allclose(path[:, 1], [4.8, 9.6, 10])


def test_joint_motion_steps_scale_with_speed() -> None:
    assert joint_increment(100) == 12 and joint_increment(50) == 6
    assert joint_increment(5) == pytest.approx(1.2)  # SPEED clamped to 10
    assert clamp_speed(250) == 100 and clamp_speed(-3) == 10
    assert len(joint_path([0] * 6, [90, 0, 0, 0, 0, 0], joint_increment(100))) == 8
    assert len(joint_path([0] * 6, [90, 0, 0, 0, 0, 0], joint_increment(50))) == 15
    assert len(joint_path([0] * 6, [0] * 6, 12)) == 0


def test_straight_line_keeps_orientation_and_stays_on_the_segment() -> None:
    here = fk(START)
    goal = here.xyz + np.array([120.0, -60.0, 90.0])
    path = straight_path(START, goal, here.rotation, indicators(START), straight_increment(100))
    assert len(path) == int(np.ceil(120 / 25.4))
    xyz, rotations = fk_batch(path)
    assert np.abs(rotations - here.rotation).max() < 1e-9  # Table 2-3: only the position changes
    d = goal - here.xyz
    t = (xyz - here.xyz) @ d / (d @ d)
    assert np.abs(xyz - here.xyz - t[:, None] * d).max() < 1e-6
    assert np.allclose(t, np.arange(1, len(path) + 1) / len(path))
    assert np.abs(xyz[-1] - goal).max() < 1e-6


def test_straight_line_interpolates_a_changing_orientation() -> None:
    here = fk(START)
    goal_r = oat_to_rotation(*np.add(here.oat, (20.0, 10.0, -15.0)))
    path = straight_path(START, here.xyz + [0, 50, 0], goal_r, indicators(START), 25.4)
    _, rotations = fk_batch(path)
    angles = [np.degrees(np.arccos(np.clip((np.trace(here.rotation.T @ r) - 1) / 2, -1, 1))) for r in rotations]
    assert np.all(np.diff(angles) > 0)
    assert np.abs(rotations[-1] - goal_r).max() < 1e-9


def test_moves_that_would_change_arm_is_refused_with_no_motion() -> None:
    here = fk(START)
    config = indicators(START)
    lefty = Config(-config.arm, config.elbow, config.wrist)
    with pytest.raises(MotionRefused, match="ARM"):
        straight_path(START, here.xyz + [50, 0, 0], here.rotation, lefty, 25.4)


def test_straight_line_through_the_waist_axis_is_refused() -> None:
    # from in front of the robot to behind it across the base: ARM would have to flip
    here = fk(START)
    goal = here.xyz * np.array([-1.0, -1.0, 1.0])
    with pytest.raises(MotionRefused) as caught:
        straight_path(START, goal, here.rotation, indicators(START), 25.4)
    assert "out of reach" in str(caught.value) or "singularity" in str(caught.value)


def test_straight_line_to_a_goal_out_of_reach_is_refused_before_any_step() -> None:
    here = fk(START)
    with pytest.raises(MotionRefused) as caught:
        straight_path(START, here.xyz + [0, 0, 2000], here.rotation, indicators(START), 25.4)
    assert "out of reach" in str(caught.value)
    assert caught.value.step == 0  # the goal itself: no path was built


def test_a_straight_line_refused_on_the_way_names_the_step() -> None:
    # both ends reachable pointing down; on the way across the base JT5 passes its stop
    down = oat_to_rotation(0.0, 90.0, 0.0)
    start = ik([300.0, 0.0, 300.0], down, Config())
    with pytest.raises(MotionRefused) as caught:
        straight_path(start, np.array([-300.0, 0.0, 300.0]), down, Config(), 25.4)
    assert caught.value.step >= 1 and caught.value.joint == 5
    assert f"at step {caught.value.step} of the line" in str(caught.value)


def test_appro_offsets_back_along_tool_z() -> None:
    r = fk(START).rotation
    p = np.array([400.0, 100.0, -200.0])
    assert np.allclose(approach_point(p, r, 50.0), p - 50.0 * r[:, 2])
    # the thesis's APPRO A, -50 stops 50 mm past A
    assert np.allclose(approach_point(p, r, -50.0), p + 50.0 * r[:, 2])


def test_pendant_world_and_tool_steps_keep_orientation() -> None:
    here = fk(START)
    path = pendant_straight(START, world_displacement(2, 10.0), 8.0)
    end = fk(path[-1])
    assert np.allclose(end.xyz - here.xyz, [0, 0, 10])
    assert np.abs(end.rotation - here.rotation).max() < 1e-9
    path = pendant_straight(START, tool_displacement(START, 2, 10.0), 8.0)
    end = fk(path[-1])
    assert np.allclose(end.xyz - here.xyz, 10.0 * here.rotation[:, 2])


def test_pendant_refuses_near_the_elbow_singularity() -> None:
    # JT3 = 95: within one 8-degree increment of the straight elbow (JT3 = 90)
    near = [-20.0, -100.0, 95.0, 10.0, 50.0, 20.0]
    with pytest.raises(MotionRefused) as caught:
        pendant_straight(near, world_displacement(0, -10.0), 8.0)
    assert caught.value.joint == 3
    # with a 2-degree increment the same step is allowed
    pendant_straight(near, world_displacement(0, -2.0), 2.0)
