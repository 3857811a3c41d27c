"""PUMA kinematics: forward, inverse (Lee's geometric solution), O/A/T and indicators.

Everything here follows SPEC section 2. Angles users see and type are degrees in the
PUMA convention; inside, the scalar fast paths use radians and the ``math`` module
(one call must cost microseconds), and the batch versions take numpy arrays of poses.

Frames: WCS millimetres, Z up, origin where joint axes 1 and 2 meet.
"""

from __future__ import annotations

import math
import struct
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import NamedTuple, Protocol, Sequence

import numpy as np

from functools import lru_cache
# ik_fast calls these by their bare names: one lookup less a call on ik's hot path (issue 25)
from math import asin, atan2, cos, hypot, isfinite, pi, sin, sqrt

from valterm.core.errors import RefusedValue, ValtermError
from valterm.core import resources

ROBOT_FILE = ("robot", "PUMA.toml")  # under the package data (core/resources.py)

# R6 = Rz(O) . Rx(A) . Ry(-T) . C  (SPEC section 2)
ORIENTATION_BASE = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, -1.0], [-1.0, 0.0, 0.0]])

# Below this |cos A| the O/A/T decomposition is at gimbal lock and T is reported as 0.
GIMBAL_EPS = 1e-9
# Below this sin JT5 the wrist is singular (JT4 and JT6 turn about one axis).
WRIST_EPS = 1e-9
# Within these of a boundary an indicator is tied and reads positive (SPEC §2, READY).
TIE = 1e-9
TIE_MM = 1e-6
# How far past full stretch (or full fold) the elbow equation may be and still count as it:
# 1e-4 of k is about 0.02 mm of the PUMA 560's reach. A point taught with the arm stretched
# (READY, then DRIVE 1 or 2) and stored in a .LOC file's 2 decimals lies up to 0.01 mm
# beyond the reach (and the orientation's 2 decimals move the wrist 0.005 mm): it is reached.
REACH_SLACK = 1e-4

# ik's stop fit: fit_to_stops' tolerance on the whole-turn count (1e-12 turn), in degrees
_FIT_TOL = 3.6e-10


# ik's stop fit of one joint: low - tol, high + tol, low, high, angle - 360 / + 360 may fit
_StopFit = tuple[float, float, float, float, bool, bool]
# how far inside the edges _settled keeps: far beyond rounding (1e-13 degree), far below
# anything that matters to the speed (the whole fit still runs on the angles left out)
_SETTLED_MARGIN = 1e-6


def _settled(lo: float, hi: float, low: float, high: float) -> tuple[float, float]:
    """The angles ik's stop fit leaves as they are with no work: inside the stops and
    (-180, 180] (nothing to clamp or wrap) and with no 360-degree equivalent inside [lo, hi]
    (nothing to choose), each edge ``_SETTLED_MARGIN`` inside so that rounding in angle -+ 360
    cannot matter. JT1 and JT5: their whole stops; JT4 and JT6: about +-94 degrees."""
    return (max(low, -180.0 + _SETTLED_MARGIN, hi - 360.0 + _SETTLED_MARGIN),
            min(high, 180.0, lo + 360.0 - _SETTLED_MARGIN))


@dataclass(frozen=True)
class RobotGeometry:
    """Link lengths, tool offsets and joint stops of the PUMA (from the robot model file)."""

    a2: float
    d2: float
    d4: float
    d6: float
    led_sensor: float
    clamp_tip: float
    stops: tuple[tuple[float, float], ...]
    ready: tuple[float, ...]
    model_geometry: str = "PUMA.SET"
    name: str = "PUMA 600"  # as the robot file names it (STATUS, --json)
    stops_array: np.ndarray = field(init=False, repr=False, compare=False)
    # ik's stop fit per joint (``_fit_turns``), made once: the angles that are their own fit
    # (``_settled``), then the whole fit's low - tol, high + tol, low, high, and whether
    # angle - 360 / angle + 360 can fall inside at all (stops beyond -180 / 180)
    fit_bounds: tuple[tuple[float, float, _StopFit], ...] = field(init=False, repr=False, compare=False)
    # ik_fast's lengths in one tuple, made once: d2, a2, d4, d6 and the constant products of
    # Lee's solution (d2^2, a2^2, d4^2, 2 a2 d4; the same floats as computed in place)
    lee_terms: tuple[float, float, float, float, float, float, float, float] = field(
        init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "stops_array", np.array(self.stops, dtype=float))
        d2, a2, d4 = self.d2, self.a2, self.d4
        object.__setattr__(self, "lee_terms", (d2, a2, d4, self.d6, d2 * d2, a2 * a2, d4 * d4, 2.0 * a2 * d4))
        object.__setattr__(self, "fit_bounds", tuple(
            (*_settled(low - _FIT_TOL, high + _FIT_TOL, low, high),
             (low - _FIT_TOL, high + _FIT_TOL, low, high, low - _FIT_TOL <= -180.0, high + _FIT_TOL > 180.0))
            for low, high in self.stops))

    def point_offset(self, point: int) -> float:
        """Distance beyond the wrist centre along a of position option 1, 2 or 3 (§3.4)."""
        if point == 1:
            return self.d6
        if point == 2:
            return self.d6 + self.led_sensor
        if point == 3:
            return self.d6 + self.clamp_tip
        raise RefusedValue(f"position option must be 1, 2 or 3, not {point}")


def load_robot(path: Path | None = None) -> RobotGeometry:
    """Read the robot model file (TOML); the bundled PUMA's when no path is given."""
    data = resources.read_toml(*ROBOT_FILE) if path is None else tomllib.loads(path.read_text(encoding="utf-8"))
    path = path or resources.data_path(*ROBOT_FILE)
    links, tool = data["links"], data["tool"]
    stops = tuple((float(lo), float(hi)) for lo, hi in data["stops"]["joints"])
    if len(stops) != 6 or any(lo >= hi for lo, hi in stops):
        raise ValueError(f"{path}: [stops] joints must hold six [low, high] pairs")
    return RobotGeometry(
        a2=float(links["a2"]),
        d2=float(links["d2"]),
        d4=float(links["d4"]),
        d6=float(links["d6"]),
        led_sensor=float(tool["led_sensor"]),
        clamp_tip=float(tool["clamp_tip"]),
        stops=stops,
        ready=tuple(float(v) for v in data["ready"]["joints"]),
        model_geometry=str(data.get("model", {}).get("geometry", "PUMA.SET")),
        name=str(data.get("name", "PUMA 600")),
    )


@lru_cache(maxsize=1)
def robot_geometry() -> RobotGeometry:
    """The bundled PUMA's geometry, read on first use (never at import time)."""
    return load_robot()


# ---------------------------------------------------------------------------
# Configuration indicators
# ---------------------------------------------------------------------------

class Config(NamedTuple):
    """The three configuration indicators: +1 = RIGHTY / ABOVE / NOFLIP, -1 = LEFTY / BELOW / FLIP."""

    arm: int = 1
    elbow: int = 1
    wrist: int = 1

    @property
    def words(self) -> tuple[str, str, str]:
        return (
            "RIGHTY" if self.arm > 0 else "LEFTY",
            "ABOVE" if self.elbow > 0 else "BELOW",
            "NOFLIP" if self.wrist > 0 else "FLIP",
        )

    def as_dict(self) -> dict[str, str]:
        arm, elbow, wrist = self.words
        return {"arm": arm, "elbow": elbow, "wrist": wrist}

    def __str__(self) -> str:
        return ",".join(self.words)

    @classmethod
    def parse(cls, text: str) -> "Config":
        """Parse ``LEFTY,ABOVE,NOFLIP`` (any order, commas or spaces, unique prefixes)."""
        words = [w for w in text.replace(",", " ").upper().split() if w]
        arm, elbow, wrist = 1, 1, 1
        seen: set[str] = set()
        for word in words:
            matches = [name for name in _INDICATORS if name.startswith(word)]
            if len(matches) != 1:
                raise RefusedValue(
                    f"{word!r} is not a configuration indicator ({', '.join(CONFIG_WORDS)})"
                )
            kind, value = _INDICATORS[matches[0]]
            if kind in seen:
                raise RefusedValue(f"{text!r} names the {kind} indicator twice")
            seen.add(kind)
            if kind == "arm":
                arm = value
            elif kind == "elbow":
                elbow = value
            else:
                wrist = value
        return cls(arm, elbow, wrist)


_INDICATORS = {
    "RIGHTY": ("arm", 1),
    "LEFTY": ("arm", -1),
    "ABOVE": ("elbow", 1),
    "BELOW": ("elbow", -1),
    "NOFLIP": ("wrist", 1),
    "FLIP": ("wrist", -1),
}

#: The configuration words (VAL-II commands and indicator names), the one list of them.
CONFIG_WORDS: tuple[str, ...] = tuple(_INDICATORS)


def indicator_kind(word: str) -> str:
    """`arm`, `elbow` or `wrist`: which indicator a configuration word (or unique prefix) sets."""
    word = word.strip().upper()
    matches = [w for w in CONFIG_WORDS if w.startswith(word)]
    if len(matches) != 1:
        raise RefusedValue(f"{word!r} is not a configuration indicator")
    return _INDICATORS[matches[0]][0]


# ---------------------------------------------------------------------------
# Angles
# ---------------------------------------------------------------------------

def wrap180(angle: float) -> float:
    """Wrap degrees to (-180, 180] so the same pose always reads the same (§6.1.2)."""
    wrapped = math.fmod(angle, 360.0)
    if wrapped <= -180.0:
        wrapped += 360.0
    elif wrapped > 180.0:
        wrapped -= 360.0
    return wrapped


def shown_angle(angle: float) -> float:
    """A joint as the 1985 rules show it (SPEC §3a, the thesis's figures): in (-180, 180] at
    the readout's two decimals (Fig. 2-8a1's JT2 172.08, held as -187.92 inside the stop
    -225..45; -179.999 is shown 180.00)."""
    wrapped = wrap180(angle)
    return 180.0 if round(wrapped, 2) == -180.0 else wrapped


def joints_between(start: Sequence[float], end: Sequence[float], fraction: float) -> tuple[float, ...]:
    """The pose ``fraction`` of the way from ``start`` to ``end``, each joint along its shortest
    turn (the 1985 rules keep angles in (-180, 180]: 179 -> -179 is a 2-degree step, not 358)."""
    return tuple(float(a) + wrap180(float(b) - float(a)) * fraction for a, b in zip(start, end))


def wrap180_array(angles: np.ndarray) -> np.ndarray:
    wrapped = np.fmod(angles, 360.0)
    wrapped = np.where(wrapped <= -180.0, wrapped + 360.0, wrapped)
    result: np.ndarray = np.where(wrapped > 180.0, wrapped - 360.0, wrapped)
    return result


class IKError(ValtermError):
    """A location the robot cannot take; ``reason`` is what WHERE-style messages print."""

    joint: int = 0
    reason: str = "no solution"

    def __init__(self, message: str | None = None) -> None:
        super().__init__(message or self.reason)


class OutOfReach(IKError):
    reason = "out of reach"


class BeyondStop(IKError):
    def __init__(self, joint: int, angle: float, stop: tuple[float, float] | None = None) -> None:
        self.joint = joint
        self.angle = angle
        self.stop = stop
        self.reason = f"joint {joint} beyond its stop"
        limits = f", stop {stop[0]:g}..{stop[1]:g}" if stop is not None else ""
        # the message names the angle and the stop, as a refused straight line does
        super().__init__(f"{self.reason} ({angle:.2f} deg{limits})")


class HasStops(Protocol):
    """A robot's joint stops: the thesis's RobotGeometry, or a DH robot file's (core/dh.py)."""

    @property
    def stops(self) -> tuple[tuple[float, float], ...]: ...


def fit_to_stops(
    joints: Sequence[float],
    current: Sequence[float] | None = None,
    geometry: HasStops | None = None,
) -> list[float]:
    """The 360-degree equivalent of each joint within its stops nearest the current angle.

    Raises BeyondStop for the first joint with no equivalent within its stops.
    """
    geometry = geometry or robot_geometry()
    fitted = []
    for index, angle in enumerate(joints):
        low, high = geometry.stops[index]
        near = angle if current is None else current[index]
        # candidates angle + 360k inside [low, high]
        k_low = math.ceil((low - angle) / 360.0 - 1e-12)
        k_high = math.floor((high - angle) / 360.0 + 1e-12)
        if k_low > k_high:  # named as given (230 typed beside the stop 225, not -130)
            raise BeyondStop(index + 1, angle if abs(angle) <= 360.0 else wrap180(angle), (low, high))
        best = None
        for k in range(k_low, k_high + 1):
            candidate = angle + 360.0 * k
            if best is None or abs(candidate - near) < abs(best - near):
                best = candidate
        assert best is not None
        fitted.append(min(max(best, low), high))
    return fitted


def canonical_angle(angle: float, low: float, high: float) -> float | None:
    """The 1985 rules' angle (SPEC §3a): the 360-degree equivalent of ``angle`` inside
    [low, high], the one in (-180, 180] where two are; None when no equivalent is inside."""
    wrapped = wrap180(angle)
    return equivalent_inside(wrapped, low, high, wrapped, 1e-9)


def equivalent_inside(angle: float, low: float, high: float, near: float, tol: float) -> float | None:
    """Of ``angle`` (wrapped to (-180, 180]) and its +-360 equivalents, the one inside
    [low, high] (``tol`` of slack) nearest ``near``, clamped to the stops; None when none is.
    Only those three can lie inside stops narrower than 720 degrees; ties go to the lower
    (fit_to_stops' order)."""
    best = None
    for candidate in (angle - 360.0, angle, angle + 360.0):
        if low - tol <= candidate <= high + tol and (best is None or abs(candidate - near) < abs(best - near)):
            best = candidate
    if best is None:
        return None
    return low if best < low else high if best > high else best


def canonical_joints(joints: Sequence[float], geometry: HasStops | None = None) -> list[float]:
    """Each joint as the 1985 rules show it (``canonical_angle``); BeyondStop for the first
    joint with no equivalent inside its stops (named by the angle as it would be shown)."""
    geometry = geometry or robot_geometry()
    shown = []
    for index, (angle, (low, high)) in enumerate(zip(joints, geometry.stops)):
        canonical = canonical_angle(float(angle), low, high)
        if canonical is None:
            raise BeyondStop(index + 1, wrap180(float(angle)), (low, high))
        shown.append(canonical)
    return shown


def readout_joints(joints: Sequence[float], geometry: HasStops | None = None) -> list[float]:
    """Angles as a readout prints them: inside the stops where an equivalent is (JT3 215.04,
    not -144.96), else the geometric angle wrapped to (-180, 180] (``kin ik`` flags those)."""
    geometry = geometry or robot_geometry()
    shown = []
    for angle, (low, high) in zip(joints, geometry.stops):
        canonical = canonical_angle(float(angle), low, high)
        shown.append(wrap180(float(angle)) if canonical is None else canonical)
    return shown


# ---------------------------------------------------------------------------
# Orientation: O, A, T
# ---------------------------------------------------------------------------

def _rz(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _rx(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _ry(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def oat_to_rotation(o: float, a: float, t: float) -> np.ndarray:
    """The tool rotation (columns n, o, a) of O, A, T in degrees."""
    rotation: np.ndarray = _rz(math.radians(o)) @ _rx(math.radians(a)) @ _ry(-math.radians(t)) @ ORIENTATION_BASE
    return rotation


def oat_to_rotation_array(oat: np.ndarray) -> np.ndarray:
    """Batch O, A, T (n, 3) degrees -> rotations (n, 3, 3)."""
    o, a, t = np.radians(np.asarray(oat, dtype=float)).T
    co, so, ca, sa, cb, sb = np.cos(o), np.sin(o), np.cos(a), np.sin(a), np.cos(-t), np.sin(-t)
    q = np.empty((len(co), 3, 3))
    # Q = Rz(O) Rx(A) Ry(beta), beta = -T
    q[:, 0, 0] = co * cb - so * sa * sb
    q[:, 0, 1] = -so * ca
    q[:, 0, 2] = co * sb + so * sa * cb
    q[:, 1, 0] = so * cb + co * sa * sb
    q[:, 1, 1] = co * ca
    q[:, 1, 2] = so * sb - co * sa * cb
    q[:, 2, 0] = -ca * sb
    q[:, 2, 1] = sa
    q[:, 2, 2] = ca * cb
    rotations: np.ndarray = q @ ORIENTATION_BASE
    return rotations


def rotation_to_oat(rotation: np.ndarray | Sequence[Sequence[float]]) -> tuple[float, float, float]:
    """O, A, T in degrees of a tool rotation, with the reporting rules of SPEC section 2.

    O is kept in [0, 180) using the equivalent (O+-180, 180-A, T-180); angles are wrapped
    to (-180, 180]; at gimbal lock (A = +-90) T is reported as 0.
    """
    r = rotation
    # Q = R6 . C^T = Rz(O) Rx(A) Ry(-T): Q[:,0] = o, Q[:,1] = -a, Q[:,2] = -n
    q00, q01 = r[0][1], -r[0][2]
    q10, q11 = r[1][1], -r[1][2]
    q20, q21, q22 = r[2][1], -r[2][2], -r[2][0]
    sin_a = max(-1.0, min(1.0, q21))
    cos_a = math.hypot(q01, q11)
    if cos_a < GIMBAL_EPS:
        a = 90.0 if sin_a > 0 else -90.0
        o = math.degrees(math.atan2(q10, q00))
        # only O+-T is defined here; with T = 0, O carries the whole turn, wrapped
        return (wrap180(o), a, 0.0)
    o = math.degrees(math.atan2(-q01, q11))
    a = math.degrees(math.atan2(sin_a, cos_a))
    t = -math.degrees(math.atan2(-q20, q22))
    o, a, t = wrap180(o), wrap180(a), wrap180(t)
    if not 0.0 <= o < 180.0:
        o, a, t = wrap180(o + 180.0), wrap180(180.0 - a), wrap180(t - 180.0)
    return (o, a, t)


# ---------------------------------------------------------------------------
# Forward kinematics
# ---------------------------------------------------------------------------

class Pose(NamedTuple):
    """A tool pose: position (mm, WCS) and rotation (columns n, o, a)."""

    xyz: np.ndarray
    rotation: np.ndarray

    @property
    def oat(self) -> tuple[float, float, float]:
        return rotation_to_oat(self.rotation)


def fk_fast(
    j1: float, j2: float, j3: float, j4: float, j5: float, j6: float,
    offset: float | None = None, geometry: RobotGeometry | None = None,
) -> tuple[float, ...]:
    """Forward kinematics on radians: (x, y, z, n0, n1, n2, o0, o1, o2, a0, a1, a2).

    The scalar fast path: plain floats and ``math`` only.
    """
    geometry = geometry or robot_geometry()
    offset = geometry.d6 if offset is None else offset
    c1, s1 = math.cos(j1), math.sin(j1)
    c2, s2 = math.cos(j2), math.sin(j2)
    c23, s23 = math.cos(j2 + j3), math.sin(j2 + j3)
    c4, s4 = math.cos(j4), math.sin(j4)
    c5, s5 = math.cos(j5), math.sin(j5)
    c6, s6 = math.cos(j6), math.sin(j6)
    # wrist centre in the waist frame (e2 = -JT2, e3 = 90 - JT2 - JT3)
    u = geometry.a2 * c2 + geometry.d4 * s23
    v = geometry.d2
    w = -geometry.a2 * s2 + geometry.d4 * c23
    # W = Rz4 Ry5 Rz6, columns
    w0x, w0y, w0z = c4 * c5 * c6 - s4 * s6, s4 * c5 * c6 + c4 * s6, -s5 * c6
    w1x, w1y, w1z = -c4 * c5 * s6 - s4 * c6, -s4 * c5 * s6 + c4 * c6, s5 * s6
    w2x, w2y, w2z = c4 * s5, s4 * s5, c5
    # R03 = Rz1 Ry23 = [[c1c23, -s1, c1s23], [s1c23, c1, s1s23], [-s23, 0, c23]]
    r00, r01, r02 = c1 * c23, -s1, c1 * s23
    r10, r11, r12 = s1 * c23, c1, s1 * s23
    r20, r22 = -s23, c23
    nx = r00 * w0x + r01 * w0y + r02 * w0z
    ny = r10 * w0x + r11 * w0y + r12 * w0z
    nz = r20 * w0x + r22 * w0z
    ox = r00 * w1x + r01 * w1y + r02 * w1z
    oy = r10 * w1x + r11 * w1y + r12 * w1z
    oz = r20 * w1x + r22 * w1z
    ax = r00 * w2x + r01 * w2y + r02 * w2z
    ay = r10 * w2x + r11 * w2y + r12 * w2z
    az = r20 * w2x + r22 * w2z
    x = c1 * u - s1 * v + offset * ax
    y = s1 * u + c1 * v + offset * ay
    z = w + offset * az
    return (x, y, z, nx, ny, nz, ox, oy, oz, ax, ay, az)


def fk(joints: Sequence[float], point: int = 1, geometry: RobotGeometry | None = None) -> Pose:
    """Forward kinematics of JT1..JT6 (degrees, PUMA convention) to position option 1, 2 or 3."""
    geometry = geometry or robot_geometry()
    j1, j2, j3, j4, j5, j6 = (math.radians(j) for j in joints)
    r = fk_fast(j1, j2, j3, j4, j5, j6, offset=geometry.point_offset(point), geometry=geometry)
    rotation = np.array([[r[3], r[6], r[9]], [r[4], r[7], r[10]], [r[5], r[8], r[11]]])
    return Pose(np.array(r[:3]), rotation)


def fk_batch(joints: np.ndarray, point: int = 1, geometry: RobotGeometry | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Batch forward kinematics: joints (n, 6) degrees -> xyz (n, 3), rotations (n, 3, 3).

    The tool frame only (``fk_fast`` on arrays), not the seven link frames: what a batch of
    poses needs, at a fraction of the memory.
    """
    geometry = geometry or robot_geometry()
    all_joints = np.asarray(joints, dtype=float).reshape(-1, 6)
    n = len(all_joints)
    xyz = np.empty((n, 3))
    rot = np.empty((n, 3, 3))
    for lo in range(0, n, BATCH_CHUNK):   # in chunks: temporaries stay in cache
        part = slice(lo, lo + BATCH_CHUNK)
        _fk_chunk(all_joints[part], geometry.point_offset(point), geometry, xyz[part], rot[part])
    return xyz, rot


def _fk_chunk(joints: np.ndarray, offset: float, geometry: RobotGeometry, xyz: np.ndarray, rot: np.ndarray) -> None:
    """``fk_batch`` of one chunk, written into ``xyz`` and ``rot``."""
    q = np.radians(joints.T, order="C")   # one contiguous row per joint: no strided ufuncs
    c, s = np.cos(q), np.sin(q)
    c1, s1, c2, s2, c4, s4, c5, s5, c6, s6 = c[0], s[0], c[1], s[1], c[3], s[3], c[4], s[4], c[5], s[5]
    q23 = q[1] + q[2]
    c23, s23 = np.cos(q23), np.sin(q23)
    u = geometry.a2 * c2 + geometry.d4 * s23
    w = geometry.d4 * c23 - geometry.a2 * s2
    # W = Rz4 Ry5 Rz6 as columns, then R = Rz1 Ry23 W (see fk_fast)
    c5c6, c5s6 = c5 * c6, c5 * s6
    wcols = ((c4 * c5c6 - s4 * s6, s4 * c5c6 + c4 * s6, -s5 * c6),
             (-c4 * c5s6 - s4 * c6, c4 * c6 - s4 * c5s6, s5 * s6),
             (c4 * s5, s4 * s5, c5))
    r00, r10, r20 = c1 * c23, s1 * c23, -s23
    r02, r12 = c1 * s23, s1 * s23
    for col, (wx, wy, wz) in enumerate(wcols):
        rot[:, 0, col] = r00 * wx - s1 * wy + r02 * wz
        rot[:, 1, col] = r10 * wx + c1 * wy + r12 * wz
        rot[:, 2, col] = r20 * wx + c23 * wz
    xyz[:, 0] = c1 * u - s1 * geometry.d2 + offset * rot[:, 0, 2]
    xyz[:, 1] = s1 * u + c1 * geometry.d2 + offset * rot[:, 1, 2]
    xyz[:, 2] = w + offset * rot[:, 2, 2]


def link_frames(joints: Sequence[float], geometry: RobotGeometry | None = None) -> np.ndarray:
    """The seven link frames of one pose (JT1..JT6 degrees) as (7, 4, 4): ``link_frames_batch``
    for a single pose, on Python floats, each number by the same operations (a zero included:
    its sign too), written out (no tuples built on the way) into one array at the end."""
    geometry = geometry or robot_geometry()
    q1, q2, q3, q4, q5, q6 = [math.radians(float(j)) for j in joints]
    cos, sin = math.cos, math.sin
    c1, s1, c2, s2, c23, s23 = cos(q1), sin(q1), cos(q2), sin(q2), cos(q2 + q3), sin(q2 + q3)
    c4, s4, c5, s5, c6, s6 = cos(q4), sin(q4), cos(q5), sin(q5), cos(q6), sin(q6)
    n1 = -s1
    # columns x, y, z of each rotation: Rz1 (c1, s1, 0) (-s1, c1, 0) (0, 0, 1); Rz1 Ry2 and Rz1 Ry23
    x20, x21, x22, z20, z21, z22 = c1 * c2, s1 * c2, -s2, c1 * s2, s1 * s2, c2
    x30, x31, x32, z30, z31, z32 = c1 * c23, s1 * c23, -s23, c1 * s23, s1 * s23, c23
    # each later joint turns two columns about the third: (c a + s b, c b - s a)
    x40, x41, x42 = c4 * x30 + s4 * n1, c4 * x31 + s4 * c1, c4 * x32 + s4 * 0.0          # JT4: x, y about z
    y40, y41, y42 = c4 * n1 - s4 * x30, c4 * c1 - s4 * x31, c4 * 0.0 - s4 * x32
    z50, z51, z52 = c5 * z30 + s5 * x40, c5 * z31 + s5 * x41, c5 * z32 + s5 * x42      # JT5: z, x about y
    x50, x51, x52 = c5 * x40 - s5 * z30, c5 * x41 - s5 * z31, c5 * x42 - s5 * z32
    x60, x61, x62 = c6 * x50 + s6 * y40, c6 * x51 + s6 * y41, c6 * x52 + s6 * y42      # JT6: x, y about z
    y60, y61, y62 = c6 * y40 - s6 * x50, c6 * y41 - s6 * x51, c6 * y42 - s6 * x52
    d2, a2, d4 = geometry.d2, geometry.a2, geometry.d4
    h0, h1, h2 = n1 * d2, c1 * d2, 0.0                                                # the shoulder
    e0, e1, e2 = h0 + a2 * x20, h1 + a2 * x21, h2 + a2 * x22                        # the elbow
    w0, w1, w2 = e0 + d4 * z30, e1 + d4 * z31, e2 + d4 * z32                        # the wrist centre
    # the floats' bytes into a fresh array: the quickest way numpy takes 112 Python floats
    return np.frombuffer(bytearray(_FRAMES.pack(
        1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        c1, n1, 0.0, 0.0, s1, c1, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        x20, n1, z20, h0, x21, c1, z21, h1, x22, 0.0, z22, h2, 0.0, 0.0, 0.0, 1.0,
        x30, n1, z30, e0, x31, c1, z31, e1, x32, 0.0, z32, e2, 0.0, 0.0, 0.0, 1.0,
        x40, y40, z30, w0, x41, y41, z31, w1, x42, y42, z32, w2, 0.0, 0.0, 0.0, 1.0,
        x50, y40, z50, w0, x51, y41, z51, w1, x52, y42, z52, w2, 0.0, 0.0, 0.0, 1.0,
        x60, y60, z50, w0, x61, y61, z51, w1, x62, y62, z52, w2, 0.0, 0.0, 0.0, 1.0))).reshape(7, 4, 4)


_FRAMES = struct.Struct("112d")


def link_frames_batch(joints: np.ndarray, geometry: RobotGeometry | None = None, radians: bool = False) -> np.ndarray:
    """The seven link frames (base, waist, upper arm, forearm, wrist, joint 5, clamp) as 4x4.

    joints (n, 6) -> (n, 7, 4, 4). Frame k is where the drawn polyhedra of link k are placed:
    0 base (fixed), 1 waist (Rz JT1), 2 upper arm (at the shoulder, turned by JT2),
    3 forearm (at the elbow), 4 wrist (at the wrist centre, turned by JT4), 5 by JT5,
    6 the clamp (R6, origin at the wrist centre). The same arithmetic as ``link_frames``, in
    the same order, on columns of poses: the numbers are those of one pose at a time (the
    swept check of a whole path relies on it to give the verdicts of the pose-by-pose one).
    """
    geometry = geometry or robot_geometry()
    q = np.asarray(joints, dtype=float).reshape(-1, 6)
    if not radians:
        q = np.radians(q)
    n = len(q)
    cos, sin = np.cos(q.T), np.sin(q.T)
    c1, s1, c2, s2 = cos[0], sin[0], cos[1], sin[1]
    c23, s23 = np.cos(q[:, 1] + q[:, 2]), np.sin(q[:, 1] + q[:, 2])
    zero, one = np.zeros(n), np.ones(n)

    def turn(a: np.ndarray, b: np.ndarray, j: int) -> tuple[np.ndarray, np.ndarray]:
        """(c a + s b, -s a + c b) for columns a, b (3, n) turned by joint j about the third."""
        c, s = cos[j], sin[j]
        return c * a + s * b, c * b - s * a

    # each rotation's columns x, y, z as (3, n): the same products as ``link_frames``, three rows at a time
    r1 = (np.array([c1, s1, zero]), np.array([-s1, c1, zero]), np.array([zero, zero, one]))
    r2 = (np.array([c1 * c2, s1 * c2, -s2]), r1[1], np.array([c1 * s2, s1 * s2, c2]))
    r3 = (np.array([c1 * c23, s1 * c23, -s23]), r1[1], np.array([c1 * s23, s1 * s23, c23]))
    r4 = (*turn(r3[0], r3[1], 3), r3[2])
    r5x, r5z = turn(r4[2], r4[0], 4)
    r5 = (r5z, r4[1], r5x)
    r6 = (*turn(r5[0], r5[1], 5), r5[2])
    shoulder = np.array([-s1 * geometry.d2, c1 * geometry.d2, zero])
    elbow = shoulder + geometry.a2 * r2[0]
    wrist = elbow + geometry.d4 * r3[2]
    columns = np.array([r1[0], r1[1], r1[2], np.zeros((3, n)), *r2, shoulder, *r3, elbow, *r4, wrist, *r5, wrist,
                        *r6, wrist])                                          # (24, 3, n): frame, column, row
    frames = np.zeros((n, 7, 4, 4))
    frames[:, :, 3, 3] = 1.0
    frames[:, 0, :3, :3] = np.eye(3)
    frames[:, 1:, :3, :] = columns.reshape(6, 4, 3, n).transpose(3, 0, 2, 1)
    return frames


def indicators(joints: Sequence[float], geometry: RobotGeometry | None = None) -> Config:
    """Theoretical configuration indicators of a joint vector (degrees), SPEC section 2."""
    geometry = geometry or robot_geometry()
    j2, j3, j6 = (math.radians(joints[i]) for i in (1, 2, 5))
    reach = geometry.a2 * math.cos(j2) + geometry.d4 * math.sin(j2 + j3)
    # at a boundary an indicator reads positive: READY is RIGHTY ABOVE NOFLIP (§6.2.6)
    arm = 1 if -reach > -TIE_MM else -1
    c3 = math.cos(j3)
    elbow = 1 if abs(c3) < TIE else arm * (1 if c3 > 0 else -1)
    c6 = math.cos(j6)
    if abs(c6) > TIE:
        wrist = 1 if c6 > 0 else -1
    else:
        wrist = 1 if math.sin(j6) > -TIE else -1
    return Config(arm, elbow, wrist)


def indicators_batch(joints: np.ndarray, geometry: RobotGeometry | None = None) -> np.ndarray:
    """Batch indicators: joints (n, 6) degrees -> (n, 3) of +1/-1 (arm, elbow, wrist)."""
    geometry = geometry or robot_geometry()
    q = np.radians(np.asarray(joints, dtype=float).reshape(-1, 6))
    reach = geometry.a2 * np.cos(q[:, 1]) + geometry.d4 * np.sin(q[:, 1] + q[:, 2])
    arm = np.where(-reach > -TIE_MM, 1, -1)
    c3 = np.cos(q[:, 2])
    elbow = np.where(np.abs(c3) < TIE, 1, arm * np.where(c3 > 0, 1, -1))
    c6 = np.cos(q[:, 5])
    wrist = np.where(np.abs(c6) > TIE, np.sign(c6), np.where(np.sin(q[:, 5]) > -TIE, 1, -1)).astype(int)
    return np.stack([arm, elbow, wrist], axis=1)


# ---------------------------------------------------------------------------
# Inverse kinematics (Lee's geometric solution)
# ---------------------------------------------------------------------------

_HALF_PI = 0.5 * math.pi   # delta = 90 degrees - JT3 (exactly half of pi)


def ik_fast(
    x: float, y: float, z: float, rotation: Sequence[Sequence[float]],
    arm: int, elbow: int, wrist: int,
    j4_hint: float = 0.0, geometry: RobotGeometry | None = None,
) -> tuple[float, float, float, float, float, float]:
    """Lee's solution on radians for the TCS origin at (x, y, z) with the tool rotation given.

    Returns JT1..JT6 in radians (not yet fitted to the stops); raises OutOfReach, also for
    a coordinate that is not a finite number.
    ``j4_hint`` (radians) is JT4 to keep when the wrist is singular (JT5 = 0).
    """
    geometry = geometry or robot_geometry()
    # the rows once as plain names: indexing nested sequences costs more than the arithmetic
    (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = rotation
    # one sum is finite only when every term is (NaN and inf propagate; a sum that overflows
    # holds a coordinate no robot reaches); a row at a time, as sum() of the rows added them
    if not isfinite(x + y + z + (r00 + r01 + r02) + (r10 + r11 + r12) + (r20 + r21 + r22)):
        raise OutOfReach("not a location: a coordinate is not a finite number")
    d2, a2, d4, d6, d2_squared, a2_squared, d4_squared, twice_a2_d4 = geometry.lee_terms
    wx, wy, wz = x - d6 * r02, y - d6 * r12, z - d6 * r22
    planar2 = wx * wx + wy * wy - d2_squared
    if planar2 < -1e-9:
        raise OutOfReach("out of reach (inside the shoulder offset)")
    reach = sqrt(planar2) if planar2 > 0.0 else 0.0
    # in the waist frame the wrist is at (X, d2, wz); RIGHTY puts it behind the shoulder
    big_x = -reach if arm > 0 else reach
    j1 = atan2(wy, wx) - atan2(d2, big_x)
    k = (big_x * big_x + wz * wz - a2_squared - d4_squared) / twice_a2_d4
    if k > 1.0 or k < -1.0:
        if abs(k) - 1.0 > REACH_SLACK:
            raise OutOfReach()
        k = 1.0 if k > 0 else -1.0
    asin_k = asin(k)
    j3 = asin_k if arm * elbow > 0 else pi - asin_k
    delta = _HALF_PI - j3  # forearm relative to upper arm (e3 - e2)
    e2 = atan2(wz, big_x) - atan2(d4 * sin(delta), a2 + d4 * cos(delta))
    j2 = -e2
    # M = (Rz1 Ry23)^T R ; rows of R03^T are the columns of R03:
    # col0 = (c1 c23, s1 c23, -s23), col1 = (-s1, c1, 0), col2 = (c1 s23, s1 s23, c23);
    # m_ij = col_i . (column j of R), summed in that order (the 0 term kept: it can turn -0 to 0;
    # p + -q is written p - q and -p + q as q - p, the same floats)
    c1, s1 = cos(j1), sin(j1)
    j23 = j2 + j3
    c23, s23 = cos(j23), sin(j23)
    c1c23, s1c23 = c1 * c23, s1 * c23
    c1s23, s1s23 = c1 * s23, s1 * s23
    m02 = c1c23 * r02 + s1c23 * r12 - s23 * r22
    m12 = c1 * r12 - s1 * r02 + 0.0 * r22
    m22 = c1s23 * r02 + s1s23 * r12 + c23 * r22
    m20 = c1s23 * r00 + s1s23 * r10 + c23 * r20
    m21 = c1s23 * r01 + s1s23 * r11 + c23 * r21
    sin5 = hypot(m02, m12)
    if sin5 > WRIST_EPS:
        j4 = atan2(m12, m02)
        j5 = atan2(sin5, m22)
        j6 = atan2(m21, -m20)
    else:
        # singular wrist: JT5 = 0 (or 180); keep JT4, JT6 takes the rest of the turn
        j4 = j4_hint
        j5 = 0.0 if m22 > 0 else pi
        m00 = c1c23 * r00 + s1c23 * r10 - s23 * r20
        m10 = c1 * r10 - s1 * r00 + 0.0 * r20
        m01 = c1c23 * r01 + s1c23 * r11 - s23 * r21
        m11 = c1 * r11 - s1 * r01 + 0.0 * r21
        # N = Rz(-j4) M = Ry5 Rz6 ; Ry(0 or pi) leaves row 1 as (sin6, cos6, 0)
        c4, s4 = cos(j4), sin(j4)
        n10 = -s4 * m00 + c4 * m10
        n11 = -s4 * m01 + c4 * m11
        j6 = atan2(n10, n11)
    c6 = cos(j6)
    # the wrist as solved: the sign of cos JT6 (of sin JT6 within 1e-12 of cos JT6 = 0)
    if c6 > 1e-12:
        current_wrist = 1
    elif c6 < -1e-12:
        current_wrist = -1
    else:
        current_wrist = 1 if sin(j6) > 0 else -1
    if current_wrist != wrist:
        j4, j5, j6 = j4 + pi, -j5, j6 + pi
    return (j1, j2, j3, j4, j5, j6)


def ik(
    xyz: Sequence[float] | np.ndarray,
    rotation: np.ndarray | Sequence[Sequence[float]],
    config: Config,
    current: Sequence[float] | None = None,
    geometry: RobotGeometry | None = None,
    enforce_stops: bool = True,
) -> list[float]:
    """JT1..JT6 (degrees) for the TCS origin at ``xyz`` with the given tool rotation.

    The joints are the 360-degree equivalents within the stops nearest ``current``
    (or nearest the wrapped value when there is no current pose). Raises OutOfReach or
    BeyondStop(joint). With ``enforce_stops=False`` the geometric solution is returned
    wrapped to (-180, 180], whatever the stops say.
    """
    geometry = geometry or robot_geometry()
    hint = math.radians(current[3]) if current is not None else 0.0
    # Python floats on entry: math on numpy scalars is several times slower
    rot = rotation.tolist() if isinstance(rotation, np.ndarray) else rotation
    x, y, z = xyz.tolist() if isinstance(xyz, np.ndarray) else (float(v) for v in xyz)
    # (ik_fast refuses a coordinate that is not a finite number)
    radians = ik_fast(x, y, z, rot, config.arm, config.elbow, config.wrist, hint, geometry)
    if not enforce_stops:
        return [_wrap_turn(math.degrees(v)) for v in radians]
    return _fit_turns(radians, current, geometry.fit_bounds)


def _wrap_turn(angle: float) -> float:
    """``wrap180`` for the angles ``ik_fast`` gives (within one turn of (-180, 180]): the same
    value with one comparison instead of a remainder."""
    if angle > 180.0:
        angle -= 360.0
    elif angle <= -180.0:
        angle += 360.0
    return angle if -180.0 < angle <= 180.0 else wrap180(angle)


_DEGREES = 180.0 / math.pi   # math.degrees(v) is exactly v * this


def _fit_turns(radians: Sequence[float], current: Sequence[float] | None,
               bounds: Sequence[tuple[float, float, _StopFit]]) -> list[float]:
    """``fit_to_stops`` of ``ik_fast``'s angles wrapped to (-180, 180] (``_wrap_turn``), in
    one pass with no call per joint (ik's hot path, issue 25). Most angles are their own fit
    (``_settled``: one comparison); for the rest, of the angle and its +-360 equivalents the
    one inside the stops nearest the current angle, ties to the lower (``equivalent_inside``
    written out), clamped; BeyondStop when none is inside. ``bounds`` is
    ``RobotGeometry.fit_bounds``."""
    j1, j2, j3, j4, j5, j6 = radians
    # written out: a comprehension is a call of its own
    fitted = [j1 * _DEGREES, j2 * _DEGREES, j3 * _DEGREES, j4 * _DEGREES, j5 * _DEGREES, j6 * _DEGREES]
    index = -1
    for settled_low, settled_high, stop in bounds:   # (a counter costs less than enumerate here)
        index += 1
        angle = fitted[index]
        if settled_low <= angle <= settled_high:
            continue
        lo, hi, low, high, below_may, above_may = stop
        if not -180.0 < angle <= 180.0:
            angle = _wrap_turn(angle)
        near = angle if current is None else current[index]
        best = None
        # angle - 360 <= -180 and angle + 360 > 180: each is tried only where the stops reach
        if below_may and lo <= (below := angle - 360.0) <= hi:
            best = below
        if lo <= angle <= hi and (best is None or abs(angle - near) < abs(best - near)):
            best = angle
        if above_may and lo <= (above := angle + 360.0) <= hi and (best is None or abs(above - near) < abs(best - near)):
            best = above
        if best is None:
            raise BeyondStop(index + 1, angle, (low, high))
        fitted[index] = low if best < low else high if best > high else best
    return fitted


def ik_oat(
    xyz: Sequence[float], oat: Sequence[float], config: Config,
    current: Sequence[float] | None = None, geometry: RobotGeometry | None = None,
) -> list[float]:
    """IK of a location given as XW YW ZW O A T (what a .LOC file and WHERE hold)."""
    geometry = geometry or robot_geometry()
    return ik(xyz, oat_to_rotation(*oat), config, current, geometry)


# Batch status codes: 0 solved, OUT_OF_REACH, or the number (1..6) of the joint beyond its stop.
OUT_OF_REACH = -1


def ik_batch(
    xyz: np.ndarray,
    rotations: np.ndarray,
    config: np.ndarray | Sequence[int] | Config,
    geometry: RobotGeometry | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Vectorised IK: xyz (n, 3), rotations (n, 3, 3), config (3,) or (n, 3) of +-1.

    Returns joints (n, 6) degrees (wrapped, then fitted to the stops nearest the wrapped
    value) and status (n,): 0, OUT_OF_REACH or the first joint beyond its stop. Singular
    wrists take JT4 = 0.
    """
    geometry = geometry or robot_geometry()
    p = np.asarray(xyz, dtype=float).reshape(-1, 3)
    r = np.asarray(rotations, dtype=float).reshape(-1, 3, 3)
    n = len(p)
    # one array as given (never a tuple of rows per pose): (3,) broadcasts, (n, 3) is per pose
    cfg = np.asarray(config if isinstance(config, np.ndarray) else tuple(config), dtype=float).reshape(-1, 3)
    if n <= BATCH_CHUNK:
        return _ik_chunk(p, r, cfg, geometry)
    # in chunks: the temporaries stay in cache and the memory per pose stays small
    joints = np.empty((n, 6))
    status = np.empty(n, dtype=np.intp)
    for lo in range(0, n, BATCH_CHUNK):
        part = slice(lo, lo + BATCH_CHUNK)
        joints[part], status[part] = _ik_chunk(p[part], r[part], cfg if len(cfg) == 1 else cfg[part], geometry)
    return joints, status


BATCH_CHUNK = 8192   # poses per pass of the batch functions


def _ik_chunk(p: np.ndarray, r: np.ndarray, cfg: np.ndarray, geometry: RobotGeometry) -> tuple[np.ndarray, np.ndarray]:
    """``ik_batch`` on one chunk of poses (see there)."""
    arm, elbow, wrist = cfg[:, 0], cfg[:, 1], cfg[:, 2]
    a = r[:, :, 2]
    w = p - geometry.d6 * a
    planar2 = w[:, 0] ** 2 + w[:, 1] ** 2 - geometry.d2 ** 2
    status = np.where(planar2 < -1e-9, OUT_OF_REACH, 0)
    reach = np.sqrt(np.clip(planar2, 0.0, None))
    big_x = np.where(arm > 0, -reach, reach)
    j1 = np.arctan2(w[:, 1], w[:, 0]) - np.arctan2(geometry.d2, big_x)
    a2, d4 = geometry.a2, geometry.d4
    k = (big_x ** 2 + w[:, 2] ** 2 - a2 * a2 - d4 * d4) / (2.0 * a2 * d4)
    status = np.where((np.abs(k) - 1.0 > REACH_SLACK) & (status == 0), OUT_OF_REACH, status)
    asin_k = np.arcsin(np.clip(k, -1.0, 1.0))
    j3 = np.where(arm * elbow > 0, asin_k, np.pi - asin_k)
    delta = 0.5 * np.pi - j3
    j2 = -(np.arctan2(w[:, 2], big_x) - np.arctan2(d4 * np.sin(delta), a2 + d4 * np.cos(delta)))
    c1, s1 = np.cos(j1), np.sin(j1)
    c23, s23 = np.cos(j2 + j3), np.sin(j2 + j3)
    # only the entries of M = (Rz1 Ry23)^T R that the wrist solution needs
    col0 = (c1 * c23, s1 * c23, -s23)
    col1 = (-s1, c1)
    col2 = (c1 * s23, s1 * s23, c23)
    m02 = col0[0] * r[:, 0, 2] + col0[1] * r[:, 1, 2] + col0[2] * r[:, 2, 2]
    m12 = col1[0] * r[:, 0, 2] + col1[1] * r[:, 1, 2]
    m22 = col2[0] * r[:, 0, 2] + col2[1] * r[:, 1, 2] + col2[2] * r[:, 2, 2]
    m20 = col2[0] * r[:, 0, 0] + col2[1] * r[:, 1, 0] + col2[2] * r[:, 2, 0]
    m21 = col2[0] * r[:, 0, 1] + col2[1] * r[:, 1, 1] + col2[2] * r[:, 2, 1]
    sin5 = np.hypot(m02, m12)
    regular = sin5 > WRIST_EPS
    j4 = np.arctan2(m12, m02)
    j5 = np.arctan2(sin5, m22)
    j6 = np.arctan2(m21, -m20)
    if not regular.all():
        # singular wrist: JT4 = 0 and JT6 takes the whole turn
        m10 = col1[0] * r[:, 0, 0] + col1[1] * r[:, 1, 0]
        m11 = col1[0] * r[:, 0, 1] + col1[1] * r[:, 1, 1]
        j4 = np.where(regular, j4, 0.0)
        j5 = np.where(regular, j5, np.where(m22 > 0, 0.0, np.pi))
        j6 = np.where(regular, j6, np.arctan2(m10, m11))
    c6 = np.cos(j6)
    current_wrist = np.where(np.abs(c6) > 1e-12, np.sign(c6), np.sign(np.sin(j6)))
    flip = current_wrist != wrist
    j4 = j4 + flip * np.pi
    j5 = np.where(flip, -j5, j5)
    j6 = j6 + flip * np.pi
    joints = wrap180_array(np.degrees(np.stack([j1, j2, j3, j4, j5, j6], axis=1)))
    joints, beyond = fit_to_stops_batch(joints, geometry)
    status = np.where(status == 0, beyond, status)
    return joints, status


def fit_to_stops_batch(joints: np.ndarray, geometry: RobotGeometry | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Batch fit_to_stops for wrapped angles, nearest the given angle.

    Returns (fitted, first joint beyond its stop or 0). Angles must lie in (-180, 180]:
    then only the angle itself and its +-360 equivalents can be nearest.
    """
    geometry = geometry or robot_geometry()
    q = np.asarray(joints, dtype=float)
    low = geometry.stops_array[:, 0]
    high = geometry.stops_array[:, 1]
    tol = 1e-9
    inside = (q >= low - tol) & (q <= high + tol)
    up = q + 360.0
    down = q - 360.0
    up_ok = up <= high + tol
    down_ok = down >= low - tol
    # the angle itself is nearest; else whichever shifted one is inside (at most one can be nearer)
    fitted = np.where(inside, q, np.where(up_ok, up, np.where(down_ok, down, q)))
    ok = inside | up_ok | down_ok
    first_bad = np.where(ok.all(axis=1), 0, np.argmin(ok, axis=1) + 1)
    return fitted, first_bad


class Location(NamedTuple):
    """A location as WHERE shows it and a .LOC file holds it: XW YW ZW (mm) and O A T (deg).

    A location taught by HERE or the pendant also keeps the arm's configuration and its joint
    angles (§6.1.1); SET copies both (§6.1.4); a location typed or read without them has None.
    """

    xyz: tuple[float, float, float]
    oat: tuple[float, float, float]
    config: Config | None = None
    joints: tuple[float, ...] | None = None

    @property
    def rotation(self) -> np.ndarray:
        return oat_to_rotation(*self.oat)

    def shifted(self, dx: float, dy: float, dz: float) -> "Location":
        """The location moved along the world axes: its configuration stays, its joints do not."""
        x, y, z = self.xyz
        return Location((x + dx, y + dy, z + dz), self.oat, self.config)

    @classmethod
    def from_pose(cls, pose: Pose) -> "Location":
        x, y, z = (float(v) for v in pose.xyz)
        return cls((x, y, z), pose.oat)
