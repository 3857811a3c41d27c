"""Transformations: a location as a 4x4 homogeneous matrix, and the V+ functions on them.

The thesis's locations are XW YW ZW O A T (SPEC §2); V+ adds arithmetic on them (the thesis
names FRAME and INVERSE as future work, §8.2). Every operation here composes 4x4 matrices
and reads back with the same O/A/T rules as WHERE, so a transformation built from a .LOC
location round-trips exactly.

V+ semantics followed where the thesis is silent:
- ``a:b`` (compound): b expressed in a's frame, ``a @ b``;
- ``INVERSE(a)``: the inverse transformation;
- ``RX(d) RY(d) RZ(d)``: pure rotations about the world axes, no translation;
- ``SHIFT(a BY dx, dy, dz)``: a translated along the world axes;
- ``TRANS(x, y, z)`` without angles and ``NULL``: a pure translation (identity rotation);
  with angles, the location of those six components in the thesis's O A T;
- ``FRAME(l1, l2, l3, l4)``: X axis from l1 towards l2, the XY plane through l3, origin at l4;
- ``DECOMPOSE``: the six components X Y Z O A T;
- ``DISTANCE(a, b)``, ``DX/DY/DZ(a)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from valterm.core.errors import ValtermError
from valterm.core.kinematics import Location, oat_to_rotation, rotation_to_oat


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
        """DECOMPOSE: the six components X Y Z O A T."""
        location = self.location()
        return (*location.xyz, *location.oat)

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


def trans(x: float = 0.0, y: float = 0.0, z: float = 0.0,
          o: float = 0.0, a: float = 0.0, t: float = 0.0) -> Transform:
    """TRANS(x, y, z, o, a, t): a location from its six components (omitted = 0)."""
    return Transform(_homogeneous(oat_to_rotation(o, a, t), (x, y, z)))


def translation(x: float = 0.0, y: float = 0.0, z: float = 0.0) -> Transform:
    """TRANS(x, y, z) with no angles, and NULL: a pure translation (V+'s null rotation).

    The thesis's O A T (0, 0, 0) is not the identity rotation (its tool points along -X_w),
    so an offset in a compound (``frame:TRANS(80, 0, 0):grip``) must not go through it.
    """
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
