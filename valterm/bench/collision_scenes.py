"""Issue 40: the collision bench's scenes as users meet them, and the peers that check them.

* ``crowded_cell``: parts standing round the path of a program the arm clears: no part is met
  at a pose or between two, but every part comes within 5-30 mm of the moving arm.
* ``heavy_cell``: parts the arm passes through (many contacts), and a 0.5 mm plate the hand
  goes through between two poses without touching it at either: only a check that looks
  between poses finds it.

Both are made from a seed, the same every run. The arm is the thesis's PUMA playing the
program at SPEED 100 (12 degrees a step), so the program's steps are long.

The peers, on the same poses: plain python-fcl per pose (an AABB tree of the links collided
with one of the parts), and the same plus fcl's ``continuousCollide`` between consecutive
poses on the link x part pairs whose boxes (the link's at the two poses, joined) meet.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable

import numpy as np

from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.events import Collision, PoseEvent

if TYPE_CHECKING:
    from valterm.core.simulator import Simulator

CLEAR_FROM, CLEAR_TO = 5.0, 30.0    # mm: how far a crowded cell's parts stand from the moving arm
PLATE = 0.5                          # mm: the thin plate's thickness
SUBSTEPS = 24                        # samples a step when placing parts (half a degree apart)


@dataclass
class CellScene:
    """A cell and the program played in it: its parts, the MOVEs' joint goals (the first the
    start) and every pose the simulator shows on the way."""

    name: str
    parts: list[Polyhedron]
    goals: np.ndarray
    poses: np.ndarray                        # (poses, 6) degrees, the start first
    plate: int | None = None                 # the thin plate's part number (1-based)
    plate_step: int | None = None            # the pose the hand reaches through it
    notes: dict[str, float] = field(default_factory=dict)


def _simulator(parts: list[Polyhedron]) -> Simulator:
    from valterm.core.cell.workcell import WorkCell
    from valterm.core.simulator import Simulator

    return Simulator(WorkCell(objects=list(parts)))


def program_poses(goals: np.ndarray) -> np.ndarray:
    """Every pose the program's MOVEs pass through at SPEED 100, the start first."""
    sim = _simulator([])
    sim.stand_at(goals[0])
    sim.collision_checks = False
    out = [list(sim.joints)]
    for goal in goals[1:]:
        for event in sim.move_joints(goal):
            if type(event).__name__ == "PoseEvent":
                out.append(list(sim.joints))
    return np.array(out, dtype=float)


def _between(poses: np.ndarray, substeps: int) -> np.ndarray:
    """The poses and ``substeps - 1`` joint-interpolated poses between each two (the joints
    move linearly over a step, as the simulator's swept check has them)."""
    t = np.arange(substeps)[:, None] / substeps
    q0, q1 = poses[:-1], poses[1:]
    turn = (q1 - q0 + 180.0) % 360.0 - 180.0
    inner = q0[:, None, :] + turn[:, None, :] * t[None]
    return np.concatenate([inner.reshape(-1, 6), poses[-1:]])


class _ArmSamples:
    """The arm at many poses as one static fcl AABB tree: how near a part comes to the arm."""

    def __init__(self, sim: Simulator, joints: np.ndarray) -> None:
        import fcl

        from valterm.core.collision.exact import convex

        frames = sim.model.link_frames_batch(joints)
        shapes = sim.model.shapes(sim.gap)
        geoms, centres = [], []
        for shape in shapes:
            poly = Polyhedron(shape)
            geoms.append(convex(poly, poly.centre))
            centres.append(poly.centre)
        self.objects = []
        for f in frames:
            for link, owner in enumerate(sim.model.frames):
                rot, at = f[owner, :3, :3], f[owner, :3, 3]
                tf = fcl.Transform(rot, rot @ centres[link] + at)
                self.objects.append(fcl.CollisionObject(geoms[link], tf))
        self.geoms = geoms
        self.tree = fcl.DynamicAABBTreeCollisionManager()
        self.tree.registerObjects(self.objects)
        self.tree.setup()

    def distance(self, part: Polyhedron) -> float:
        """The least distance from ``part`` to the arm at any sample (<= 0: they meet)."""
        import fcl

        from valterm.core.collision.exact import convex

        obj = fcl.CollisionObject(convex(part), fcl.Transform(np.eye(3), part.centre))
        hit = fcl.CollisionData(fcl.CollisionRequest(), fcl.CollisionResult())
        self.tree.collide(obj, hit, fcl.defaultCollisionCallback)
        if hit.result.is_collision:
            return 0.0
        data = fcl.DistanceData(fcl.DistanceRequest(), fcl.DistanceResult())
        self.tree.distance(obj, data, fcl.defaultDistanceCallback)
        return float(data.result.min_distance)


def _links_placed(sim: Simulator, joints: np.ndarray) -> np.ndarray:
    """(poses, links, 2k?, 3) is ragged: the link vertices placed, as (poses, vertices, 3) and
    the link of each vertex."""
    frames = sim.model.link_frames_batch(joints)
    shapes = sim.model.shapes(sim.gap)
    local = np.concatenate(shapes)
    owners = np.repeat(sim.model.frames, [len(v) for v in shapes])
    each = frames[:, owners]
    placed: np.ndarray = np.einsum("pvij,vj->pvi", each[..., :3, :3], local) + each[..., :3, 3]
    return placed


def _link_rows(sim: Simulator) -> np.ndarray:
    shapes = sim.model.shapes(sim.gap)
    return np.repeat(np.arange(len(shapes)), [len(v) for v in shapes])


def crowded_cell(n: int, moves: int = 24, seed: int = 40) -> CellScene:
    """``n`` boxes standing round the path of a ``moves``-MOVE program, each 5-30 mm from the
    arm where the arm comes nearest it, none met along the way."""
    from valterm.bench.collision import move_program

    goals = move_program(moves, seed)
    poses = program_poses(goals)
    sim = _simulator([])
    samples = _between(poses, SUBSTEPS)
    arm = _ArmSamples(sim, samples)
    placed = _links_placed(sim, poses)
    rows = _link_rows(sim)
    rng = np.random.default_rng(seed)
    parts: list[Polyhedron] = []
    nearest = []
    while len(parts) < n:
        made = _part_beside(arm, placed, rows, rng, str(len(parts) + 1))
        if made is not None:
            parts.append(made[0])
            nearest.append(made[1])
    return CellScene("crowded", parts, goals, poses, notes={"nearest_mm": float(min(nearest)),
                                                           "farthest_mm": float(max(nearest))})


def _part_beside(arm: _ArmSamples, placed: np.ndarray, rows: np.ndarray, rng: np.random.Generator,
                 name: str) -> tuple[Polyhedron, float] | None:
    """A box beside the arm at a random pose, moved out (or in) along the way from the link's
    centre until the arm's nearest approach along the whole path is 5-30 mm; None if it won't."""
    pose = int(rng.integers(len(placed)))
    link = int(rng.integers(rows.max() + 1))
    verts = placed[pose][rows == link]
    centre = verts.mean(axis=0)
    corner = verts[int(rng.integers(len(verts)))]
    way = corner - centre + rng.normal(0.0, 10.0, 3)
    way /= np.linalg.norm(way)
    half = rng.uniform(15.0, 45.0, 3)
    at = corner + way * (half.max() + 15.0)
    target = rng.uniform(CLEAR_FROM + 3.0, CLEAR_TO - 3.0)
    for _ in range(10):
        box = Polyhedron.box(at - half, at + half, name)
        d = arm.distance(box)
        if CLEAR_FROM <= d <= CLEAR_TO:
            return box, d
        at = at + way * ((half.min() if d <= 0.0 else 0.0) + target - d)
    return None


def heavy_cell(n: int, moves: int = 24, seed: int = 41) -> CellScene:
    """``n`` parts along the path of a ``moves``-MOVE program, each sitting on a moving link (the
    upper arm to the fingers) at one of its poses (most met at several), the last a 0.5 mm plate the hand passes through
    between two poses and touches at none."""
    from valterm.bench.collision import move_program

    goals = move_program(moves, seed)
    poses = program_poses(goals)
    sim = _simulator([])
    placed = _links_placed(sim, poses)
    rows = _link_rows(sim)
    rng = np.random.default_rng(seed)
    parts: list[Polyhedron] = []
    for i in range(n - 1):
        pose = int(rng.integers(len(placed)))
        verts = placed[pose][rows == int(rng.integers(3, rows.max() + 1))]   # the upper arm on
        w = rng.dirichlet(np.ones(len(verts)))
        at = w @ verts + rng.normal(0.0, 15.0, 3)
        half = rng.uniform(15.0, 45.0, 3)
        parts.append(Polyhedron.box(at - half, at + half, str(i + 1)))
    plate, step = thin_plate(sim, poses, str(n))
    parts.append(plate)
    return CellScene("heavy", parts, goals, poses, plate=n, plate_step=step)


def thin_plate(sim: Simulator, poses: np.ndarray, name: str) -> tuple[Polyhedron, int]:
    """A 0.5 mm plate, 40 mm square, across the way a finger goes between two poses where it
    is wholly on one side of the plate at the first and wholly on the other at the second,
    and no link touches it at any pose; and the pose the finger reaches through it."""
    placed = _links_placed(sim, poses)
    rows = _link_rows(sim)
    arm = _ArmSamples(sim, poses)
    finger = next(i for i, name_ in enumerate(sim.model.names) if name_.startswith("FINGER"))
    v = placed[:, rows == finger]
    for k in range(len(poses) - 2, 0, -1):
        mid = (poses[k] + ((poses[k + 1] - poses[k] + 180.0) % 360.0 - 180.0) / 2.0)[None]
        at = _links_placed(sim, mid)[0][rows == finger]
        way = v[k + 1].mean(axis=0) - v[k].mean(axis=0)
        way /= np.linalg.norm(way)
        centre = at.mean(axis=0)
        if (v[k] @ way).max() + 2.0 > centre @ way or (v[k + 1] @ way).min() - 2.0 < centre @ way:
            continue
        plate = _plate(centre, way, name)
        if arm.distance(plate) > 1.0:
            return plate, k + 1
    raise ValueError("no step of the program passes a finger clean through a plate")


def _plate(centre: np.ndarray, normal: np.ndarray, name: str) -> Polyhedron:
    """A 40 x 40 x ``PLATE`` mm box centred at ``centre``, its thin side along ``normal``."""
    a = np.cross(normal, [0.0, 0.0, 1.0] if abs(normal[2]) < 0.9 else [1.0, 0.0, 0.0])
    a /= np.linalg.norm(a)
    rot = np.column_stack([a, np.cross(normal, a), normal])
    box = Polyhedron.box(np.array([-20.0, -20.0, -PLATE / 2]), np.array([20.0, 20.0, PLATE / 2]), name)
    return box.transformed(rot, centre)


def glancing_cell(at: float, depth: float, turn: float = 36.0) -> tuple[CellScene, int]:
    """One 40 mm cube a finger's corner clips between two poses and leaves before the next: the
    arm outstretched turns JT1 by ``turn`` degrees (three steps at SPEED 100), and a fraction
    ``at`` of the way through the middle step the arm's farthest point along u (outward from
    the base and a little up) is ``depth`` mm inside the cube, whose corner points back along
    u. No point of the arm comes farther along u at any other moment of the motion (a turn
    about the vertical keeps each point's height and distance from the axis), so only that
    corner meets the cube, for a moment; and the step it meets it in (the pose it ends at)."""
    start = np.array([0.0, -60.0, 150.0, 0.0, 30.0, 0.0])
    goals = np.array([start, start + np.array([turn, 0.0, 0.0, 0.0, 0.0, 0.0])])
    poses = program_poses(goals)
    sim = _simulator([])
    k = len(poses) // 2
    v = _links_placed(sim, (poses[k - 1] + at * (poses[k] - poses[k - 1]))[None])[0]
    far = v[int(np.hypot(v[:, 0], v[:, 1]).argmax())]
    u = np.array([far[0], far[1], 0.3 * np.hypot(far[0], far[1])])
    u /= np.linalg.norm(u)
    corner = v[int((v @ u).argmax())]
    cube = Polyhedron.box(np.zeros(3), np.full(3, 40.0), "1")
    return CellScene("glancing", [cube.transformed(_diagonal_to(u), corner - depth * u)], goals, poses), k


def _diagonal_to(u: np.ndarray) -> np.ndarray:
    """The rotation taking the unit cube's diagonal (1, 1, 1) / sqrt 3 to the unit vector ``u``
    (Rodrigues' formula; ``u`` is never opposite it here)."""
    a = np.full(3, 1.0 / np.sqrt(3.0))
    v, c = np.cross(a, u), float(a @ u)
    k = np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])
    turned: np.ndarray = np.eye(3) + k + k @ k / (1.0 + c)
    return turned


# -- the peers ------------------------------------------------------------------------------

Contacts = dict[tuple[str, str], int]    # (link, part number) -> the first pose they meet at


class FclPeer:
    """python-fcl on the scene's poses: per pose (``per_pose``) and per pose plus the step
    before each pose by ``continuousCollide`` (``with_ccd``). Link objects built once, moved."""

    def __init__(self, scene: CellScene) -> None:
        import fcl

        from valterm.core.collision.exact import convex

        sim = _simulator(scene.parts)
        self.names = sim.model.names
        self.owners = np.asarray(sim.model.frames)
        shapes = sim.model.shapes(sim.gap)
        self.links, centres, self.link_index, self.geoms = [], [], {}, []
        for i, shape in enumerate(shapes):
            poly = Polyhedron(shape)
            geom = convex(poly, poly.centre)
            self.links.append(fcl.CollisionObject(geom, fcl.Transform()))
            self.geoms.append(geom)
            self.link_index[id(geom)] = i
            centres.append(poly.centre)
        self.local_centres = np.array(centres)
        self.local = [np.asarray(s) - c for s, c in zip(shapes, centres)]
        self.tree = fcl.DynamicAABBTreeCollisionManager()
        self.tree.registerObjects(self.links)
        self.tree.setup()
        self.part_geoms = [convex(p) for p in scene.parts]
        self.parts = [fcl.CollisionObject(g, fcl.Transform(np.eye(3), p.centre))
                      for g, p in zip(self.part_geoms, scene.parts)]
        self.part_index = {id(g): i for i, g in enumerate(self.part_geoms)}
        self.still = fcl.DynamicAABBTreeCollisionManager()
        self.still.registerObjects(self.parts)
        self.still.setup()
        self.lo = np.array([p.vertices.min(axis=0) for p in scene.parts])
        self.hi = np.array([p.vertices.max(axis=0) for p in scene.parts])
        self.joints = scene.poses
        self.link_frames = sim.model.link_frames
        self.ccd = fcl.ContinuousCollisionRequest(ccd_motion_type=fcl.CCDMotionType.CCDM_SCREW,
                                                  ccd_solver_type=fcl.CCDSolverType.CCDC_CONSERVATIVE_ADVANCEMENT)

    def _placements(self, q: list[float]) -> tuple[np.ndarray, np.ndarray]:
        placed = self.link_frames(q)[self.owners]
        rot = placed[:, :3, :3]
        return rot, np.einsum("lij,lj->li", rot, self.local_centres) + placed[:, :3, 3]

    def _pose(self, rot: np.ndarray, at: np.ndarray, k: int, found: Contacts) -> None:
        import fcl

        for obj, r, t in zip(self.links, rot, at):
            obj.setRotation(r)
            obj.setTranslation(t)
        self.tree.update()
        data = fcl.CollisionData(fcl.CollisionRequest(num_max_contacts=1 << 30), fcl.CollisionResult())
        self.tree.collide(self.still, data, fcl.defaultCollisionCallback)
        for c in data.result.contacts:
            link = self.link_index.get(id(c.o1), self.link_index.get(id(c.o2)))
            part = self.part_index.get(id(c.o2), self.part_index.get(id(c.o1)))
            if link is not None and part is not None:
                found.setdefault((self.names[link], str(part + 1)), k)

    def per_pose(self) -> Contacts:
        """The link x part contacts at the poses, each with the first pose it is met at."""
        found: Contacts = {}
        for k, q in enumerate(self.joints.tolist()[1:], start=1):
            rot, at = self._placements(q)
            self._pose(rot, at, k, found)
        return found

    def with_ccd(self) -> Contacts:
        """The same, and between each two poses fcl's continuous check (screw motion,
        conservative advancement) of each link against the parts its joined box meets."""
        import fcl

        found: Contacts = {}
        before: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None = None
        for k, q in enumerate(self.joints.tolist()):
            rot, at = self._placements(q)
            verts = [r @ v.T for r, v in zip(rot, self.local)]
            lo = np.array([v.min(axis=1) for v in verts]) + at
            hi = np.array([v.max(axis=1) for v in verts]) + at
            if before is not None:
                r0, t0, lo0, hi0 = before
                blo, bhi = np.minimum(lo, lo0), np.maximum(hi, hi0)
                meet = np.all((blo[:, None] <= self.hi[None]) & (self.lo[None] <= bhi[:, None]), axis=2)
                for link, part in zip(*np.nonzero(meet)):
                    name = (self.names[link], str(part + 1))
                    if name in found:
                        continue
                    start = fcl.CollisionObject(self.geoms[link], fcl.Transform(r0[link], t0[link]))
                    result = fcl.ContinuousCollisionResult()
                    fcl.continuousCollide(start, fcl.Transform(rot[link], at[link]), self.parts[part],
                                          self.parts[part].getTransform(), self.ccd, result)
                    if result.is_collide:
                        found[name] = k
            if k:                  # the simulator checks the poses it moves to, not the start
                self._pose(rot, at, k, found)
            before = (rot, at, lo, hi)
        return found


def valterm_contacts(scene: CellScene, checks: bool = True) -> tuple[Contacts, int]:
    """``run --collisions`` on the scene: the link x part collisions said, each with the pose
    it is said at, and the poses played."""
    sim = _simulator(scene.parts)
    sim.stand_at(scene.goals[0])
    sim.collision_checks = checks
    found: Contacts = {}
    k = 0
    for goal in scene.goals[1:]:
        for event in sim.move_joints(goal):
            if isinstance(event, PoseEvent):
                k += 1
            elif isinstance(event, Collision) and event.b.isdigit():
                found.setdefault((event.a, event.b), k)
    return found, k


def differences(ours: Contacts, theirs: Contacts) -> list[tuple[str, str, int | None, int | None]]:
    """The pairs the two find at different poses (or one only): link, part, ours, theirs."""
    out = []
    for pair in sorted(set(ours) | set(theirs)):
        if ours.get(pair) != theirs.get(pair):
            out.append((*pair, ours.get(pair), theirs.get(pair)))
    return out


def timed_together(funcs: list[Callable[[], Any]], rounds: int) -> list[float]:
    """Seconds of the best of ``rounds`` calls of each, taken in turn round by round (a busy
    machine's slow spell then falls on all of them, not on one)."""
    import time

    best = [float("inf")] * len(funcs)
    for _ in range(rounds):
        for i, func in enumerate(funcs):
            start = time.perf_counter()
            func()
            best[i] = min(best[i], time.perf_counter() - start)
    return best


def bench_scene(scene: CellScene, rounds: int = 3) -> dict[str, Any]:
    """µs per pose of ``run --collisions`` on the scene (the motion with the checks on, less
    the same without), of plain python-fcl per pose and of fcl per pose + continuousCollide,
    all on the same poses (link frames included); the pairs each finds and where they differ."""
    peer = FclPeer(scene)
    ours, poses = valterm_contacts(scene)
    plain, ccd = peer.per_pose(), peer.with_ccd()
    on, off, fcl_s, ccd_s = timed_together([lambda: valterm_contacts(scene, True),
                                            lambda: valterm_contacts(scene, False), peer.per_pose, peer.with_ccd],
                                           rounds)
    us = (on - off) / poses * 1e6
    return {"us_per_pose": us, "fcl_us_per_pose": fcl_s / poses * 1e6, "ccd_us_per_pose": ccd_s / poses * 1e6,
            "vs_fcl_x": us / (fcl_s / poses * 1e6), "vs_ccd_x": us / (ccd_s / poses * 1e6),
            "poses": poses, "contacts": len(ours), "fcl_contacts": len(plain), "ccd_contacts": len(ccd),
            "vs_fcl": differences(ours, plain), "vs_ccd": differences(ours, ccd),
            "ours": ours, "plain": plain, "ccd": ccd}


class DenseOracle:
    """The arm's own path between two poses, sampled finely (joints moving linearly, as the
    simulator has them): python-fcl at each sample, one link x part pair at a time. It
    settles where the checkers differ."""

    def __init__(self, scene: CellScene, samples: int = 200) -> None:
        self.peer = FclPeer(scene)
        self.scene, self.samples = scene, samples

    def meets(self, link: str, part: str, k: int) -> bool:
        """Does the pair meet on the way from pose k - 1 to pose k (pose k included)?"""
        import fcl

        rows = [i for i, name in enumerate(self.peer.names) if name == link]
        obj = self.peer.parts[int(part) - 1]
        for q in _between(self.scene.poses[k - 1: k + 1], self.samples)[1:]:
            rot, at = self.peer._placements([float(v) for v in q])
            for i in rows:
                mover = fcl.CollisionObject(self.peer.geoms[i], fcl.Transform(rot[i], at[i]))
                if fcl.collide(mover, obj, fcl.CollisionRequest(), fcl.CollisionResult()):
                    return True
        return False


def explain(scene: CellScene, ours: Contacts, theirs: Contacts, peer: str, oracle: DenseOracle) -> list[str]:
    """Each pair valterm and ``peer`` first find at different poses, and what the arm's path,
    sampled finely on the way to those poses (``DenseOracle``), says: a line each."""
    lines = []
    for link, part, mine, other in differences(ours, theirs):
        said = sorted({k for k in (mine, other) if k is not None})
        met = {k: oracle.meets(link, part, k) for k in said}
        first = said[0]
        who = [name for name, k in (("valterm", mine), (peer, other)) if k == first]
        if met[first]:
            why = f"the path meets it by pose {first}: {' and '.join(who)} right"
        else:
            why = f"the path does not meet it on the way to pose {first}: a false contact from {who[0]}"
        plate = " (the 0.5 mm plate)" if scene.plate is not None and part == str(scene.plate) else ""
        lines.append(f"{scene.name} cell, {len(scene.parts)} parts: {link} x part {part}{plate}: valterm at pose "
                     f"{mine}, {peer} at {other}; {why}")
    return lines


def scene_figures(rounds: int = 3) -> tuple[dict[str, float], list[str]]:
    """The bench's figures for the crowded and the heavy cell at 30 and 100 parts, and a line
    for each pair valterm and a peer find differently, with which the arm's path agrees."""
    figures: dict[str, float] = {}
    notes: list[str] = []
    for make in (crowded_cell, heavy_cell):
        for n in (30, 100):
            scene = make(n)
            found = bench_scene(scene, rounds)
            name = f"collision_{scene.name}"
            for key in ("us_per_pose", "fcl_us_per_pose", "ccd_us_per_pose", "vs_fcl_x", "vs_ccd_x",
                        "poses", "contacts", "fcl_contacts", "ccd_contacts"):
                figures[f"{name}_{key.replace('_per_pose', '')}_{n}parts"] = float(found[key])
            figures[f"{name}_differ_fcl_{n}parts"] = float(len(found["vs_fcl"]))
            figures[f"{name}_differ_ccd_{n}parts"] = float(len(found["vs_ccd"]))
            earlier = [d for d in found["vs_fcl"] if d[2] is not None and (d[3] is None or d[2] < d[3])]
            if earlier:
                notes.append(f"{scene.name} cell, {n} parts: {len(earlier)} pairs met between poses before fcl per "
                             f"pose sees them at a pose ({sum(d[3] is None for d in earlier)} never at a pose)")
            oracle = DenseOracle(scene)
            notes += explain(scene, found["ours"], found["ccd"], "fcl + CCD", oracle)
            plate = str(scene.plate)
            if scene.plate is not None and plate not in {b for _, b in found["plain"]}:
                notes += [line for line in explain(scene, found["ours"], found["plain"], "fcl per pose", oracle)
                          if f"part {plate} " in line]
    return figures, notes
