"""Where imported parts land: a free spot on a table in front of the robot.

The thesis placed transferred parts "at the origin of the user specified coordinate axes"
(§7.1), which in world coordinates is inside the robot's shoulder (SPEC §1: the origin is
where joint axes 1 and 2 meet). Here the parts (moved together, their arrangement kept)
rest on the top of a table of the setup instead:

* a table is a slab: thin against its width (PROCESS objects 3 and 8, DEMO3 table A, the
  CONV conveyor). A setup without one gets the bundled cells' work table in front of the
  robot: DEMO3 table A, X 300..700, Y -400..400, top Z = -320 (PROCESS's right-hand table
  has the same top), a stand-in drawn nowhere;
* the spot keeps ``CLEARANCE`` from every object of the setup and from the robot at READY
  (its pedestal is the square |X|, |Y| <= 102 about the Z axis; at READY the arm stands
  straight up over it);
* the robot reaches it: the tool pointing straight down ``APPROACH`` above the centre of the
  parts' top solves (IK, any configuration, within the stops);
* of the spots that pass, the one nearest ``FRONT`` (the middle of that table in front) wins.

When nothing fits (a part wider than every table) the parts stand on the floor level of the
tables just in front of the robot's pedestal, and a warning says to move them (MANIPULATION).
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from valterm.core.cad.hull import convex_hull_2d
from valterm.core.cell.polyhedron import Polyhedron

CLEARANCE = 20.0          # mm between the parts and anything else, in plan
APPROACH = 50.0           # mm above the parts' top the tool must reach, pointing down
GRID_STEP = 10.0          # mm between candidate spots on a table
SLAB_RATIO = 0.3          # a table's height is at most this share of its smaller width
MIN_TABLE_WIDTH = 100.0   # mm: anything narrower is a leg or a part, not a table
FRONT = np.array([500.0, 0.0])  # the middle of table A in front of the robot (X_w, Y_w)
TOOL_DOWN_OAT = (90.0, 90.0, 0.0)  # O, A, T with the approach vector a = -Z_w
_EPS = 1e-6


@dataclass(frozen=True)
class Table:
    """The top of a table: its convex outline in plan (counter-clockwise) and its height."""

    outline: np.ndarray  # (k, 2) X_w, Y_w
    top: float


DEFAULT_TABLE = Table(np.array([[300.0, -400.0], [700.0, -400.0], [700.0, 400.0], [300.0, 400.0]]), -320.0)


def tables(objects: Sequence[Polyhedron]) -> list[Table]:
    """The table tops among ``objects``: slabs thin against their width."""
    found = []
    for poly in objects:
        lo, hi = poly.extreme_box
        size = hi - lo
        width = float(min(size[0], size[1]))
        if width >= MIN_TABLE_WIDTH and size[2] <= SLAB_RATIO * width:
            outline = convex_hull_2d(poly.vertices[:, :2])
            if len(outline) >= 3:
                found.append(Table(outline, float(hi[2])))
    return found


def robot_at_ready() -> list[Polyhedron]:
    """The robot's links at READY, from the robot model."""
    from valterm.core.simulator import default_model

    model = default_model()
    return model.place(model.geometry.ready)


def reachable(points: np.ndarray | Sequence[float]) -> np.ndarray:
    """For (n, 3) points (or one point): does the tool, pointing straight down, reach it in
    some configuration within the stops? (vectorised IK, every configuration tried)"""
    from valterm.core.kinematics import ik_batch, oat_to_rotation

    xyz = np.asarray(points, dtype=float).reshape(-1, 3)
    rotations = np.broadcast_to(oat_to_rotation(*TOOL_DOWN_OAT), (len(xyz), 3, 3))
    found = np.zeros(len(xyz), dtype=bool)
    for config in itertools.product((-1, 1), repeat=3):
        _, status = ik_batch(xyz, rotations, config)
        found |= status == 0
    return found


def _boxes(objects: Sequence[Polyhedron]) -> tuple[np.ndarray, np.ndarray]:
    if not objects:
        return np.zeros((0, 3)), np.zeros((0, 3))
    return (np.array([p.vertices.min(axis=0) for p in objects]),
            np.array([p.vertices.max(axis=0) for p in objects]))


def _candidates(table: Table, size: np.ndarray) -> np.ndarray:
    """(n, 2) minimum corners of the parts' footprint that stand wholly on ``table``."""
    lo, hi = table.outline.min(axis=0), table.outline.max(axis=0) - size[:2]
    if np.any(hi < lo - _EPS):
        return np.zeros((0, 2))
    xs = np.arange(lo[0], hi[0] + _EPS, GRID_STEP)
    ys = np.arange(lo[1], hi[1] + _EPS, GRID_STEP)
    corners = np.stack(np.meshgrid(xs, ys, indexing="ij"), -1).reshape(-1, 2)
    offsets = np.array([[0, 0], [size[0], 0], [size[0], size[1]], [0, size[1]]])
    footprint = corners[:, None, :] + offsets[None]                         # (n, 4, 2)
    a, b = table.outline, np.roll(table.outline, -1, axis=0)                # edges a -> b
    edge = b - a
    rel = footprint[:, :, None, :] - a[None, None]                          # (n, 4, k, 2)
    cross = edge[..., 0] * rel[..., 1] - edge[..., 1] * rel[..., 0]
    inside = np.all(cross >= -_EPS * float(np.abs(edge).max()), axis=(1, 2))
    return np.asarray(corners[inside])


def _free(corners: np.ndarray, size: np.ndarray, bottom: float,
          lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Which footprint corners keep CLEARANCE in plan from every box (lo, hi) they meet in height."""
    if len(lo) == 0:
        return np.ones(len(corners), dtype=bool)
    top = bottom + size[2]
    meets_height = (lo[:, 2] < top - _EPS) & (hi[:, 2] > bottom + _EPS)          # (m,)
    c_lo = corners[:, None, :] - CLEARANCE
    c_hi = corners[:, None, :] + size[None, None, :2] + CLEARANCE
    overlap = np.all((c_lo < hi[None, :, :2]) & (lo[None, :, :2] < c_hi), axis=2) & meets_height[None]
    return np.asarray(~overlap.any(axis=1))


def place_on_table(parts: Sequence[Polyhedron],
                   around: Sequence[Polyhedron] = ()) -> tuple[list[Polyhedron], list[str]]:
    """``parts`` moved together onto a free, reachable spot of a table; and any warnings."""
    lo_parts, hi_parts = _boxes(parts)
    lo, hi = lo_parts.min(axis=0), hi_parts.max(axis=0)
    size = hi - lo
    obstacles = list(around) + robot_at_ready()
    o_lo, o_hi = _boxes(obstacles)
    corners, tops = [], []
    for table in tables(around) or [DEFAULT_TABLE]:
        found = _candidates(table, size)
        found = found[_free(found, size, table.top, o_lo, o_hi)]
        corners.append(found)
        tops.append(np.full(len(found), table.top))
    corner, top = np.concatenate(corners), np.concatenate(tops)
    centre = corner + size[:2] / 2
    ok = reachable(np.column_stack([centre, top + size[2] + APPROACH]))
    if ok.any():
        best = np.flatnonzero(ok)[np.argmin(np.linalg.norm(centre[ok] - FRONT, axis=1))]
        return _moved(parts, np.array([*corner[best], top[best]]) - lo), []
    return _in_front(parts, lo, size)


def _in_front(parts: Sequence[Polyhedron], lo: np.ndarray, size: np.ndarray) -> tuple[list[Polyhedron], list[str]]:
    """No spot fits: just in front of the robot's pedestal, at the tables' height."""
    front = float(robot_front()) + CLEARANCE
    corner = np.array([front, -size[1] / 2, DEFAULT_TABLE.top])
    warning = (f"no free spot on a table within reach for {size[0]:.0f} x {size[1]:.0f} x {size[2]:.0f} mm; "
               f"placed in front of the robot at X = {front:.0f} mm: move it in MANIPULATION mode")
    return _moved(parts, corner - lo), [warning]


def robot_front() -> float:
    """The largest X_w of the robot at READY (its pedestal's front face)."""
    return float(max(p.vertices[:, 0].max() for p in robot_at_ready()))


def _moved(parts: Sequence[Polyhedron], offset: np.ndarray) -> list[Polyhedron]:
    return [p.translated(offset) for p in parts]
