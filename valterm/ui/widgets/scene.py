"""The model view's scene from the simulator: the cell, the robot, the LED sensor.

No textual here: the hardcopy uses it headless too.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from valterm.core.render.legend import LED_COLOUR
from valterm.core.render.raster import Scene, frame_lines, link_colour, object_colour

if TYPE_CHECKING:  # annotations only
    from valterm.core.cell.polyhedron import Polyhedron
    from valterm.core.simulator import Simulator


def simulator_scene(simulator: Simulator, part_axes: int | None = None) -> Scene:
    """Objects first, then the robot, then a carried part (later items win shared cells).

    ``part_axes``: a part number whose frame is drawn at its reference corner (MANIPULATION
    mode with AXES on)."""
    objects = simulator.cell.objects
    carried = simulator.carried
    items = [(p, link_colour(i)) for i, p in enumerate(simulator.robot_polyhedra())]
    if carried is not None and 1 <= carried <= len(objects):
        items.append((objects[carried - 1], object_colour(carried)))
    p0, p1 = simulator.model.led_segment(simulator.joints, simulator.gap, simulator.base)
    lines = [np.stack([np.asarray(p0, dtype=float), np.asarray(p1, dtype=float)])]
    colours = [LED_COLOUR]
    if part_axes is not None and 1 <= part_axes <= len(objects):
        frame = frame_lines(objects[part_axes - 1].reference, length=150.0)
        lines.extend(frame)
        colours.extend([LED_COLOUR] * 3)
    return Scene.build(items, np.stack(lines), colours, background=_cell_scene(objects, carried))


_CELL: list[tuple[tuple[object, ...], Scene]] = []


def _cell_scene(objects: Sequence[Polyhedron], carried: int | None) -> Scene:
    """The parts that are not carried, as one static scene kept while none of them moves
    (the rasteriser draws it once per view and size)."""
    key = (carried, *(p.vertices for p in objects))
    if _CELL:
        (held, *arrays), scene = _CELL[0]
        if held == carried and len(arrays) == len(objects) and all(a is p.vertices for a, p in zip(arrays, objects)):
            return scene
    scene = Scene.build((p, object_colour(i)) for i, p in enumerate(objects, start=1) if i != carried)
    _CELL[:] = [(key, scene)]
    return scene
