"""What the user needs to judge a program, drawn over the cell and the robot.

The tool-path trace of the last motions, the LED sensor line with the part it sees, the
target of the current motion as a small frame (the "ghost"), the parts and links in collision
in a colour of their own, drawn over everything else, the WORLD axes, and a depth cue
(polyhedra further away take a dimmer colour index, which the view maps to a darker shade
where the terminal has colour).

Everything here is extra coloured segments and per-polyhedron colour indices handed to
``Scene.build``; the rasterizer itself is untouched.
"""

from __future__ import annotations

import weakref
from collections import deque
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.render.legend import (
    DIM_OFFSET,
    GHOST_COLOUR,
    HIGHLIGHT_COLOUR,
    LED_COLOUR,
    SEEN_COLOUR,
    TRACE_COLOUR,
    TRACE_POINTS,
)
from valterm.core.render.raster import AXIS_LENGTH, Scene, ViewTransform, frame_lines, link_colour, object_colour

if TYPE_CHECKING:
    from valterm.core.simulator import Simulator

DIM_FRACTION = 0.45  # polyhedra in the farthest 45 % of the depth range are dimmed

TRACE_STEP = 0.5  # mm the clamp must move to add a point
GHOST_LENGTH = 80.0  # mm, the axes of the target frame


def clamp_point(simulator: Simulator, joints: Sequence[float] | None = None) -> np.ndarray:
    """The world position whose path the trace draws: the clamp tip (KEYBOARD's POSITION 3),
    at ``joints`` (else where the arm is)."""
    xyz, _ = simulator.tool_pose(3, joints)
    return np.asarray(xyz, dtype=float)


class Trace:
    """The clamp's path over the last motions (a capped polyline)."""

    def __init__(self, points: Iterable[Sequence[float] | np.ndarray] = (), maxlen: int = TRACE_POINTS) -> None:
        self._points: deque[np.ndarray] = deque(maxlen=maxlen)
        # the points as one array, made again only after a change: the picture asks for them
        # 30 times a second, and a long session's trace holds thousands (issue 40)
        self._array: np.ndarray | None = None
        self._segments: np.ndarray | None = None
        for point in points:
            self.add(point)

    def add(self, point: Sequence[float] | np.ndarray) -> None:
        p = np.asarray(point, dtype=float)
        if not self._points or float(np.linalg.norm(p - self._points[-1])) >= TRACE_STEP:
            self._points.append(p)
            self._array = self._segments = None

    def clear(self) -> None:
        self._points.clear()
        self._array = self._segments = None

    def __len__(self) -> int:
        return len(self._points)

    def points(self) -> np.ndarray:
        """The points in order, (N, 3); read only (the same array until the trace changes)."""
        if self._array is None:
            self._array = np.array(self._points) if self._points else np.zeros((0, 3))
            self._array.flags.writeable = False
        return self._array

    def segments(self) -> np.ndarray:
        """(N-1, 2, 3) consecutive points joined; read only, as ``points``."""
        if self._segments is None:
            pts = self.points()
            self._segments = np.stack([pts[:-1], pts[1:]], axis=1) if len(pts) >= 2 else np.zeros((0, 2, 3))
            self._segments.flags.writeable = False
        return self._segments


@dataclass
class Overlays:
    """Which extras to draw and their data."""

    trace: Trace | None = None  # None: no trace
    goal: Sequence[float] | None = None  # joints of the current motion's target: the ghost
    collided: frozenset[str] = frozenset()  # link names and part numbers (as text) in collision
    led_part: bool = True  # highlight the part the LED sensor sees
    axes: bool = False  # the WORLD axes as lines (the rasterizer's AXES adds the labels)
    depth: ViewTransform | None = None  # dim what is far from the viewer of this view
    part_axes: int | None = None  # a part whose frame is drawn (MANIPULATION mode)
    extra: list[tuple[np.ndarray, int]] = field(default_factory=list)  # (segments, colour)
    # the joints the robot is drawn at instead of the simulator's: an in-between pose of the
    # app's playback (drawn only; the LED's verdict and the collisions are the pose's own)
    drawn: Sequence[float] | None = None
    # the parts standing in the cell as the scene's background (kept while they stand still:
    # the app's pictures, 30 a second); the scene's own items then hold the rest only
    static_cell: bool = False


def _dimmed(polys: list[Polyhedron], colours: list[int], keep: list[bool], view: ViewTransform) -> list[int]:
    """Colour indices with the far polyhedra moved to their dim shade."""
    if len(polys) < 2:
        return colours
    # each one's centre's depth: one projection of all the vertices, summed polyhedron by
    # polyhedron (not a mean and a product a polyhedron: the picture is made 30 times a second)
    vertices = [p.vertices for p in polys]
    counts = np.array([len(v) for v in vertices])
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    depth = np.add.reduceat(np.concatenate(vertices) @ view.depth_axis(), starts) / counts
    lo, hi = float(depth.min()), float(depth.max())
    if hi - lo < 1e-6:
        return colours
    far = (depth - lo) / (hi - lo) < DIM_FRACTION
    return [c + DIM_OFFSET if f and k else c for c, f, k in zip(colours, far, keep)]


def picture_scene(simulator: Simulator, overlays: Overlays | None = None) -> Scene:
    """The simulator's scene with the overlays: objects, robot, a carried part, then lines."""
    ov = overlays or Overlays()
    objects = simulator.cell.objects
    carried = simulator.carried
    seen = led_part_seen(simulator) if ov.led_part else None
    names = simulator.model.names

    def object_item(number: int) -> tuple[Polyhedron, int, bool]:
        if str(number) in ov.collided:
            return objects[number - 1], HIGHLIGHT_COLOUR, False
        if number == seen:
            return objects[number - 1], SEEN_COLOUR, False
        return objects[number - 1], object_colour(number), True

    items = [object_item(n) for n in range(1, len(objects) + 1) if n != carried]
    joints = simulator.joints if ov.drawn is None else list(ov.drawn)
    for i, poly in enumerate(simulator.model.place(joints, simulator.gap, simulator.base)):
        hit = i < len(names) and names[i] in ov.collided
        items.append((poly, HIGHLIGHT_COLOUR if hit else link_colour(i), not hit))
    if carried is not None and 1 <= carried <= len(objects):
        poly, colour, keep = object_item(carried)
        items.append((poly if ov.drawn is None else _carried_at(simulator, poly, joints), colour, keep))
    if ov.collided:  # the colliding bodies are drawn last: what overlaps them never hides them
        items = [item for item in items if item[1] != HIGHLIGHT_COLOUR] + \
                [item for item in items if item[1] == HIGHLIGHT_COLOUR]
    polys = [p for p, _, _ in items]
    colours = [c for _, c, _ in items]
    if ov.depth is not None:
        colours = _dimmed(polys, colours, [k for _, _, k in items], ov.depth)
    lines, line_colours = _lines(simulator, ov)
    if not ov.static_cell:
        return Scene.build(zip(polys, colours), lines, line_colours)
    # the parts standing in the cell lead the items (a colliding one was moved last)
    standing = sum(1 for n in range(1, len(objects) + 1) if n != carried and str(n) not in ov.collided)
    background = _standing(list(zip(polys[:standing], colours[:standing])))
    return Scene.build(zip(polys[standing:], colours[standing:]), lines, line_colours, background=background)


_STANDING: list[tuple[list[tuple[np.ndarray, int]], Scene]] = []


def _standing(items: list[tuple[Polyhedron, int]]) -> Scene | None:
    """The parts standing in the cell as the picture's background, the same Scene object
    while none of them moves or changes colour (the rasterizer draws it once per view and
    size, then each picture draws only the arm, a carried part and the lines over it)."""
    if not items:
        return None
    if _STANDING:
        held, scene = _STANDING[0]
        if len(held) == len(items) and all(v is p.vertices and c == k for (v, c), (p, k) in zip(held, items)):
            return scene
    scene = Scene.build(items)
    _STANDING[:] = [([(p.vertices, c) for p, c in items], scene)]
    return scene


_SEEN: list[tuple[weakref.ref[Simulator], tuple[object, ...], list[np.ndarray], int | None]] = []


def led_part_seen(simulator: Simulator) -> int | None:
    """``simulator.led_part()``, worked out once a pose: the in-between pictures of a motion
    (drawn at 30 a second, the poses come 10-15) ask it where the simulator has not moved.
    Kept while the simulator, its pose, gap, carried part, base and every part's vertices
    (an array a move replaces, never changes in place) are the same."""
    objects = simulator.cell.objects
    pose = (tuple(simulator.joints), simulator.gap, simulator.carried, simulator.base.tobytes())
    if _SEEN:
        held, held_pose, arrays, seen = _SEEN[0]
        if held() is simulator and held_pose == pose and len(arrays) == len(objects) \
                and all(a is p.vertices for a, p in zip(arrays, objects)):
            return seen
    seen = simulator.led_part()
    _SEEN[:] = [(weakref.ref(simulator), pose, [p.vertices for p in objects], seen)]
    return seen


def _carried_at(simulator: Simulator, part: Polyhedron, joints: Sequence[float]) -> Polyhedron:
    """The carried part as the clamp holds it at ``joints`` (it rides the clamp rigidly)."""
    here = simulator.model.clamp_frame(simulator.joints, simulator.base)
    there = simulator.model.clamp_frame(joints, simulator.base)
    move = there @ np.linalg.inv(here)
    return Polyhedron(part.vertices @ move[:3, :3].T + move[:3, 3], part.name, part.winding_flipped)


def _lines(simulator: Simulator, ov: Overlays) -> tuple[np.ndarray, list[int]]:
    """The loose segments, drawn after the polyhedra: trace, ghost, axes, then the LED line."""
    parts: list[tuple[np.ndarray, int]] = []
    if ov.trace is not None:
        parts.append((ov.trace.segments(), TRACE_COLOUR))
    if ov.goal is not None and len(ov.goal):
        parts.append((_ghost(simulator, ov.goal), GHOST_COLOUR))
    if ov.axes:
        parts.append((_WORLD_AXES, 1))
    objects = simulator.cell.objects
    if ov.part_axes is not None and 1 <= ov.part_axes <= len(objects):
        parts.append((frame_lines(list(objects[ov.part_axes - 1].reference), length=150.0), LED_COLOUR))
    parts.extend(ov.extra)
    joints = simulator.joints if ov.drawn is None else list(ov.drawn)
    p0, p1 = simulator.model.led_segment(joints, simulator.gap, simulator.base)
    parts.append((np.stack([np.asarray(p0, dtype=float), np.asarray(p1, dtype=float)])[None], LED_COLOUR))
    segs = [np.asarray(s, dtype=float).reshape(-1, 2, 3) for s, _ in parts]
    colours = [c for s, c in zip(segs, (c for _, c in parts)) for _ in range(len(s))]
    return np.concatenate(segs), colours


_WORLD_AXES = frame_lines((0.0, 0.0, 0.0), length=AXIS_LENGTH)
_WORLD_AXES.flags.writeable = False  # shared by every picture
_GHOSTS: list[tuple[object, tuple[object, ...], np.ndarray]] = []


def _ghost(simulator: Simulator, goal: Sequence[float]) -> np.ndarray:
    """The target frame's axes, made once a goal (a motion's pictures all show the same)."""
    key = (tuple(goal), simulator.base.tobytes())
    if _GHOSTS and _GHOSTS[0][0] is simulator.model and _GHOSTS[0][1] == key:
        return _GHOSTS[0][2]
    frame = simulator.model.clamp_frame(list(goal), simulator.base)
    ghost = frame_lines(frame[:3, 3].tolist(), frame[:3, :3], GHOST_LENGTH)
    ghost.flags.writeable = False
    _GHOSTS[:] = [(simulator.model, key, ghost)]
    return ghost


def cell_points(simulator: Simulator, trace: Trace | None = None) -> np.ndarray:
    """What the frame-all view frames: the cell, the robot as it stands, the trace, the origin."""
    scene = picture_scene(simulator, Overlays(led_part=False, trace=trace))
    return np.concatenate([scene.vertices, scene.lines.reshape(-1, 3), np.zeros((1, 3))])


FOLLOW_HALF = 220.0  # mm about the clamp framed by the follow view


def clamp_points(simulator: Simulator) -> np.ndarray:
    """A box about the clamp tip and the part under it (the follow-the-clamp view)."""
    tip = clamp_point(simulator)
    box = tip + FOLLOW_HALF * np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)])
    under = _part_under(simulator, tip)
    if under is None:
        return box
    return np.concatenate([box, simulator.cell.objects[under - 1].vertices])


def _part_under(simulator: Simulator, tip: np.ndarray) -> int | None:
    """The LED's part, else the nearest part whose footprint holds the clamp tip's XY, below it."""
    seen = simulator.led_part()
    if seen is not None:
        return seen
    best: tuple[float, int] | None = None
    for number, poly in enumerate(simulator.cell.objects, start=1):
        if number == simulator.carried:
            continue
        lo, hi = poly.vertices.min(axis=0), poly.vertices.max(axis=0)
        if lo[0] <= tip[0] <= hi[0] and lo[1] <= tip[1] <= hi[1] and hi[2] <= tip[2] + 1.0:
            gap = float(tip[2] - hi[2])
            if best is None or gap < best[0]:
                best = (gap, number)
    return None if best is None else best[1]
