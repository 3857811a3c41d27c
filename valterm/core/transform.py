"""Transformations: a location as a 4x4 homogeneous matrix, and the V+ functions on them.

The matrix is the tool's pose in the world: the rotation's columns are the tool's n, o, a
axes (a, the approach, is the tool's Z) and the last column its position. Both dialects
mean the same pose by a location; they write its orientation differently:

- the thesis (1985 dialect, WHERE, .LOC files): X Y Z and O A T (SPEC §2,
  ``kinematics.oat_to_rotation``; O A T (0, 0, 0) has the tool along -X of the world);
- V+ (Adept V+ reference: TRANS, DECOMPOSE, WHERE): X Y Z and yaw, pitch, roll, Z-Y-Z
  Euler angles: R = RZ(yaw) RY(pitch) RZ(roll), so (0, 0, 0), the null transformation,
  has the tool's Z along the world's Z, and pitch 180 points the tool straight down.

``convert_orientation`` is the one conversion between the two; ``Transform.location()``
gives the Location (O A T) the simulator stores, so a workspace location used by both
dialects is the same pose.

V+ semantics (the thesis names FRAME and INVERSE as future work, §8.2):
- ``a:b`` (compound): b expressed in a's frame, ``a @ b``;
- ``INVERSE(a)``: the inverse transformation;
- ``RX(d) RY(d) RZ(d)``: pure rotations about the axes, no translation;
- ``SHIFT(a BY dx, dy, dz)``: a translated along the world axes;
- ``TRANS(x, y, z, yaw, pitch, roll)`` (omitted = 0) and ``NULL`` (all 0, the identity);
- ``FRAME(l1, l2, l3, l4)``: X axis from l1 towards l2, the XY plane through l3, origin at l4;
- ``DECOMPOSE``: the six components X Y Z yaw pitch roll;
- ``DISTANCE(a, b)``, ``DX/DY/DZ(a)``.

Reporting rules for yaw pitch roll (the same angles as WHERE shows in V+): pitch in
[0, 180], yaw and roll in (-180, 180]; with pitch 0 or 180 only yaw +- roll is defined,
and yaw is reported as 0 (roll carries the whole turn): ``TRANS(x, y, z, 0, 180, r)``, the
usual tool-down location, reads back as written.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from valterm.core.errors import ValtermError
from valterm.core.kinematics import GIMBAL_EPS, Location, oat_to_rotation, rotation_to_oat, wrap180

Angles = tuple[float, float, float]
CONVENTIONS = ("OAT", "YPR")  # the thesis's O A T; V+'s yaw pitch roll


class TransformError(ValtermError):
    """A transformation that cannot be built (FRAME of collinear points, a non-finite value)."""


@dataclass(frozen=True)
class Transform:
    """A rigid transformation: ``matrix`` is 4x4, rotation columns n o a and the position."""

    matrix: np.ndarray

    @classmethod
    def of(cls, location: Location) -> Transform:
        return cls(_homogeneous(oat_to_rotation(*location.oat), location.xyz))

    @property
    def xyz(self) -> tuple[float, float, float]:
        x, y, z = (float(v) for v in self.matrix[:3, 3])
        return x, y, z

    @property
    def rotation(self) -> np.ndarray:
        return self.matrix[:3, :3]

    def location(self) -> Location:
        """Back to X Y Z O A T with WHERE's reporting rules."""
        return Location(self.xyz, rotation_to_oat(self.rotation))

    def decompose(self) -> tuple[float, float, float, float, float, float]:
        """DECOMPOSE: the six components X Y Z yaw pitch roll (V+)."""
        return (*self.xyz, *rotation_to_ypr(self.rotation))

    def __matmul__(self, other: Transform) -> Transform:
        """``a:b``: b expressed in a's frame."""
        return Transform(self.matrix @ other.matrix)


def _homogeneous(rotation: np.ndarray, xyz: tuple[float, float, float] | np.ndarray) -> np.ndarray:
    values = np.asarray(xyz, dtype=float)
    if not (np.isfinite(values).all() and np.isfinite(rotation).all()):
        raise TransformError("a transformation needs finite numbers")
    matrix = np.eye(4)
    matrix[:3, :3] = rotation
    matrix[:3, 3] = values
    return matrix


def ypr_to_rotation(yaw: float, pitch: float, roll: float) -> np.ndarray:
    """V+'s orientation: RZ(yaw) RY(pitch) RZ(roll), degrees (Z-Y-Z Euler angles)."""
    rotation: np.ndarray = rz(yaw).rotation @ ry(pitch).rotation @ rz(roll).rotation
    return rotation


def rotation_to_ypr(rotation: np.ndarray) -> Angles:
    """Yaw, pitch, roll (degrees) of a rotation, with the reporting rules above."""
    r = np.asarray(rotation, dtype=float)
    sin_pitch = math.hypot(r[0, 2], r[1, 2])
    pitch = math.degrees(math.atan2(sin_pitch, r[2, 2]))
    if sin_pitch < GIMBAL_EPS:  # the tool's Z along +-world Z: only yaw +- roll is defined
        # yaw 0: RY(0 or 180) RZ(roll) has (sin roll, cos roll) in its second row either way
        roll = math.degrees(math.atan2(r[1, 0], r[1, 1]))
        return (0.0, _tidy(pitch), _tidy(wrap180(roll)))
    yaw = math.degrees(math.atan2(r[1, 2], r[0, 2]))
    roll = math.degrees(math.atan2(r[2, 1], -r[2, 0]))
    return (_tidy(wrap180(yaw)), _tidy(pitch), _tidy(wrap180(roll)))


def _tidy(angle: float) -> float:
    """-0.0 and rounding noise next to 0 read as 0 (a readout never shows -0.00)."""
    return 0.0 if abs(angle) < 1e-9 else angle


def convert_orientation(angles: Angles, source: str, target: str) -> Angles:
    """The one conversion between the thesis's O A T and V+'s yaw pitch roll (degrees).

    ``source`` and ``target`` are "OAT" or "YPR"; the pose is the same, only its three
    angles change (each side read back with its own reporting rules).
    """
    for convention in (source, target):
        if convention not in CONVENTIONS:
            raise TransformError(f"{convention!r} is not an orientation convention (OAT or YPR)")
    rotation = oat_to_rotation(*angles) if source == "OAT" else ypr_to_rotation(*angles)
    return rotation_to_oat(rotation) if target == "OAT" else rotation_to_ypr(rotation)


def trans(x: float = 0.0, y: float = 0.0, z: float = 0.0,
          yaw: float = 0.0, pitch: float = 0.0, roll: float = 0.0) -> Transform:
    """TRANS(x, y, z, yaw, pitch, roll): a location from its six V+ components (omitted = 0)."""
    return Transform(_homogeneous(ypr_to_rotation(yaw, pitch, roll), (x, y, z)))


def translation(x: float = 0.0, y: float = 0.0, z: float = 0.0) -> Transform:
    """TRANS(x, y, z) and NULL: a pure translation (V+'s null rotation, the identity)."""
    return Transform(_homogeneous(np.eye(3), (x, y, z)))


def _axis_rotation(axis: int, degrees: float) -> Transform:
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    u, v = [(1, 2), (2, 0), (0, 1)][axis]
    rotation = np.eye(3)
    rotation[u, u], rotation[u, v], rotation[v, u], rotation[v, v] = c, -s, s, c
    return Transform(_homogeneous(rotation, (0.0, 0.0, 0.0)))


def rx(degrees: float) -> Transform:
    return _axis_rotation(0, degrees)


def ry(degrees: float) -> Transform:
    return _axis_rotation(1, degrees)


def rz(degrees: float) -> Transform:
    return _axis_rotation(2, degrees)


def inverse(transform: Transform) -> Transform:
    """INVERSE(a): R^T and -R^T p (a rigid transformation's inverse)."""
    rotation = transform.rotation.T
    return Transform(_homogeneous(rotation, -rotation @ transform.matrix[:3, 3]))


def shift(transform: Transform, dx: float = 0.0, dy: float = 0.0, dz: float = 0.0) -> Transform:
    """SHIFT(a BY dx, dy, dz): translated along the world axes, orientation kept."""
    return Transform(_homogeneous(transform.rotation, transform.matrix[:3, 3] + np.array([dx, dy, dz])))


def frame(l1: Transform, l2: Transform, l3: Transform, l4: Transform) -> Transform:
    """FRAME(l1, l2, l3, l4): X from l1 towards l2, Y in the plane of l3, origin at l4."""
    p1, p2, p3 = (np.asarray(t.xyz) for t in (l1, l2, l3))
    x = p2 - p1
    if np.linalg.norm(x) < 1e-9:
        raise TransformError("FRAME needs two distinct points for its X axis")
    x = x / np.linalg.norm(x)
    towards = p3 - p1
    y = towards - np.dot(towards, x) * x
    if np.linalg.norm(y) < 1e-9:
        raise TransformError("FRAME needs a third point off the X axis")
    y = y / np.linalg.norm(y)
    return Transform(_homogeneous(np.column_stack([x, y, np.cross(x, y)]), np.asarray(l4.xyz)))


def distance(a: Transform, b: Transform) -> float:
    """DISTANCE(a, b): between the two positions, mm."""
    return float(np.linalg.norm(a.matrix[:3, 3] - b.matrix[:3, 3]))


def scale(transform: Transform, factor: float) -> Transform:
    """SCALE(a BY s): the position multiplied by s, the orientation kept (V+)."""
    return Transform(_homogeneous(transform.rotation, transform.matrix[:3, 3] * factor))


def normalized(transform: Transform) -> Transform:
    """NORM(a): the rotation made orthonormal again (V+), the position kept: the approach
    vector a keeps its direction, o is made perpendicular to it in the plane of o and a,
    and n = o x a completes the right-handed frame."""
    approach, orientation = transform.rotation[:, 2], transform.rotation[:, 1]
    size = np.linalg.norm(approach)
    if size < 1e-12:
        raise TransformError("NORM needs a transformation with an approach vector")
    a = approach / size
    o = orientation - np.dot(orientation, a) * a
    if np.linalg.norm(o) < 1e-12:
        raise TransformError("NORM needs an orientation vector off the approach vector")
    o = o / np.linalg.norm(o)
    return Transform(_homogeneous(np.column_stack([np.cross(o, a), o, a]), transform.matrix[:3, 3]))
