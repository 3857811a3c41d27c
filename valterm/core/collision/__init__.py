"""Collision checking: the 1985 coarse + fine check, the python-fcl exact check, the LED sensor.

The simulator calls ``CollisionWorld.check`` (or ``check_scene``) at every motion step and
``led_hits`` on CLOSE/CLOSEI/GRASP. python-fcl is imported only when the exact checker is used.
"""

from valterm.core.collision.grasp import led_hits
from valterm.core.collision.thesis import check_pair, margin, segment_hits_polyhedron
from valterm.core.collision.world import CollisionWorld, Finding, ThesisChecker, check_scene, default_skip

__all__ = [
    "CollisionWorld", "Finding", "ThesisChecker", "check_scene", "default_skip",
    "check_pair", "margin", "segment_hits_polyhedron", "led_hits",
]
