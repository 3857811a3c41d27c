"""The drawn PUMA model: the link polyhedra of assets/robot/PUMA.SET placed at a joint vector.

Placing the whole model is one vectorised call: every vertex of every link is transformed
by its link frame at once (einsum), then split back into polyhedra.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Sequence

import numpy as np

from valterm.core.cell.polyhedron import Polyhedron
from valterm.core import resources
from valterm.core.arms import Arm, DHArm, ThesisArm, thesis_arm
from valterm.core.dh import DHRobot, dh_robot
from valterm.core.kinematics import ROBOT_FILE, RobotGeometry, robot_geometry
from valterm.core.robot_choice import ROBOT_FOLDER, THESIS_ROBOT

__all__ = ["THESIS_ROBOT", "RobotModel", "load_model", "load_robot_model"]


@dataclass(frozen=True)
class RobotModel:
    """The drawn robot: link shapes in their own frames, and the clamp's gaps."""

    geometry: RobotGeometry
    names: tuple[str, ...]
    frames: np.ndarray         # (links,) frame index of each link polyhedron
    local: tuple[np.ndarray, ...]  # per link, (2k, 3) vertices in its frame (fingers closed)
    finger_side: np.ndarray    # (links,) -1/+1 for a finger, 0 otherwise
    closed_gap: float
    open_gap: float
    # the robot that places the links (core/arms.py): the thesis's, or a robot file's DH arm
    arm: Arm = field(default_factory=thesis_arm)

    @property
    def chain(self) -> DHRobot | None:
        """A robot file's DH table, None for the thesis's robot."""
        return self.arm.chain if isinstance(self.arm, DHArm) else None

    @property
    def count(self) -> int:
        return len(self.names)

    def shapes(self, gap: float) -> list[np.ndarray]:
        """Each link's vertices in its own frame, the fingers set for this clamp gap."""
        verts = []
        for shape, side in zip(self.local, self.finger_side):
            if side:
                # each finger slides along the clamp's Y (its o axis) by half the extra gap
                shape = shape + np.array([0.0, side * (gap - self.closed_gap) / 2.0, 0.0])
            verts.append(shape)
        return verts

    def _stacked(self, gap: float) -> tuple[np.ndarray, np.ndarray]:
        verts = self.shapes(gap)
        owners = np.repeat(self.frames, [len(v) for v in verts])
        return np.concatenate(verts), owners

    def place(self, joints: Sequence[float], gap: float | None = None, base: np.ndarray | None = None) -> list[Polyhedron]:
        """The link polyhedra in world millimetres at JT1..JT6 (degrees) with the clamp gap."""
        gap = self.open_gap if gap is None else gap
        frames = self.link_frames(joints, base)
        verts, owners = self._stacked(gap)
        world = np.einsum("vij,vj->vi", frames[owners, :3, :3], verts) + frames[owners, :3, 3]
        split = np.cumsum([len(v) for v in self.local])[:-1]
        return [Polyhedron(v, name) for v, name in zip(np.split(world, split), self.names)]

    def link_frames(self, joints: Sequence[float], base: np.ndarray | None = None) -> np.ndarray:
        """The seven (4, 4) link frames in world coordinates at JT1..JT6 (degrees)."""
        frames = self.arm.link_frames(joints)
        return frames if base is None else base @ frames

    def link_frames_batch(self, joints: np.ndarray, base: np.ndarray | None = None) -> np.ndarray:
        """``link_frames`` of (n, 6) poses at once, (n, 7, 4, 4): the same numbers, pose by pose."""
        frames = self.arm.link_frames_batch(np.asarray(joints, dtype=float).reshape(-1, 6))
        return frames if base is None else base @ frames

    def clamp_frame(self, joints: Sequence[float], base: np.ndarray | None = None) -> np.ndarray:
        """The 4x4 clamp frame (R6, origin at the wrist centre) in world coordinates."""
        frame: np.ndarray = self.link_frames(joints)[6]
        return frame if base is None else base @ frame

    def led_segment(self, joints: Sequence[float], gap: float | None = None,
                    base: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """The LED sensor: a segment across the finger gap, 25.4 mm beyond the TCS origin (§2.5)."""
        gap = self.open_gap if gap is None else gap
        frame = self.clamp_frame(joints, base)
        along = self.geometry.d6 + self.geometry.led_sensor
        half = gap / 2.0
        ends = np.array([[0.0, -half, along, 1.0], [0.0, half, along, 1.0]]) @ frame.T
        return ends[0, :3], ends[1, :3]


def load_model(file: tuple[str, str] = ROBOT_FILE, geometry: RobotGeometry | None = None) -> RobotModel:
    """Read a bundled robot file's model (``file``: its folder and name under the package
    data, the thesis's PUMA by default) and its setup-form geometry."""
    geometry = geometry or robot_geometry()
    from valterm.core.files.setup import read_setup  # the same reader as any setup file

    data = resources.read_toml(*file)["model"]
    path = resources.data_path(*file)
    cell = read_setup(path.parent / data["geometry"], checked=False)  # the links' vertices only
    names = tuple(data["names"])
    frames = np.asarray(data["frames"], dtype=int)
    sides = np.asarray(data["finger_side"], dtype=int)
    if not (len(names) == len(frames) == len(sides) == len(cell.objects)):
        raise ValueError(f"{path}: names, frames and finger_side need one entry per object of {data['geometry']}")
    return RobotModel(
        arm=thesis_arm() if geometry is robot_geometry() else ThesisArm(geometry),
        geometry=geometry,
        names=names,
        frames=frames,
        local=tuple(p.vertices for p in cell.objects),
        finger_side=sides,
        closed_gap=float(data["closed_gap"]),
        open_gap=float(data["open_gap"]),
    )


def load_robot_model(name: str = THESIS_ROBOT) -> RobotModel:
    """The drawn robot a robot file names: the thesis's (PUMA) or a DH robot file's (PUMA560).

    A DH robot's links are placed by its own chain; its ``geometry`` carries only what the
    drawing and the readouts take from it (stops, ready pose, name, frame 6 at the flange
    with no clamp): the thesis's kinematics are never run on it."""
    if name.upper() == THESIS_ROBOT:
        return load_model()
    chain = dh_robot(name.upper())
    file = (ROBOT_FOLDER, f"{name.upper()}.toml")
    geometry = RobotGeometry(a2=chain.a[1], d2=chain.d[2], d4=chain.d[3], d6=chain.d[5], led_sensor=0.0,
                             clamp_tip=0.0, stops=chain.stops, ready=chain.ready, name=chain.name,
                             model_geometry=str(resources.read_toml(*file)["model"]["geometry"]))
    return replace(load_model(file, geometry), arm=DHArm(chain, name.upper()))
