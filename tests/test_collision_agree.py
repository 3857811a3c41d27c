"""The 1985 fine check (with its containment test) and python-fcl agree on every pair.

Cases within a hair of touching are the tolerance band of both methods: a case counts only
when fcl gives the same answer with the moving solid shrunk and grown by 0.05 mm.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.collision.thesis import check_pair
from valterm.core.collision.world import CollisionWorld
from valterm.bench.collision import bench_collision_step, demo_links, demo_objects
from valterm.core.collision.exact import collides

CELLS = Path(__file__).resolve().parent.parent / "cells"
BAND = 0.05  # mm


def rotation(rng: np.random.Generator) -> np.ndarray:
    q = rng.normal(size=4)
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def scaled(poly: Polyhedron, by: float) -> Polyhedron:
    """Grown (by > 0) or shrunk about the centre so every vertex moves about ``by`` mm."""
    c = poly.centre
    f = 1.0 + by / poly.radius
    return Polyhedron(c + (poly.vertices - c) * f)


def inside(a: Polyhedron, b: Polyhedron) -> bool:
    """Every vertex of a within the convex b (half-space test with the outward face normals)."""
    normals = b.face_normals()
    first = np.array([b.vertices[f[0]] for f in b.topology.faces])
    return bool(np.all(np.einsum("vfk,fk->vf", a.vertices[:, None, :] - first[None], normals) <= 1e-9))


def robust(a: Polyhedron, b: Polyhedron) -> bool | None:
    """fcl's answer if it holds across the tolerance band, else None (touching)."""
    lo, hi = collides(scaled(a, -BAND), b), collides(scaled(a, BAND), b)
    return lo if lo == hi else None


def compare(a: Polyhedron, b: Polyhedron, stats: dict) -> None:
    truth = robust(a, b)
    if truth is None:
        stats["band"] += 1
        return
    thesis = check_pair(a, b, 1e6) == "collides"   # a huge margin: always on to the fine check
    assert thesis == truth, (a.vertices, b.vertices)
    if inside(a, b) or inside(b, a):
        stats["inside"] += 1
        return
    stats["hit" if truth else "miss"] += 1


def test_random_boxes_agree():
    rng = np.random.default_rng(1985)
    stats = {"hit": 0, "miss": 0, "band": 0, "inside": 0}
    for _ in range(400):
        a = Polyhedron.box(-rng.uniform(2, 60, 3), rng.uniform(2, 60, 3))
        b = Polyhedron.box(-rng.uniform(2, 60, 3), rng.uniform(2, 60, 3))
        if rng.random() < 0.5:
            a = a.transformed(rotation(rng), np.zeros(3))
        b = b.transformed(rotation(rng), rng.uniform(-90, 90, 3))
        if rng.random() < 0.05:                     # now and then a small one wholly inside
            b = Polyhedron(a.centre + (a.vertices - a.centre) * 0.3).transformed(np.eye(3), np.zeros(3))
        compare(a, b, stats)
    assert stats["hit"] > 80 and stats["miss"] > 80 and stats["inside"] > 0, stats


def test_touching_face_to_face_is_the_band():
    table = Polyhedron.box(np.array([0.0, 0, -20]), np.array([100.0, 100, 0]))
    part = Polyhedron.box(np.array([30.0, 30, 0]), np.array([60.0, 60, 70]))
    assert robust(part, table) is None
    assert check_pair(part, table, 25.4) == "near"          # touching is not colliding in 1985 terms
    assert check_pair(part.translated(np.array([0, 0, 0.1])), table, 0) == "near"
    assert collides(part.translated(np.array([0, 0, -0.1])), table)


def test_inside_is_reported_by_both():
    outer = Polyhedron.box(np.zeros(3), np.full(3, 100.0))
    inner = Polyhedron.box(np.full(3, 30.0), np.full(3, 60.0))
    assert inside(inner, outer)
    assert collides(inner, outer) and check_pair(inner, outer, 0) == "collides"


@pytest.mark.parametrize("name", ["PROCESS", "CONV", "DEMO3"])
def test_bundled_cells_agree_along_a_sweep(name):
    path = CELLS / f"{name}.SET"
    if not path.exists():
        pytest.skip(f"{path.name} not bundled")
    from valterm.core.files.setup import read_setup
    objects = read_setup(path).objects
    rng = np.random.default_rng(7)
    stats = {"hit": 0, "miss": 0, "band": 0, "inside": 0}
    lo = np.min([p.extreme_box[0] for p in objects], axis=0)
    hi = np.max([p.extreme_box[1] for p in objects], axis=0)
    for moving in range(len(objects)):
        part = objects[moving]
        for _ in range(12):                        # the part carried to random places in the cell
            to = rng.uniform(lo, hi)
            placed = part.transformed(rotation(rng), np.zeros(3))
            placed = placed.translated(to - placed.centre)
            for other, b in enumerate(objects):
                if other != moving:
                    compare(placed, b, stats)
    assert stats["hit"] > 5 and stats["miss"] > 50, stats


def test_scene_checkers_agree_on_the_demo_step():
    links, objects = demo_links(), demo_objects()
    labels = [label for label, _ in links]
    polys = [p for _, p in links]
    thesis = {(f.a, f.b) for f in CollisionWorld(labels).check(polys, objects) if f.kind == "collides"}
    exact = {(f.a, f.b) for f in CollisionWorld(labels, checker="exact").check(polys, objects)}
    assert thesis == exact and thesis


def test_bench_reports_both_checkers():
    result = bench_collision_step(demo_links(), demo_objects(), steps=5)
    assert result["objects"] == 14 and result["links"] == 9
    assert result["thesis_us_per_step"] > 0 and result["fcl_us_per_step"] > 0
    assert result["thesis_collides"] == result["fcl_collides"]
