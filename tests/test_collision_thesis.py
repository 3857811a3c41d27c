"""The 1985 coarse + fine check (§2.7) on hand-built cases with known answers, and the messages."""

from __future__ import annotations

import numpy as np
import pytest

from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.collision.thesis import check_pair, margin
from valterm.core.collision.world import CollisionWorld, Finding, check_scene, default_skip
from valterm.core.collision.thesis import segment_hits_polyhedron
from valterm.core.events import Collision, Near


def box(lo, hi, name: str = "") -> Polyhedron:
    return Polyhedron.box(np.array(lo, float), np.array(hi, float), name)


def turned(poly: Polyhedron, degrees: float, axis: int = 2) -> Polyhedron:
    t = np.radians(degrees)
    c, s = np.cos(t), np.sin(t)
    r = {2: [[c, -s, 0], [s, c, 0], [0, 0, 1]], 0: [[1, 0, 0], [0, c, -s], [0, s, c]]}[axis]
    centre = poly.centre
    return poly.transformed(np.array(r), centre - np.array(r) @ centre)


def test_margin_grows_with_speed_and_is_clamped():
    assert margin(100) == pytest.approx(25.4)
    assert margin(50) == pytest.approx(12.7)
    assert margin(5) == pytest.approx(2.54) == margin(10)
    assert margin(400) == pytest.approx(25.4)


def test_edge_through_face_with_no_vertex_inside():
    slab = box([-50, -50, -1], [50, 50, 1])
    rod = box([-1, -1, -40], [1, 1, 40])       # pierces the slab; no vertex of either inside the other
    assert check_pair(rod, slab, 0.0) == "collides"
    assert check_pair(slab, rod, 0.0) == "collides"


def test_cross_shaped_bars_collide():
    a = box([-100, -5, -5], [100, 5, 5])
    b = turned(box([-100, -5, -5], [100, 5, 5]), 90)
    assert check_pair(a, b, 0.0) == "collides"


def test_near_but_clear_and_far():
    a = box([0, 0, 0], [10, 10, 10])
    b = box([20, 0, 0], [30, 10, 10])            # 10 mm apart
    assert check_pair(a, b, margin(100)) == "near"
    assert check_pair(box([200, 0, 0], [210, 10, 10]), b, margin(100)) == "clear"


def test_speed_margin_decides_near():
    a = box([0, 0, 0], [10, 10, 10])             # radius 8.66 about (5, 5, 5)
    b = box([28, 0, 0], [40, 10, 10])            # centre 23 mm from b's box: radius + 14.3 needed
    assert check_pair(a, b, margin(100)) == "near"
    assert check_pair(a, b, margin(10)) == "clear"


def test_parallel_faces_touching_is_clear_overlap_collides():
    table = box([0, 0, -20], [100, 100, 0])
    part = box([30, 30, 0], [60, 60, 70])        # resting on the table, face to face
    assert check_pair(part, table, 25.4) == "near"
    sunk = part.translated(np.array([0.0, 0.0, -0.5]))
    assert check_pair(sunk, table, 25.4) == "collides"


def test_rotated_corner_poking_in():
    a = box([0, 0, 0], [50, 50, 50])
    b = turned(turned(box([-20, -20, -20], [20, 20, 20]), 45), 35, axis=0).translated(np.array([75.0, 25, 25]))
    assert check_pair(b, a, 0.0) == "collides"
    assert check_pair(b.translated(np.array([20.0, 0, 0])), a, 25.4) == "near"


def test_one_inside_another_collides():
    outer = box([0, 0, 0], [100, 100, 100])
    inner = box([40, 40, 40], [60, 60, 60])
    # no edge crosses a face (the 1985 blind spot); the containment test sees it, either way round
    assert check_pair(inner, outer, 0.0) == "collides"
    assert check_pair(outer, inner, 0.0) == "collides"
    assert check_pair(inner.translated(np.array([200.0, 0, 0])), outer, 150.0) == "near"


def test_finger_inside_base_collides():
    """Issue 13: FINGER wholly inside BASE at these joints was reported only as near."""
    from valterm.core.simulator import Simulator

    sim = Simulator()
    sim.stand_at([27.96, -203.01, -28.29, 138.39, -59.53, 154.18])
    sim.collision_checks = True
    texts = [e.text for e in sim.check_collisions()]
    assert "FINGER COLLIDES WITH BASE" in texts


def test_segment_hits_polyhedron():
    b = box([0, 0, 0], [10, 10, 10])
    assert segment_hits_polyhedron([5, 5, -5], [5, 5, 5], b)
    assert not segment_hits_polyhedron([15, 5, -5], [15, 5, 5], b)
    assert not segment_hits_polyhedron([4, 5, 4], [6, 5, 6], b)              # wholly inside
    assert segment_hits_polyhedron([4, 5, 4], [6, 5, 6], b, solid=True)
    assert not segment_hits_polyhedron([-5, 5, 10.5], [15, 5, 10.5], b)      # parallel, just above
    assert segment_hits_polyhedron([-5, 5, 9.5], [15, 5, 9.5], b)            # parallel, just inside
    assert not segment_hits_polyhedron([20, 5, 5], [30, 5, 5], b, solid=True)


# -- the scene and its messages ---------------------------------------------------------------

def robot(clamp_at=(0.0, 0.0, 0.0)) -> list[tuple[str, Polyhedron]]:
    off = np.array(clamp_at)
    return [
        ("BASE", box([-50, -50, -300], [50, 50, -200])),
        ("WAIST", box([-40, -40, -205], [40, 40, -100])),        # overlaps BASE: adjacent, not reported
        ("CLAMP", box([-10, -10, -10], [10, 10, 10]).translated(off)),
        ("FINGER", box([-10, -3, 10], [-6, 3, 30]).translated(off)),
        ("FINGER", box([6, -3, 10], [10, 3, 30]).translated(off)),
    ]


def test_message_texts_as_in_fig_c12():
    assert Finding("near", "CLAMP", 10).text == "CLAMP IS NEAR PART 10"
    assert Finding("near", 10, 5).text == "PART 10 IS NEAR PART 5"
    assert Finding("collides", 10, 7).text == "10 COLLIDES WITH 7"
    assert Finding("collides", "CLAMP", 7).text == "CLAMP COLLIDES WITH 7"
    ev = Finding("collides", 10, 7).event()
    assert isinstance(ev, Collision) and ev.text == "10 COLLIDES WITH 7" and (ev.a, ev.b) == ("10", "7")
    assert isinstance(Finding("near", "CLAMP", 10).event(), Near)


def test_clamp_near_then_collides():
    part = box([30, -10, -10], [50, 10, 10])
    far = box([500, 500, 500], [510, 510, 510])
    found = check_scene(robot(), [far, part])
    assert [f.text for f in found] == ["CLAMP IS NEAR PART 2", "FINGER IS NEAR PART 2"]
    found = check_scene(robot((35.0, 0.0, 0.0)), [far, part])
    texts = [f.text for f in found]
    assert "CLAMP COLLIDES WITH 2" in texts and "CLAMP IS NEAR PART 2" not in texts
    assert all("BASE" not in t and "WAIST" not in t for t in texts)


def test_carried_part_messages_and_near_with_collision():
    held = box([-8, -8, 12], [8, 8, 28])                  # between the fingers
    other = box([-20, -20, 25], [20, 20, 60])             # overlaps the held part's top
    near_only = box([0, 0, 50], [20, 20, 70])             # close above, clear
    found = check_scene(robot(), [held, other, near_only], carried=[1])
    texts = [f.text for f in found]
    assert "1 COLLIDES WITH 2" in texts
    assert "PART 1 IS NEAR PART 3" in texts
    assert not any("IS NEAR PART 1" in t or "WITH 1" in t for t in texts)   # held: not against the robot
    both = check_scene(robot(), [held, other, near_only], carried=[1], near_with_collision=True)
    texts = [f.text for f in both]
    assert texts.index("PART 1 IS NEAR PART 2") + 1 == texts.index("1 COLLIDES WITH 2")


def test_link_against_link_and_skips():
    labels = ["BASE", "WAIST", "UPPER ARM", "FOREARM", "WRIST", "CLAMP", "FINGER", "FINGER"]
    skip = default_skip(labels)
    assert (0, 1) in skip and (1, 2) in skip and (4, 6) in skip and (6, 7) in skip and (5, 7) in skip
    assert (0, 3) not in skip and (2, 5) not in skip
    links = robot((0.0, 0.0, -200.0))                     # clamp driven down through the base top
    found = check_scene(links, [])
    assert [f.text for f in found][0] == "CLAMP COLLIDES WITH BASE"   # WAIST is next to CLAMP here: skipped
    inside = check_scene(robot((0.0, 0.0, -250.0)), [])      # wholly inside the base: containment
    assert "CLAMP COLLIDES WITH BASE" in [f.text for f in inside]
    assert not any(f.a == "WAIST" and f.b == "BASE" for f in found)


def test_findings_order_is_stable_and_deduplicated():
    parts = [box([30, -10, -10], [50, 10, 10]), box([-50, -10, -10], [-30, 10, 10])]
    world = CollisionWorld([label for label, _ in robot()])
    links = [p for _, p in robot()]
    first = world.check(links, parts)
    assert first == world.check(links, parts)
    assert len({f.text for f in first}) == len(first)
    assert [f.b for f in first if f.a == "CLAMP"] == [1, 2]


def test_world_rejects_wrong_link_count():
    world = CollisionWorld(["BASE", "CLAMP"])
    with pytest.raises(ValueError):
        world.check([box([0, 0, 0], [1, 1, 1])], [])


def test_separating_plane_shortcut_never_changes_the_fine_answer():
    """The fine check's shortcut (a face plane clear of the other's vertices by 1 mm) against
    the full edge-face test, over random boxes and prisms from overlapping to a hair apart."""
    from valterm.core.collision.thesis import Scene, fine

    rng = np.random.default_rng(15)
    polys = []
    for n in range(1200):
        k = int(rng.choice([4, 6, 8]))
        angles = np.sort(rng.uniform(0, 2 * np.pi, k))
        radius = rng.uniform(10, 80)
        front = np.column_stack([radius * np.cos(angles), radius * np.sin(angles), np.zeros(k)])
        prism = Polyhedron.from_polygons(front, front + [0.0, 0.0, rng.uniform(5, 120)])
        t = np.radians(rng.uniform(0, 360, 2))
        turn = np.array([[np.cos(t[0]), -np.sin(t[0]), 0], [np.sin(t[0]), np.cos(t[0]), 0], [0, 0, 1]])
        tip = np.array([[1, 0, 0], [0, np.cos(t[1]), -np.sin(t[1])], [0, np.sin(t[1]), np.cos(t[1])]])
        # every other polyhedron placed about as far from the one before as their sizes
        offset = rng.normal(size=3)
        offset *= rng.uniform(0.0, 1.6) * 80.0 / np.linalg.norm(offset)
        polys.append(prism.transformed(turn @ tip, offset if n % 2 else np.zeros(3)))
    scene = Scene.of(polys)
    a, b = np.arange(0, 1200, 2), np.arange(1, 1200, 2)
    full = fine(scene, a, b, shortcut=False)
    assert np.array_equal(fine(scene, a, b), full)
    fired = 0
    for i in range(600):                            # one pair at a time: the shortcut then fires
        one, two = a[i:i + 1], b[i:i + 1]
        assert fine(scene, one, two)[0] == full[i], i
        fired += int(fine_separated(scene, one, two))
    assert 100 < full.sum() < 500 and fired > 100, (full.sum(), fired)


def fine_separated(scene, a, b) -> bool:
    """Whether the shortcut answers this pair (the signed distances as ``fine`` computes them)."""
    from valterm.core.collision.thesis import _separated

    lay, v = scene.layout, scene.vertices
    src, dst = np.concatenate([a, b]), np.concatenate([b, a])
    seg = v[lay.edge_idx[src]]
    poly = v[lay.face_idx[dst]]
    normal = np.cross(poly[:, :, 1] - poly[:, :, 0], poly[:, :, 2] - poly[:, :, 0])
    normal /= np.maximum(np.linalg.norm(normal, axis=-1, keepdims=True), 1e-300)
    off = np.einsum("nfk,nfk->nf", normal, poly[:, :, 0])
    s = np.einsum("nepk,nfk->nepf", seg, normal) - off[:, None, None, :]
    outward = -np.sign(np.einsum("nfk,nk->nf", normal, scene.centres[dst]) - off)
    return bool(_separated(s, outward, len(a))[0])
