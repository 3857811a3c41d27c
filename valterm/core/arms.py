"""The robot the simulator moves: one interface for the thesis's PUMA and a DH robot file's arm.

The simulator, motion and the readouts ask a robot (an ``Arm``) for everything kinematic:
forward and inverse kinematics with a configuration, the configuration indicators, the stops,
the readout and the 1985 rules' canonical angles, the link frames the drawing and the collision
check place the links by, and where the robot's own frame sits in the cell. ``--robot`` chooses
one once per session (``arm_of``).

- ``ThesisArm``: the thesis's fitted model (``core/kinematics.py``: Lee's solution, the fitted
  offsets, the fast scalar and batch paths), each method one call of those functions;
- ``DHArm``: a robot file's standard DH table (``core/dh.py``: the PUMA 560 of the Robotics
  Toolbox), mounted with its shoulder where the thesis's robot has its own, so a cell laid out
  for the thesis's robot (PROCESS) is in front of it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Protocol

import numpy as np

from valterm.core import kinematics
from valterm.core.dh import DHRobot, dh_robot
from valterm.core.errors import RefusedValue
from valterm.core.kinematics import (
    OUT_OF_REACH,
    BeyondStop,
    Config,
    IKError,
    OutOfReach,
    Pose,
    RobotGeometry,
)
from valterm.core.robot_choice import THESIS_ROBOT


class Arm(Protocol):
    """What the simulator and motion ask of a robot (angles in degrees, lengths in mm)."""

    @property
    def key(self) -> str: ...          # what --robot names it: PUMA, PUMA560

    @property
    def name(self) -> str: ...         # as its file names it: PUMA 600, PUMA 560

    @property
    def stops(self) -> tuple[tuple[float, float], ...]: ...

    @property
    def ready(self) -> tuple[float, ...]: ...

    @property
    def elbow_straight(self) -> float: ...   # JT3 with the forearm in line with the upper arm

    @property
    def mount(self) -> np.ndarray: ...       # 4x4: the robot's own frame in the cell's robot frame

    def fk(self, joints: Sequence[float], point: int = 1) -> Pose: ...

    def ik(self, xyz: Sequence[float] | np.ndarray, rotation: np.ndarray | Sequence[Sequence[float]],
           config: Config, current: Sequence[float] | None = None, enforce_stops: bool = True) -> list[float]: ...

    def ik_batch(self, xyz: np.ndarray, rotations: np.ndarray,
                 config: Sequence[int] | Config) -> tuple[np.ndarray, np.ndarray]: ...

    def indicators(self, joints: Sequence[float]) -> Config: ...

    def canonical_joints(self, joints: Sequence[float]) -> list[float]: ...

    def readout_joints(self, joints: Sequence[float]) -> list[float]: ...

    def fit_to_stops(self, joints: Sequence[float], current: Sequence[float] | None = None) -> list[float]: ...

    def link_frames(self, joints: Sequence[float]) -> np.ndarray: ...

    def link_frames_batch(self, joints: np.ndarray) -> np.ndarray: ...   # (n, 6) -> (n, 7, 4, 4), as link_frames


@dataclass(frozen=True)
class ThesisArm:
    """The thesis's PUMA: every method is the kinematics module's function on its geometry."""

    geometry: RobotGeometry
    key: str = THESIS_ROBOT
    elbow_straight: float = 90.0  # JTsim3 = 0 (§3.3)
    mount: np.ndarray = field(default_factory=lambda: np.eye(4), compare=False, repr=False)

    @property
    def name(self) -> str:
        return self.geometry.name

    @property
    def stops(self) -> tuple[tuple[float, float], ...]:
        return self.geometry.stops

    @property
    def ready(self) -> tuple[float, ...]:
        return self.geometry.ready

    def fk(self, joints: Sequence[float], point: int = 1) -> Pose:
        return kinematics.fk(joints, point, self.geometry)

    def ik(self, xyz: Sequence[float] | np.ndarray, rotation: np.ndarray | Sequence[Sequence[float]],
           config: Config, current: Sequence[float] | None = None, enforce_stops: bool = True) -> list[float]:
        return kinematics.ik(xyz, rotation, config, current, self.geometry, enforce_stops)

    def ik_batch(self, xyz: np.ndarray, rotations: np.ndarray,
                 config: Sequence[int] | Config) -> tuple[np.ndarray, np.ndarray]:
        return kinematics.ik_batch(xyz, rotations, config, self.geometry)

    def indicators(self, joints: Sequence[float]) -> Config:
        return kinematics.indicators(joints, self.geometry)

    def canonical_joints(self, joints: Sequence[float]) -> list[float]:
        return kinematics.canonical_joints(joints, self.geometry)

    def readout_joints(self, joints: Sequence[float]) -> list[float]:
        return kinematics.readout_joints(joints, self.geometry)

    def fit_to_stops(self, joints: Sequence[float], current: Sequence[float] | None = None) -> list[float]:
        return kinematics.fit_to_stops(joints, current, self.geometry)

    def link_frames(self, joints: Sequence[float]) -> np.ndarray:
        return kinematics.link_frames(joints, self.geometry)

    def link_frames_batch(self, joints: np.ndarray) -> np.ndarray:
        return kinematics.link_frames_batch(joints, self.geometry)


@dataclass(frozen=True)
class DHArm:
    """A robot file's arm by its DH table (``core/dh.py``); frame 6 is its tool point (it has
    no LED sensor or clamp tip: position options 2 and 3 are frame 6 too)."""

    chain: DHRobot
    key: str

    @property
    def name(self) -> str:
        return self.chain.name

    @property
    def stops(self) -> tuple[tuple[float, float], ...]:
        return self.chain.stops

    @property
    def ready(self) -> tuple[float, ...]:
        return self.chain.ready

    @property
    def elbow_straight(self) -> float:
        # the wrist centre on the upper arm's line: q3 = -atan2(d4, a3) (dh.py's inverse)
        return -math.degrees(math.atan2(self.chain.d[3], self.chain.a[2])) - self.chain.offset[2]

    @property
    def mount(self) -> np.ndarray:
        # the shoulder (d1 above the mounting surface) where the thesis's robot has its own
        frame = np.eye(4)
        frame[2, 3] = -self.chain.d[0]
        return frame

    def fk(self, joints: Sequence[float], point: int = 1) -> Pose:
        if point not in (1, 2, 3):
            raise RefusedValue(f"position option must be 1, 2 or 3, not {point}")
        tool = self.chain.fk([float(v) for v in joints])
        return Pose(tool[:3, 3].copy(), tool[:3, :3].copy())

    def ik(self, xyz: Sequence[float] | np.ndarray, rotation: np.ndarray | Sequence[Sequence[float]],
           config: Config, current: Sequence[float] | None = None, enforce_stops: bool = True) -> list[float]:
        tool = np.eye(4)
        tool[:3, :3], tool[:3, 3] = np.asarray(rotation, dtype=float), np.asarray(xyz, dtype=float)
        if not np.isfinite(tool).all():
            raise OutOfReach("not a location: a coordinate is not a finite number")
        joints = self.chain.ik(tool, config)
        if current is not None and abs(math.sin(math.radians(joints[4]))) < WRIST_SINGULAR:
            joints = _keep_jt4(joints, float(current[3]))
        if not enforce_stops:
            return joints
        return kinematics.fit_to_stops(joints, current, self.chain)

    def ik_batch(self, xyz: np.ndarray, rotations: np.ndarray,
                 config: Sequence[int] | Config) -> tuple[np.ndarray, np.ndarray]:
        """As ``kinematics.ik_batch``: joints (n, 6) fitted to the stops nearest the wrapped
        angle, status 0, OUT_OF_REACH or the first joint beyond its stop."""
        p = np.asarray(xyz, dtype=float).reshape(-1, 3)
        r = np.asarray(rotations, dtype=float).reshape(-1, 3, 3)
        arm, elbow, wrist = (int(v) for v in config)
        wanted = Config(arm, elbow, wrist)
        joints = np.zeros((len(p), 6))
        status = np.zeros(len(p), dtype=np.intp)
        for i in range(len(p)):  # a line's steps: a few hundred at most
            try:
                solved = self.ik(p[i], r[i], wanted, enforce_stops=False)
                joints[i] = solved
                joints[i] = self.fit_to_stops(solved)
            except BeyondStop as error:
                status[i] = error.joint
            except IKError:
                status[i] = OUT_OF_REACH
        return joints, status

    def indicators(self, joints: Sequence[float]) -> Config:
        return self.chain.indicators([float(v) for v in joints])

    def canonical_joints(self, joints: Sequence[float]) -> list[float]:
        return kinematics.canonical_joints(joints, self.chain)

    def readout_joints(self, joints: Sequence[float]) -> list[float]:
        return kinematics.readout_joints(joints, self.chain)

    def fit_to_stops(self, joints: Sequence[float], current: Sequence[float] | None = None) -> list[float]:
        return kinematics.fit_to_stops(joints, current, self.chain)

    def link_frames(self, joints: Sequence[float]) -> np.ndarray:
        frames: np.ndarray = self.chain.link_frames([float(v) for v in joints])[0]
        return frames

    def link_frames_batch(self, joints: np.ndarray) -> np.ndarray:
        return self.chain.link_frames(joints)


WRIST_SINGULAR = 1e-9  # |sin JT5| below this: JT4 and JT6 turn about one axis


def _keep_jt4(joints: list[float], jt4: float) -> list[float]:
    """A singular wrist (JT5 = 0 or 180) keeps JT4 where it is, JT6 takes the rest of the turn
    (as the thesis's robot does): the same tool frame, no needless twirl of JT4."""
    turn = kinematics.wrap180(jt4) - joints[3]
    straight = math.cos(math.radians(joints[4])) > 0  # JT5 = 0: JT4 + JT6 is what counts
    jt6 = joints[5] - turn if straight else joints[5] + turn
    return [*joints[:3], kinematics.wrap180(jt4), joints[4], kinematics.wrap180(jt6)]


@lru_cache(maxsize=1)
def thesis_arm() -> ThesisArm:
    """The thesis's robot (the default), on the bundled geometry."""
    return ThesisArm(kinematics.robot_geometry())


def arm_of(name: str | None = None) -> Arm:
    """The robot ``--robot`` names (PUMA, the thesis's, when None); RobotFileError if none."""
    key = (name or THESIS_ROBOT).strip().upper()
    if key == THESIS_ROBOT:
        return thesis_arm()
    return DHArm(dh_robot(key), key)


def as_arm(robot: Arm | RobotGeometry | None) -> Arm:
    """An arm from what a caller passes: an arm, the thesis's geometry (its own arm), or None."""
    if robot is None:
        return thesis_arm()
    if isinstance(robot, RobotGeometry):
        return thesis_arm() if robot is kinematics.robot_geometry() else ThesisArm(robot)
    return robot
