"""Cycle time: how long the real PUMA would take for a motion, and for a whole program.

A joint-coordinated motion follows a trapezoidal profile on every joint; the slowest joint
governs (the controller stretches the others to arrive together). A straight line runs its
tool path at the tool speed, its turn at the wrist's speed, whichever is slower. SPEED s%
time-scales a profile by 100/s. The parameters and their source are in the robot data
file, ``[timing]`` of ``assets/robot/PUMA.toml`` (another robot's, ``--robot PUMA560``:
its own file's).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from valterm.core import resources
from valterm.core.events import Delay, Event, Hand, Motion
from valterm.core.kinematics import ROBOT_FILE


@dataclass(frozen=True)
class Timing:
    """Per-joint maximum speeds (deg/s) and accelerations (deg/s^2) at SPEED 100, and more."""

    joint_speed: tuple[float, ...]
    joint_accel: tuple[float, ...]
    tool_speed: float
    tool_accel: float
    hand_time: float


@lru_cache(maxsize=4)
def robot_timing(robot: str | None = None) -> Timing:
    """A bundled robot's timing parameters (the thesis's PUMA when None), read on first use."""
    file = ROBOT_FILE if robot is None else (ROBOT_FILE[0], f"{robot}.toml")
    data = resources.read_toml(*file)["timing"]
    return Timing(
        joint_speed=tuple(float(v) for v in data["joint_speed"]),
        joint_accel=tuple(float(v) for v in data["joint_accel"]),
        tool_speed=float(data["tool_speed"]),
        tool_accel=float(data["tool_accel"]),
        hand_time=float(data["hand_time"]),
    )


def trapezoid_seconds(distance: float, speed: float, accel: float) -> float:
    """Time to cover ``distance`` from rest to rest: accelerate, cruise, decelerate.

    Too short to reach full speed, the profile is a triangle: 2 sqrt(d / a).
    """
    distance = abs(distance)
    if distance <= 0.0:
        return 0.0
    if distance >= speed * speed / accel:
        return distance / speed + speed / accel
    return 2.0 * math.sqrt(distance / accel)


def joint_motion_seconds(start: np.ndarray, goal: np.ndarray, speed_percent: float,
                         timing: Timing | None = None) -> float:
    """A joint-coordinated motion: the slowest joint's trapezoid, time-scaled by SPEED."""
    timing = timing or robot_timing()
    delta = np.abs(np.asarray(goal, dtype=float) - np.asarray(start, dtype=float))
    slowest = max(trapezoid_seconds(float(d), v, a)
                  for d, v, a in zip(delta, timing.joint_speed, timing.joint_accel))
    return slowest * 100.0 / speed_percent


def straight_motion_seconds(length_mm: float, turn_deg: float, speed_percent: float,
                            timing: Timing | None = None, tool_mm_per_s: float | None = None) -> float:
    """A straight line: the tool path at the tool speed, or the turn at the wrist's, if slower.

    ``tool_mm_per_s`` (V+ ``SPEED n MMPS``): the tool tip cruises at that speed, accelerating at
    the robot's tool acceleration; the turn keeps the percent speed."""
    timing = timing or robot_timing()
    scale = 100.0 / speed_percent
    turn = trapezoid_seconds(turn_deg, timing.joint_speed[3], timing.joint_accel[3]) * scale
    if tool_mm_per_s is not None:
        return max(trapezoid_seconds(length_mm, tool_mm_per_s, timing.tool_accel), turn)
    return max(trapezoid_seconds(length_mm, timing.tool_speed, timing.tool_accel) * scale, turn)


class CycleClock:
    """The robot's time: adds up a run's events (motions, the hand, DELAY) and WAIT polls.

    One clock per interpreter: STATUS and ``run`` read the cycle time off it, V+ TIMER and
    scripted inputs (``run --inputs``) go by it. ``hand_time`` starts as the robot file's;
    V+ ``PARAMETER HAND.TIME`` sets it.
    """

    def __init__(self, timing: Timing | None = None) -> None:
        self.timing = timing or robot_timing()
        self.hand_time = self.timing.hand_time
        self.seconds = 0.0

    def observe(self, event: Event) -> None:
        if isinstance(event, Motion):
            self.seconds += event.seconds
        elif isinstance(event, Hand):
            self.seconds += self.hand_time
        elif isinstance(event, Delay):
            self.seconds += event.seconds
