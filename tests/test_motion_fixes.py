"""Motion core fixes found by an independent oracle (issue 13 item 4): no silent surprises."""

from __future__ import annotations

import math

import numpy as np
import pytest

from valterm.core.kinematics import (
    Config,
    IKError,
    canonical_joints,
    fk,
    ik,
    indicators,
    indicators_batch,
    robot_geometry,
)
from valterm.core.motion import MotionRefused, STRAIGHT_INCREMENT, straight_path
from valterm.core.rules import CONTROLLER, RULES_1985
from valterm.core.simulator import Simulator


def test_ready_reads_all_indicators_positive() -> None:
    ready = robot_geometry().ready
    assert indicators(ready) == Config(1, 1, 1)
    assert indicators_batch(np.array([ready])).tolist() == [[1, 1, 1]]


def test_ready_sets_the_users_indicators() -> None:
    sim = Simulator()
    for word in ("LEFTY", "BELOW", "FLIP"):
        sim.set_indicator(word)
    assert sim.config == Config(-1, -1, -1)
    list(sim.ready())
    assert sim.config == Config(1, 1, 1)


def test_away_from_a_tie_the_indicators_are_unchanged() -> None:
    # Fig. 2-8 rows keep their printed indicators (the tie rule only decides boundaries)
    assert indicators([-100.02, 172.08, 19.34, -1.52, 35.64, -9.54]) == Config(1, 1, 1)
    assert indicators([156.36, 8.18, 159.13, -179.90, -13.68, 1.27]) == Config(-1, 1, 1)


def _line_to_joints(start: list[float], goal: list[float], config: Config, rules: str = RULES_1985) -> np.ndarray:
    pose = fk(goal)
    return straight_path(start, pose.xyz, pose.rotation, config, STRAIGHT_INCREMENT, rules=rules)


def test_under_the_controller_rules_a_line_whose_wrist_reaches_its_stop_is_refused() -> None:
    start = [10.0, -60.0, 150.0, 250.0, 30.0, 0.0]  # wound: a real PUMA's JT4 at 250
    goal = [10.0, -60.0, 150.0, 290.0 - 360.0, 30.0, 0.0]  # the same wrist pose as JT4 = 290
    config = indicators(start)
    with pytest.raises(MotionRefused) as refused:
        _line_to_joints(start, goal, config, CONTROLLER)
    assert refused.value.joint == 4 and refused.value.step >= 1
    assert "joint 4 beyond its stop" in str(refused.value) and "266" in str(refused.value)


def test_under_the_1985_rules_the_same_line_goes_its_angles_a_function_of_the_pose() -> None:
    # SPEC §3a: JT4 290 is JT4 -70 (one pose, one set of angles): the line is not refused
    start = [10.0, -60.0, 150.0, 250.0, 30.0, 0.0]
    goal = [10.0, -60.0, 150.0, 290.0 - 360.0, 30.0, 0.0]
    path = _line_to_joints(start, goal, indicators(start))
    assert canonical_joints(path[-1]) == pytest.approx(goal, abs=1e-6)


def test_a_line_within_the_stops_turns_the_wrist_smoothly() -> None:
    start = [10.0, -60.0, 150.0, 200.0, 30.0, 0.0]
    goal = [10.0, -60.0, 150.0, 240.0 - 360.0, 30.0, 0.0]
    path = _line_to_joints(start, goal, indicators(start))
    steps = np.diff(np.vstack([start, path]), axis=0)
    assert np.abs(steps[:, 3:]).max() < 45.0  # no twirl
    assert path[-1][3] == pytest.approx(240.0, abs=1e-6)  # JT4 went on past 180, continuously


def test_a_line_that_would_flip_the_wrist_at_its_last_step_is_refused() -> None:
    start = [20.0, -70.0, 160.0, 30.0, 40.0, 20.0]  # NOFLIP
    here = fk(start)
    goal_xyz = here.xyz + np.array([100.0, 0.0, 0.0])
    user = indicators(start)._replace(wrist=-1)  # the user asked for FLIP
    with pytest.raises(MotionRefused, match="straight line would change WRIST from NOFLIP to FLIP"):
        straight_path(start, goal_xyz, here.rotation, user, STRAIGHT_INCREMENT)


def test_a_pure_reorientation_takes_longer_at_a_lower_speed() -> None:
    start = [20.0, -70.0, 160.0, 30.0, 40.0, 20.0]
    here = fk(start)
    turn = fk([20.0, -70.0, 160.0, 30.0, 40.0, 80.0])  # JT6 turned 60 degrees: same TCS origin
    assert np.allclose(turn.xyz, here.xyz)
    fast = straight_path(start, here.xyz, turn.rotation, indicators(start), STRAIGHT_INCREMENT)
    slow = straight_path(start, here.xyz, turn.rotation, indicators(start), STRAIGHT_INCREMENT / 2)
    assert len(slow) == 2 * len(fast)


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_a_location_that_is_not_a_number_is_an_ik_error(bad: float) -> None:
    with pytest.raises(IKError):
        ik([bad, 100.0, 100.0], np.eye(3), Config())


def test_autoconfig_tries_the_other_configurations_nearest_first() -> None:
    from valterm.core.events import Message, Motion
    from valterm.core.kinematics import Location, rotation_to_oat

    # Fig. 2-8a2: RIGHTY BELOW puts JT2 at 102.63, beyond its stop (SPEC §2)
    joints = [-100.02, 102.63, 168.66, -0.33, -84.24, -18.99]
    pose = fk(joints)
    target = Location(tuple(float(v) for v in pose.xyz), rotation_to_oat(pose.rotation))
    sim = Simulator()
    sim.set_indicator("BELOW")
    with pytest.raises(MotionRefused, match="joint 2 beyond its stop"):
        list(sim.move(target))
    sim.autoconfig = True
    events = list(sim.move(target))
    [message] = [e for e in events if isinstance(e, Message) and e.text.startswith("AUTOCONFIG")]
    assert message.text == f"AUTOCONFIG: USING {sim.config}"
    assert sim.config.elbow == 1 and isinstance(events[-1], Motion)
    assert np.allclose(fk(sim.joints).xyz, pose.xyz, atol=1e-6)
