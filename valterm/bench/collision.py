"""Timing of one motion step's collision check, thesis and fcl (for ``valterm bench``).

A step is timed as the simulator does it: the robot links have moved since the last step
(here they alternate between the given pose and the same pose turned 1 degree about the
world Z axis, so fcl re-places every link each step) and the whole scene is checked.
"""

from __future__ import annotations

import time
from typing import Collection, Sequence

import numpy as np

from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.collision.world import CollisionWorld


def _turn(poly: Polyhedron, degrees: float) -> Polyhedron:
    t = np.radians(degrees)
    rz = np.array([[np.cos(t), -np.sin(t), 0.0], [np.sin(t), np.cos(t), 0.0], [0.0, 0.0, 1.0]])
    return poly.transformed(rz, np.zeros(3))


def _time_per_step(world: CollisionWorld, poses: list[list[Polyhedron]], objects: Sequence[Polyhedron],
                   carried: Collection[int], speed: float, steps: int) -> tuple[float, int, int]:
    found = world.check(poses[0], objects, carried, speed)   # warm up: layouts, pairs, fcl objects
    world.check(poses[1], objects, carried, speed)
    best = float("inf")
    for _ in range(5):  # best of five runs: the machine's noise, not the code's
        start = time.perf_counter()
        for n in range(steps):
            world.check(poses[n & 1], objects, carried, speed)
        best = min(best, (time.perf_counter() - start) / steps)
    near = sum(f.kind == "near" for f in found)
    return best * 1e6, near, len(found) - near


def bench_collision_step(links: Sequence[tuple[str, Polyhedron]], objects: Sequence[Polyhedron],
                         carried: Collection[int] = (), speed: float = 100.0, steps: int = 200) -> dict:
    """µs per motion step for the thesis and the fcl checker, with the scene's size and findings."""
    labels = [label for label, _ in links]
    poses = [[p for _, p in links], [_turn(p, 1.0) for _, p in links]]
    thesis = CollisionWorld(labels, checker="thesis")
    exact = CollisionWorld(labels, checker="exact")
    t_us, t_near, t_hit = _time_per_step(thesis, poses, objects, carried, speed, steps)
    e_us, _, e_hit = _time_per_step(exact, poses, objects, carried, speed, steps)
    return {
        "links": len(links),
        "objects": len(objects),
        "pairs": len(thesis.pairs(len(objects), carried).moving),
        "thesis_us_per_step": round(t_us, 1),
        "fcl_us_per_step": round(e_us, 1),
        "thesis_near": t_near,
        "thesis_collides": t_hit,
        "fcl_collides": e_hit,
    }


def demo_links() -> list[tuple[str, Polyhedron]]:
    """A stand-in PUMA of nine boxes (base .. fingers) for benchmarking without the model."""
    spec = [
        ("BASE", (-150, -150, -660), (150, 150, -200)),
        ("WAIST", (-100, -100, -200), (100, 100, 0)),
        ("SHOULDER", (-80, 0, -80), (80, 160, 80)),
        ("UPPER ARM", (-60, 100, -40), (480, 200, 40)),
        ("FOREARM", (380, 120, -40), (460, 200, 420)),
        ("WRIST", (390, 130, 420), (450, 190, 480)),
        ("CLAMP", (395, 135, 480), (445, 185, 540)),
        ("FINGER", (395, 150, 540), (405, 170, 600)),
        ("FINGER", (435, 150, 540), (445, 170, 600)),
    ]
    out = []
    for label, lo, hi in spec:
        # turned and tipped a little so nothing is axis-aligned, as a real pose is
        box = Polyhedron.box(np.array(lo, float), np.array(hi, float), label)
        out.append((label, _turn(box, 7.0).transformed(np.eye(3), np.array([0.0, 0.0, 0.0]))))
    return out


def demo_objects(n: int = 14, seed: int = 1985) -> list[Polyhedron]:
    """``n`` boxes scattered around the robot, a few near the hand, like the PROCESS cell."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n):
        angle = rng.uniform(-np.pi, np.pi)
        r = rng.uniform(350, 800)
        c = np.array([r * np.cos(angle), r * np.sin(angle), rng.uniform(-600, 100)])
        half = rng.uniform(40, 180, 3)
        out.append(Polyhedron.box(c - half, c + half, str(i + 1)))
    return out
