"""A robot given by its standard Denavit-Hartenberg table (a robot file's ``[dh]`` section).

The thesis's robot has its own fitted model and fast paths (``valterm.core.kinematics``);
a robot file such as ``robot/PUMA560.toml`` instead gives the table a textbook gives
(Corke's Robotics Toolbox ``Puma560``: Armstrong, Khatib and Burdick 1986), and everything
here is computed from it:

* forward kinematics, the chain of ``Rz(theta) Tz(d) Tx(a) Rx(alpha)`` link transforms,
  theta = joint angle + the file's offset (degrees, with the table's zero);
* the closed-form inverse of the PUMA structure (twists 90, 0, -90, 90, -90, 0 degrees,
  a1 = 0, a spherical wrist), in the file's lengths: waist from the wrist centre and the
  shoulder offset d3, shoulder and elbow by the triangle of the upper arm a2 and the forearm
  (a3, d4), the wrist as Z-Y-Z angles;
* the three configuration indicators of a joint vector, the ones the inverse takes:
  RIGHTY when the wrist centre is in front of the waist axis (the arm reaches forward,
  the toolbox's ``r``), ABOVE when the upper arm lies above the line from the shoulder to
  the wrist centre on a RIGHTY arm (below it on a LEFTY one; the toolbox's ``u``), NOFLIP
  when JT5 is at most 0 (the toolbox's ``n``). At a boundary an indicator reads positive.

Lengths are millimetres, angles degrees (as users see and type them).
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np

from valterm.core import resources
from valterm.core.errors import ValtermError
from valterm.core.kinematics import Config, OutOfReach, wrap180
from valterm.core.robot_choice import ROBOT_FOLDER, robot_names

# the structure the closed-form inverse solves: the PUMA's twists, in degrees
PUMA_TWISTS = (90.0, 0.0, -90.0, 90.0, -90.0, 0.0)
SINGULAR = 1e-9  # below this sin JT5 the wrist is singular (JT4 kept at 0)


class RobotFileError(ValtermError):
    """A robot file that cannot be used: the file and the reason."""


@dataclass(frozen=True)
class DHRobot:
    """A robot of six revolute joints by its standard DH table (mm, degrees)."""

    name: str
    a: tuple[float, ...]
    alpha: tuple[float, ...]
    d: tuple[float, ...]
    offset: tuple[float, ...]
    stops: tuple[tuple[float, float], ...]
    ready: tuple[float, ...]

    # -- forward ---------------------------------------------------------------------------
    def link_frames(self, joints: Any) -> np.ndarray:
        """Frames 0..6 of a batch of joint vectors: (n, 6) degrees -> (n, 7, 4, 4)."""
        q = np.radians(np.asarray(joints, dtype=float).reshape(-1, 6) + np.asarray(self.offset))
        n = len(q)
        frames = np.zeros((n, 7, 4, 4))
        frames[:, 0] = np.eye(4)
        for i in range(6):  # six links: the chain, each step vectorised over the poses
            ct, st = np.cos(q[:, i]), np.sin(q[:, i])
            ca, sa = math.cos(math.radians(self.alpha[i])), math.sin(math.radians(self.alpha[i]))
            link = np.zeros((n, 4, 4))
            link[:, 0, 0], link[:, 0, 1], link[:, 0, 2], link[:, 0, 3] = ct, -st * ca, st * sa, self.a[i] * ct
            link[:, 1, 0], link[:, 1, 1], link[:, 1, 2], link[:, 1, 3] = st, ct * ca, -ct * sa, self.a[i] * st
            link[:, 2, 1], link[:, 2, 2], link[:, 2, 3] = sa, ca, self.d[i]
            link[:, 3, 3] = 1.0
            frames[:, i + 1] = frames[:, i] @ link
        return frames

    def fk(self, joints: Any) -> np.ndarray:
        """The tool frame (frame 6) of one joint vector (degrees) as a 4x4 (mm)."""
        tool: np.ndarray = self.link_frames(joints)[0, 6]
        return tool

    # -- configuration ---------------------------------------------------------------------
    def indicators(self, joints: Any) -> Config:
        """The configuration indicators of a joint vector (degrees), as ``ik`` takes them."""
        q = np.radians(np.asarray(joints, dtype=float) + np.asarray(self.offset))
        px, py, pz = self._wrist_centre(self.fk(joints))
        reach = px * math.cos(q[0]) + py * math.sin(q[0])
        arm = 1 if reach >= -1e-9 else -1
        lift = _wrap(float(q[1]) - math.atan2(pz - self.d[0], reach))
        elbow = 1 if abs(lift) < 1e-12 or (lift > 0) == (arm > 0) else -1
        wrist = 1 if q[4] <= 1e-12 else -1
        return Config(arm, elbow, wrist)

    # -- inverse ---------------------------------------------------------------------------
    def ik(self, tool: np.ndarray, config: Config) -> list[float]:
        """JT1..JT6 (degrees, each in (-180, 180]) putting frame 6 at the 4x4 ``tool``;
        OutOfReach when the wrist centre is beyond the arm or inside the shoulder offset."""
        px, py, pz = self._wrist_centre(tool)
        a2, a3, d3, d4 = self.a[1], self.a[2], self.d[2], self.d[3]
        planar = math.hypot(px, py)
        if planar <= abs(d3):
            raise OutOfReach("out of reach (inside the shoulder offset)")
        # the wrist centre sits d3 beside the arm's plane: two waist angles, in front or behind
        side = math.asin(d3 / planar)
        q1 = math.atan2(py, px) + (side if config.arm > 0 else math.pi - side)
        reach = px * math.cos(q1) + py * math.sin(q1)
        height = pz - self.d[0]
        span = math.hypot(reach, height)
        forearm = math.hypot(a3, d4)
        cos_psi = (a2 * a2 + span * span - forearm * forearm) / (2.0 * a2 * span) if span > 0 else 2.0
        if abs(cos_psi) > 1.0 + 1e-12:
            raise OutOfReach()
        psi = math.acos(max(-1.0, min(1.0, cos_psi)))
        q2 = math.atan2(height, reach) + config.elbow * config.arm * psi
        # the forearm, wrist centre minus elbow, in the upper arm's frame: (a3, d4) turned by q3
        fx = math.cos(q2) * reach + math.sin(q2) * height - a2
        fy = -math.sin(q2) * reach + math.cos(q2) * height
        q3 = math.atan2(fy, fx) - math.atan2(d4, a3)
        q4, q5, q6 = self._wrist(tool, (q1, q2, q3), config.wrist)
        radians = (q1, q2, q3, q4, q5, q6)
        return [wrap180(math.degrees(v) - o) for v, o in zip(radians, self.offset)]

    def _wrist_centre(self, tool: np.ndarray) -> tuple[float, float, float]:
        centre = np.asarray(tool)[:3, 3] - self.d[5] * np.asarray(tool)[:3, 2]
        return float(centre[0]), float(centre[1]), float(centre[2])

    def _wrist(self, tool: np.ndarray, arm: tuple[float, float, float], wrist: int) -> tuple[float, float, float]:
        """JT4..JT6 (radians): the wrist's rotation R36 = Rz(q4) Ry(-q5) Rz(q6) as Z-Y-Z angles."""
        arm_deg = [math.degrees(v) - o for v, o in zip(arm, self.offset)]
        r03 = self.link_frames([*arm_deg, 0.0, 0.0, 0.0])[0, 3, :3, :3]
        r = r03.T @ np.asarray(tool)[:3, :3]
        sin_beta = math.hypot(r[0, 2], r[1, 2])
        if sin_beta < SINGULAR:
            # JT4 and JT6 turn about one axis: JT4 stays 0, JT6 takes the turn
            beta = 0.0 if r[2, 2] > 0 else math.pi
            return 0.0, -beta, math.atan2(r[1, 0], r[0, 0]) if beta == 0.0 else math.atan2(r[1, 0], -r[0, 0])
        # NOFLIP: beta >= 0, so JT5 = -beta <= 0; FLIP the other way round
        q4 = math.atan2(r[1, 2], r[0, 2]) if wrist > 0 else math.atan2(-r[1, 2], -r[0, 2])
        c4, s4 = math.cos(q4), math.sin(q4)
        beta = math.atan2(c4 * r[0, 2] + s4 * r[1, 2], r[2, 2])
        q6 = math.atan2(-s4 * r[0, 0] + c4 * r[1, 0], -s4 * r[0, 1] + c4 * r[1, 1])
        return q4, -beta, q6


def _wrap(angle: float) -> float:
    """Radians to (-pi, pi]."""
    return math.atan2(math.sin(angle), math.cos(angle))


@lru_cache(maxsize=8)
def dh_robot(name: str) -> DHRobot:
    """The bundled robot file NAME.toml (its DH table, stops and ready pose)."""
    if name not in robot_names():
        raise RobotFileError(f"no robot {name!r}; the robots are PUMA (the thesis's, the default), "
                             f"{', '.join(robot_names())}")
    return load_dh_robot(resources.data_path(ROBOT_FOLDER, f"{name}.toml"))


def load_dh_robot(path: Path) -> DHRobot:
    """Read a robot file with a ``[dh]`` table; RobotFileError names what is wrong."""
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
        table = data["dh"]
        columns = {key: tuple(float(v) for v in table[key]) for key in ("a", "alpha", "d")}
        offset = tuple(float(v) for v in table.get("offset", [0.0] * 6))
        stops = tuple((float(lo), float(hi)) for lo, hi in data["stops"]["joints"])
        ready = tuple(float(v) for v in data["ready"]["joints"])
    except (OSError, tomllib.TOMLDecodeError, KeyError, TypeError, ValueError) as error:
        raise RobotFileError(f"{path}: not a usable robot file ({error})") from None
    if any(len(column) != 6 for column in (*columns.values(), offset, stops, ready)):
        raise RobotFileError(f"{path}: [dh] a, alpha, d, offset, [stops] and [ready] need six entries each")
    if columns["alpha"] != PUMA_TWISTS or columns["a"][0] != 0.0 or any(columns["a"][3:]) or columns["d"][4]:
        raise RobotFileError(f"{path}: the inverse kinematics solves arms of the PUMA's structure "
                             "(twists 90 0 -90 90 -90 0, a1 = 0, a spherical wrist)")
    return DHRobot(name=str(data.get("name", path.stem)), a=columns["a"], alpha=columns["alpha"], d=columns["d"],
                   offset=offset, stops=stops, ready=ready)
