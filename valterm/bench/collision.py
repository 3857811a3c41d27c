"""Timing of one motion step's collision check, thesis and fcl (for ``valterm bench``).

A step is timed as the simulator does it: the robot links have moved since the last step
(here they alternate between the given pose and the same pose turned 1 degree about the
world Z axis, so fcl re-places every link each step) and the whole scene is checked.
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING, Collection, Sequence

import numpy as np

from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.collision.world import CollisionWorld

if TYPE_CHECKING:
    from valterm.core.simulator import Simulator


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


# -- the goals' own scenes (issue 15): the real PUMA model among n parts -------------------

def ring_cell(n: int, seed: int = 1985) -> list[Polyhedron]:
    """``n`` boxes around the robot at a constant density: the ring grows with n, as a bigger
    cell does (30 parts reach about 1 m, 300 about 3 m), so most parts are far from the arm."""
    rng = np.random.default_rng(seed)
    outer = np.sqrt(350.0 ** 2 + n * 30_000.0)
    out = []
    for i in range(n):
        angle = rng.uniform(-np.pi, np.pi)
        r = np.sqrt(rng.uniform(350.0 ** 2, outer ** 2))
        c = np.array([r * np.cos(angle), r * np.sin(angle), rng.uniform(-600, 100)])
        half = rng.uniform(30, 120, 3)
        out.append(Polyhedron.box(c - half, c + half, str(i + 1)))
    return out


def sweep_path(poses: int = 120) -> np.ndarray:
    """A joint path that turns JT1 once round with the hand low among the parts (3 degrees a step)."""
    j1 = np.linspace(-180.0, 180.0, poses)
    return np.column_stack([j1, np.full(poses, -150.0), np.full(poses, 150.0),
                            np.zeros(poses), np.full(poses, 40.0), np.zeros(poses)])


def _old_check(sim: "Simulator", world: CollisionWorld, said: set[tuple[str, object, object]]) -> int:
    """The pre-issue-15 path: ten Polyhedron objects per pose, the whole scene concatenated."""
    findings = world.check(sim.robot_polyhedra(), sim.cell.objects, (), sim.speed)
    now = {(f.kind, f.a, f.b) for f in findings}
    events = [f.event() for f in findings if (f.kind, f.a, f.b) not in said]
    said.clear()
    said.update(now)
    return len(events)


def bench_collision_per_pose(n_parts: int = 30, rounds: int = 5) -> dict[str, float]:
    """µs per motion pose as ``run --collisions`` pays it (link frames, swept substeps, the check,
    the events), the new path and the old one on the same poses; median of ``rounds``."""
    from valterm.core.cell.workcell import WorkCell
    from valterm.core.simulator import Simulator

    sim = Simulator(WorkCell(objects=ring_cell(n_parts)))
    path = [[float(v) for v in pose] for pose in sweep_path()]
    world = CollisionWorld(sim.model.names)
    said: set[tuple[str, object, object]] = set()

    def new() -> int:
        count = 0
        previous = path[0]
        for pose in path:
            sim.joints = pose
            count += sum(1 for _ in sim.check_collisions(previous))
            previous = pose
        return count

    def old() -> int:
        count = 0
        for pose in path:
            sim.joints = pose
            count += _old_check(sim, world, said)
        return count

    times: dict[str, list[float]] = {"new": [], "old": []}
    found = {"new": new(), "old": old()}               # warm up: layouts, caches
    for _ in range(rounds):
        for name, func in (("new", new), ("old", old)):
            start = time.perf_counter()
            func()
            times[name].append((time.perf_counter() - start) / len(path) * 1e6)
    return {
        "us_per_pose": float(np.median(times["new"])),
        "old_us_per_pose": float(np.median(times["old"])),
        "events_new": float(found["new"]),
        "events_old": float(found["old"]),
    }


def carried_boxes(count: int) -> list[Polyhedron]:
    """``count`` boxes held in the clamp, stacked along its approach axis, in the flange frame:
    a part and what rests on it, carried as GRASP carries them."""
    boxes = []
    for i in range(count):
        lo = np.array([-20.0, -30.0, 145.0 + 45.0 * i])      # between the open fingers, then beyond
        boxes.append(Polyhedron.box(lo, lo + np.array([40.0, 60.0, 40.0]), f"C{i + 1}"))
    return boxes


def bench_puma_step(n_parts: int = 30, rounds: int = 5, steps: int = 60, carried: int = 2) -> dict[str, float]:
    """µs per step of the thesis check and of fcl, both fed by link frames: the PUMA's link
    polyhedra plus ``carried`` parts in the clamp (the moving bodies) among ``n_parts`` parts;
    and fcl on placed polyhedra (``ExactChecker``, the path before) as the peer."""
    from valterm.core.cell.workcell import WorkCell
    from valterm.core.collision.frames import RobotScene
    from valterm.core.simulator import Simulator

    parts = ring_cell(n_parts)
    sim = Simulator(WorkCell(objects=parts))
    held = tuple(range(n_parts + 1, n_parts + carried + 1))     # object numbers, 1-based
    frames, polys, objects = [], [], []
    for pose in sweep_path(steps):
        sim.joints = [float(v) for v in pose]
        f = sim.model.link_frames(sim.joints, sim.base)
        flange = f[-1]
        boxes = [box.transformed(flange[:3, :3], flange[:3, 3]) for box in carried_boxes(carried)]
        frames.append(f)
        polys.append(sim.robot_polyhedra())
        objects.append([*parts, *boxes])
    scenes = {}
    for kind in ("thesis", "exact"):
        scenes[kind] = RobotScene(sim.model.names, sim.model.frames.tolist(), checker=kind)  # type: ignore[arg-type]
        scenes[kind].set_shapes(sim.model.shapes(sim.gap))
    exact_old = CollisionWorld(sim.model.names, checker="exact")

    def run(kind: str) -> None:
        if kind == "fcl_polyhedra":
            for p, o in zip(polys, objects):
                exact_old.check(p, o, held)
        else:
            for f, o in zip(frames, objects):
                scenes[kind].check(f, o, held)

    runs: dict[str, list[float]] = {"thesis": [], "exact": [], "fcl_polyhedra": []}
    for kind in runs:
        run(kind)                                       # warm up: layouts, fcl objects
    for _ in range(rounds):
        for kind in runs:
            start = time.perf_counter()
            run(kind)
            runs[kind].append((time.perf_counter() - start) / steps * 1e6)
    return {"thesis_us": float(np.median(runs["thesis"])), "fcl_us": float(np.median(runs["exact"])),
            "fcl_polyhedra_us": float(np.median(runs["fcl_polyhedra"])),
            "links": float(len(sim.model.names)), "carried": float(carried), "parts": float(n_parts)}
