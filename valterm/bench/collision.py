"""Timing of one motion step's collision check, thesis and fcl (for ``valterm bench``).

A step is timed as the simulator does it: the robot links have moved since the last step
(here they alternate between the given pose and the same pose turned 1 degree about the
world Z axis, so fcl re-places every link each step) and the whole scene is checked.
"""

from __future__ import annotations

import math
import time
from typing import Any, TYPE_CHECKING, Callable, Collection, Sequence

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
                         carried: Collection[int] = (), speed: float = 100.0, steps: int = 200) -> dict[str, Any]:
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


def _old_check(sim: "Simulator", pose: list[float], world: CollisionWorld,
               said: set[tuple[str, object, object]]) -> int:
    """The pre-issue-15 path: ten Polyhedron objects per pose, the whole scene concatenated."""
    findings = world.check(sim.model.place(pose, sim.gap, sim.base), sim.cell.objects, (), sim.speed)
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
            count += sum(1 for _ in sim.check_collisions(previous, at=pose))
            previous = pose
        return count

    def old() -> int:
        count = 0
        for pose in path:
            count += _old_check(sim, pose, world, said)
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
        joints = [float(v) for v in pose]
        f = sim.model.link_frames(joints, sim.base)
        flange = f[-1]
        boxes = [box.transformed(flange[:3, :3], flange[:3, 3]) for box in carried_boxes(carried)]
        frames.append(f)
        polys.append(sim.model.place(joints, sim.gap, sim.base))
        objects.append([*parts, *boxes])
    scenes = {}
    for kind in ("thesis", "exact"):
        scenes[kind] = RobotScene(sim.model.names, sim.model.frames.tolist(), checker=kind)
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


# -- issue 25: what users pay on a dense cell, against plain python-fcl on the same meshes ---

def dense_cell(n: int, seed: int = 2025) -> list[Polyhedron]:
    """``n`` parts within the arm's reach: four tables round the robot (tops 300 mm below the
    shoulder) and ``n - 4`` boxes standing on them, 400 to 1100 mm from the JT1 axis."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(4):                                   # the tables, one each side of the robot
        turn = np.radians(90.0 * i)
        c = np.array([750.0 * np.cos(turn), 750.0 * np.sin(turn), -340.0])
        half = np.array([250.0, 250.0, 20.0])
        out.append(Polyhedron.box(c - half, c + half, f"T{i + 1}"))
    for i in range(max(n - 4, 0)):
        angle = rng.uniform(-np.pi, np.pi)
        r = rng.uniform(520.0, 980.0)
        half = rng.uniform(15.0, 45.0, 3)
        c = np.array([r * np.cos(angle), r * np.sin(angle), -320.0 + half[2]])
        out.append(Polyhedron.box(c - half, c + half, str(i + 5)))
    return out


def move_program(moves: int = 600, seed: int = 25) -> np.ndarray:
    """Joint goals of a program of ``moves`` MOVEs over the tables: the hand 40 to 300 mm above
    their tops, turning about; (moves + 1, 6), the first the start."""
    from valterm.core.kinematics import fk_batch, robot_geometry

    rng = np.random.default_rng(seed)
    stops = robot_geometry().stops_array
    low = np.maximum(stops[:, 0], [-180, -120, 100, -90, -90, -180])
    high = np.minimum(stops[:, 1], [180, -40, 200, 90, 90, 180])
    goals = np.zeros((0, 6))
    while len(goals) <= moves:
        q = rng.uniform(low, high, (4096, 6))
        xyz, _ = fk_batch(q)
        r, z = np.hypot(xyz[:, 0], xyz[:, 1]), xyz[:, 2]
        ok = (r > 450) & (r < 1000) & (z > -260) & (z < 0)
        goals = np.concatenate([goals, q[ok]])
    return goals[: moves + 1]


def _fcl_plain(frames: list[np.ndarray], local: list[np.ndarray], owners: np.ndarray,
               parts: Sequence[Polyhedron]) -> Callable[[], int]:
    """Plain python-fcl on the same meshes: link objects built once, moved by their frames each
    pose, one AABB tree of links collided with one of the parts; the contacts counted."""
    import fcl

    from valterm.core.collision.exact import convex

    links, centres = [], []
    for shape in local:
        poly = Polyhedron(shape)
        links.append(fcl.CollisionObject(convex(poly, poly.centre)))
        centres.append(poly.centre)
    tree = fcl.DynamicAABBTreeCollisionManager()
    tree.registerObjects(links)
    tree.setup()
    objs = [fcl.CollisionObject(convex(p), fcl.Transform(np.eye(3), p.centre)) for p in parts]
    still = fcl.DynamicAABBTreeCollisionManager()
    still.registerObjects(objs)
    still.setup()
    local_centres = np.array(centres)

    def run() -> int:
        hits = 0
        for f in frames:
            placed = f[owners]
            rot = placed[:, :3, :3]
            at = np.einsum("lij,lj->li", rot, local_centres) + placed[:, :3, 3]
            for obj, r, t in zip(links, rot, at):
                obj.setRotation(r)
                obj.setTranslation(t)
            tree.update()
            data = fcl.CollisionData(fcl.CollisionRequest(num_max_contacts=1 << 30), fcl.CollisionResult())
            tree.collide(still, data, fcl.defaultCollisionCallback)
            hits += len(data.result.contacts)
        return hits

    return run


def bench_dense_run(n_parts: int = 30, moves: int = 600, rounds: int = 3) -> dict[str, float]:
    """µs per pose of a program of ``moves`` joint MOVEs on ``dense_cell(n_parts)``, as
    ``run --collisions`` pays it (the simulator's motion with checks on, less the same motion
    with them off), and plain python-fcl at the same poses (link frames included)."""
    from valterm.core.cell.workcell import WorkCell
    from valterm.core.simulator import Simulator

    goals = move_program(moves)
    parts = dense_cell(n_parts)

    def program(checks: bool, keep: bool = False) -> tuple[int, int, list[np.ndarray]]:
        """The program played: its poses, the findings said and (``keep``) each pose's link
        frames for the peer; kept only where untimed (the motion with the checks off is
        what ``run`` pays without them: no frames of its own to take away)."""
        sim = Simulator(WorkCell(objects=list(parts)))
        sim.stand_at(goals[0])
        sim.collision_checks = checks
        poses = found = 0
        frames: list[np.ndarray] = []
        for goal in goals[1:]:
            for event in sim.move_joints(goal):
                kind = type(event).__name__
                if kind == "PoseEvent":
                    poses += 1
                    if keep:
                        frames.append(sim.model.link_frames(sim.joints, sim.base))
                elif kind in ("Collision", "Near"):
                    found += 1
        return poses, found, frames

    poses, _, frames = program(False, keep=True)
    sim = Simulator(WorkCell(objects=list(parts)))
    plain = _fcl_plain(frames, sim.model.shapes(sim.gap), sim.model.frames, parts)
    link_frames = sim.model.link_frames
    base = sim.base
    joints = [[float(v) for v in f] for f in _poses(goals, sim)]

    def frames_only() -> None:
        for q in joints:
            link_frames(q, base)

    times: dict[str, list[float]] = {"on": [], "off": [], "fcl": [], "frames": []}
    found = program(True)[1]
    hits = plain()
    for _ in range(rounds):
        for name, func in (("on", lambda: program(True)), ("off", lambda: program(False)),
                           ("fcl", plain), ("frames", frames_only)):
            start = time.perf_counter()
            func()
            times[name].append((time.perf_counter() - start) / poses * 1e6)
    on, off = float(np.median(times["on"])), float(np.median(times["off"]))
    fcl_us = float(np.median(times["fcl"])) + float(np.median(times["frames"]))
    return {"us_per_pose": on - off, "fcl_us_per_pose": fcl_us, "poses": float(poses),
            "events": float(found), "fcl_contacts": float(hits), "motion_us_per_pose": off}


def _poses(goals: np.ndarray, sim: "Simulator") -> list[list[float]]:
    """Every pose the program's MOVEs pass through (as the simulator plays them)."""
    from valterm.core.motion import joint_increment, joint_path

    out: list[list[float]] = []
    here = [float(v) for v in goals[0]]
    for goal in goals[1:]:
        path = joint_path(here, [float(v) for v in goal], joint_increment(sim.speed))
        out += [[float(v) for v in pose] for pose in path]
        here = out[-1]
    return out


def bench_dense_check(n_parts: int, moves: int = 100, rounds: int = 3) -> dict[str, float]:
    """µs per pose on ``dense_cell(n_parts)`` along a program of ``moves`` MOVEs: the pose check
    alone, the pose check with the step before it swept, and plain python-fcl (link frames
    included) at the same poses; the best of ``rounds``."""
    from valterm.core.cell.workcell import WorkCell
    from valterm.core.simulator import Simulator

    parts = dense_cell(n_parts)
    sim = Simulator(WorkCell(objects=list(parts)))
    poses = _poses(move_program(moves), sim)
    frames = [sim.model.link_frames(q) for q in poses]
    plain = _fcl_plain(frames, sim.model.shapes(sim.gap), sim.model.frames, parts)
    link_frames = sim.model.link_frames

    def run(swept: bool) -> None:
        previous = poses[0]
        for pose in poses:
            for _ in sim.check_collisions(previous if swept else None, at=pose):
                pass
            previous = pose

    def frames_only() -> None:
        for pose in poses:
            link_frames(pose)

    best: dict[str, float] = {}
    for _ in range(rounds):
        for name, func in (("pose", lambda: run(False)), ("swept", lambda: run(True)), ("fcl", plain),
                           ("frames", frames_only)):
            start = time.perf_counter()
            func()
            best[name] = min(best.get(name, math.inf), (time.perf_counter() - start) / len(poses) * 1e6)
    return {"check_us": best["pose"], "swept_us": best["swept"], "fcl_us": best["fcl"] + best["frames"]}
