"""The python-fcl second opinion: same pairs, collides only, sees one solid inside another."""

from __future__ import annotations

import numpy as np

from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.collision.world import CollisionWorld
from valterm.core.collision.exact import ExactChecker, collides, distance, outward_faces


def box(lo, hi) -> Polyhedron:
    return Polyhedron.box(np.array(lo, float), np.array(hi, float))


def rz(degrees: float) -> np.ndarray:
    t = np.radians(degrees)
    return np.array([[np.cos(t), -np.sin(t), 0], [np.sin(t), np.cos(t), 0], [0, 0, 1.0]])


def test_faces_are_wound_outward_even_for_a_flipped_file():
    flipped = Polyhedron(box([0, 0, 0], [1, 2, 3]).vertices[[3, 2, 1, 0, 7, 6, 5, 4]])
    for poly in (box([0, 0, 0], [1, 2, 3]), flipped):
        v = poly.vertices - poly.centre
        for face in outward_faces(poly):
            pts = v[face]
            normal = np.cross(pts, np.roll(pts, -1, axis=0)).sum(axis=0)
            assert np.dot(normal, pts.mean(axis=0)) > 0


def test_pairs_and_inside():
    a = box([0, 0, 0], [10, 10, 10])
    assert collides(a, box([5, 5, 5], [20, 20, 20]))
    assert not collides(a, box([12, 0, 0], [20, 10, 10]))
    assert collides(box([4, 4, 4], [6, 6, 6]), a)              # inside: fcl sees it
    assert distance(a, box([12, 0, 0], [20, 10, 10])) == np.float64(2.0)


def test_checker_follows_rigid_moves_and_reshapes():
    checker = ExactChecker()
    still = box([100, -10, -10], [120, 10, 10])
    arm = box([0, -5, -5], [80, 5, 5])
    mv, st = np.array([0]), np.array([1])
    assert not checker.colliding([arm, still], mv, st)[0]
    for degrees in (5, 0, -5):                                  # swing through: rigid moves only
        moved = arm.transformed(rz(degrees), np.array([30.0, 0, 0]))
        assert checker.colliding([moved, still], mv, st)[0]
        assert checker.colliding([moved, still], mv, st)[0]     # fresh result each query
    assert not checker.colliding([arm.transformed(rz(90), np.zeros(3)), still], mv, st)[0]
    longer = box([0, -5, -5], [105, 5, 5])                      # not a rigid move: rebuilt
    assert checker.colliding([longer, still], mv, st)[0]
    assert not checker.colliding([arm, still], mv, st)[0]


def test_world_exact_reports_collides_only():
    labels = ["BASE", "CLAMP"]
    links = [box([-50, -50, -300], [50, 50, -200]), box([-10, -10, -10], [10, 10, 10])]
    parts = [box([5, -5, -5], [30, 5, 5]), box([40, -5, -5], [60, 5, 5]), box([-3, -3, -3], [6, 3, 3])]
    exact = CollisionWorld(labels, checker="exact")
    texts = [f.text for f in exact.check(links, parts)]
    assert texts == ["CLAMP COLLIDES WITH 1", "CLAMP COLLIDES WITH 3"]   # 3 is inside the clamp
    thesis = [f.text for f in CollisionWorld(labels).check(links, parts)]
    assert "CLAMP COLLIDES WITH 1" in thesis and "CLAMP COLLIDES WITH 3" in thesis
    held = [f.text for f in exact.check(links, parts, carried=[1])]
    assert held == ["CLAMP COLLIDES WITH 3", "1 COLLIDES WITH 3"]
