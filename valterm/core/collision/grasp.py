"""The LED sensor of §2.5 / §6.3: which object, if any, CLOSE/CLOSEI/GRASP latches.

The sensor is a short segment between the fingers. It "is intersected by" an object when it
crosses one of the object's face polygons (the fine check's own test) or when it lies inside
the object (a part held between the fingers contains the whole short segment and crosses no
face). When several objects qualify, the lowest-numbered one is taken, as in 1985 (§6.3).
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from valterm.core.cell.polyhedron import Polyhedron


def led_hits(led_p0: np.ndarray, led_p1: np.ndarray, objects: Sequence[Polyhedron]) -> int | None:
    """The lowest 1-based number of the objects the LED segment meets, or None."""
    p0 = np.asarray(led_p0, dtype=float)
    p1 = np.asarray(led_p1, dtype=float)
    lo_seg, hi_seg = np.minimum(p0, p1), np.maximum(p0, p1)
    for number, poly in enumerate(objects, start=1):
        lo, hi = poly.extreme_box
        if np.any(hi_seg < lo) or np.any(lo_seg > hi):
            continue  # the segment's box misses the object's: no need for the face test
        # the fine check's module loads only when a box is met: the first picture asks the
        # LED at the ready pose, where it meets none (issue 25, the start)
        from valterm.core.collision.thesis import segment_hits_polyhedron

        if segment_hits_polyhedron(p0, p1, poly, solid=True):
            return number
    return None
