"""The collision check fed by link frames (``RobotScene``) against the polyhedra path, and swept motion.

The reference is the path the simulator used before: ``robot_polyhedra()`` (ten ``Polyhedron``
objects per pose) into ``CollisionWorld.check``. The new path must give identical findings.
"""

from __future__ import annotations

import numpy as np
import pytest

from valterm.core import resources
from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.cell.workcell import WorkCell
from valterm.core.collision.world import CollisionWorld
from valterm.core.collision.arrays import thickness
from valterm.core.collision.frames import RobotScene
from valterm.core.events import Collision
from valterm.core.files.locations import read_locations
from valterm.core.files.setup import read_setup
from valterm.core.kinematics import robot_geometry
from valterm.core.simulator import Simulator


def _old(sim: Simulator, world: CollisionWorld, carried: tuple[int, ...], speed: float) -> list:
    return world.check(sim.robot_polyhedra(), sim.cell.objects, carried, speed)


def test_frames_path_matches_the_polyhedra_path_over_random_poses():
    sim = Simulator(read_setup(resources.data_path("cells", "PROCESS.SET")))
    world = CollisionWorld(sim.model.names)
    scene = RobotScene(sim.model.names, sim.model.frames.tolist())
    broad = RobotScene(sim.model.names, sim.model.frames.tolist())
    broad.broad_phase_from = 0          # the broad phase even for PROCESS's 14 parts
    stops = robot_geometry().stops_array
    rng = np.random.default_rng(2026)
    ready = np.asarray(sim.geometry.ready, dtype=float)
    counts = {"near": 0, "collides": 0, "carried": 0, "none": 0}
    gap = None
    for n in range(2000):
        if n % 2:   # half near READY and the tables, half anywhere within the stops
            joints = ready + rng.normal(0.0, 40.0, 6)
        else:
            joints = rng.uniform(stops[:, 0], stops[:, 1])
        sim.stand_at([float(v) for v in np.clip(joints, stops[:, 0], stops[:, 1])])  # the arm stays inside its stops
        if n % 50 == 0:
            sim.gap = float(rng.choice([sim.model.open_gap, sim.model.closed_gap, 35.0]))
        carried: tuple[int, ...] = ()
        if n % 5 == 0:                      # part 1 or 2 held in the clamp, moved with it
            part = 1 + n % 2
            frame = sim.model.clamp_frame(sim.joints, sim.base)
            sim.carried, sim._carried_local = part, np.array([[-20.0, -10, 40], [20, -10, 40], [20, 10, 40], [-20, 10, 40],
                                                               [-20, -10, 90], [20, -10, 90], [20, 10, 90], [-20, 10, 90]])
            sim._follow_clamp()
            carried = (part,)
            counts["carried"] += 1
            del frame
        speed = float(rng.choice([10.0, 50.0, 100.0]))
        if sim.gap != gap:                  # new finger shapes, as the simulator does
            gap = sim.gap
            scene.set_shapes(sim.model.shapes(gap))
            broad.set_shapes(sim.model.shapes(gap))
        frames = sim.model.link_frames(sim.joints, sim.base)
        new = scene.check(frames, sim.cell.objects, carried, speed)
        assert new == _old(sim, world, carried, speed), sim.joints
        if n % 2:
            assert broad.check(frames, sim.cell.objects, carried, speed) == new, sim.joints
        kinds = {f.kind for f in new}
        counts["collides" if "collides" in kinds else "near" if kinds else "none"] += 1
        sim.carried = None
    assert min(counts.values()) > 50, counts


def test_frames_path_follows_a_moved_part():
    sim = Simulator(read_setup(resources.data_path("cells", "PROCESS.SET")))
    scene = RobotScene(sim.model.names, sim.model.frames.tolist())
    scene.set_shapes(sim.model.shapes(sim.gap))
    frames = sim.model.link_frames(sim.joints, sim.base)
    before = scene.check(frames, sim.cell.objects)
    hand = sim.model.clamp_frame(sim.joints, sim.base)[:3, 3]
    placements = Polyhedron.placements
    Polyhedron(np.zeros((8, 3)))                                    # made, not moved
    assert Polyhedron.placements == placements
    part = sim.move_part(5, hand - sim.cell.objects[4].centre)     # part 5 brought to the wrist
    assert part is sim.cell.objects[4] and Polyhedron.placements == placements + 1
    after = scene.check(frames, sim.cell.objects)
    assert after != before and any(f.b == 5 for f in after)
    assert after == CollisionWorld(sim.model.names).check(sim.robot_polyhedra(), sim.cell.objects)


def test_frames_path_follows_parts_swapped_in_the_list():
    """Parts that trade places in the cell's list (no vertices set, no new polyhedron) are
    seen at once, in the broad phase too: the scene's cache is not fooled by its counter."""
    sim = Simulator(read_setup(resources.data_path("cells", "PROCESS.SET")))
    hand = sim.model.clamp_frame(sim.joints, sim.base)[:3, 3]
    sim.move_part(5, hand - sim.cell.objects[4].centre)            # part 5 at the wrist
    frames = sim.model.link_frames(sim.joints, sim.base)
    for broad_from in (10 ** 9, 0):
        scene = RobotScene(sim.model.names, sim.model.frames.tolist())
        scene.broad_phase_from = broad_from
        scene.set_shapes(sim.model.shapes(sim.gap))
        objects = sim.cell.objects
        before = scene.check(frames, objects)
        assert any(f.b == 5 for f in before) and not any(f.b == 6 for f in before)
        assert scene.check(frames, objects) == before                # nothing moved: the same
        objects[4], objects[5] = objects[5], objects[4]
        after = scene.check(frames, objects)
        assert any(f.b == 6 for f in after) and not any(f.b == 5 for f in after)
        assert after == CollisionWorld(sim.model.names).check(sim.robot_polyhedra(), objects)
        objects[4], objects[5] = objects[5], objects[4]


def test_frames_path_follows_parts_swapped_while_a_part_is_carried():
    """With a part carried (a new polyhedron every step, no vertices set, so the scene's counter
    stands still), free parts that trade places in the list are still seen at once."""
    sim = Simulator(read_setup(resources.data_path("cells", "PROCESS.SET")))
    hand = sim.model.clamp_frame(sim.joints, sim.base)[:3, 3]
    sim.move_part(5, hand - sim.cell.objects[4].centre)            # part 5 at the wrist
    frames = sim.model.link_frames(sim.joints, sim.base)
    objects = list(sim.cell.objects)
    held = objects[0]
    for checker in ("thesis", "exact"):
        scene = RobotScene(sim.model.names, sim.model.frames.tolist(), checker=checker)
        scene.set_shapes(sim.model.shapes(sim.gap))
        world = CollisionWorld(sim.model.names, checker=checker)
        placements = Polyhedron.placements
        for swapped in (False, True, True, False):
            objects[0] = Polyhedron(held.vertices + 0.0, held.name)      # carried: new each step
            if swapped != (objects[4] is not sim.cell.objects[4]):
                objects[4], objects[5] = objects[5], objects[4]
            found = scene.check(frames, objects, (1,))
            assert found == world.check(sim.robot_polyhedra(), objects, (1,)), (checker, swapped)
            assert any(f.b == (6 if swapped else 5) for f in found), (checker, swapped, found)
            assert not any(f.b == (5 if swapped else 6) for f in found), (checker, swapped, found)
        assert Polyhedron.placements == placements


def test_links_found_apart_in_their_own_frames_never_change_the_fine_answer():
    """``RobotScene._apart`` (a link's face plane, placed from its frame, clear of the other's
    vertices by 1 mm) lets the fine test answer clear at once: over random poses among parts
    near the arm, every pair whose boxes meet gets the full edge-face test's answer, and the
    shortcut answered many of them."""
    from valterm.bench.collision import dense_cell, move_program
    from valterm.core.collision.thesis import fine

    sim = Simulator(WorkCell(objects=dense_cell(30)))
    scene = RobotScene(sim.model.names, sim.model.frames.tolist())
    scene.set_shapes(sim.model.shapes(sim.gap))
    rng = np.random.default_rng(25)
    apart = hits = asked = 0
    for goal in move_program(600):        # the hand 40 to 300 mm above the tables, then lower
        joints = goal + rng.normal(0.0, 12.0, 6) * [0, 1, 1, 0, 1, 0]
        scene.check(sim.model.link_frames([float(v) for v in joints], sim.base), sim.cell.objects)
        pairs, s = scene._pairs_now, scene._scene
        lo, hi = s.lo, s.hi
        a, b = pairs.moving, pairs.stationary
        meet = np.flatnonzero(((lo[a] <= hi[b]) & (lo[b] <= hi[a])).all(axis=1))
        a, b = a[meet], b[meet]
        found = scene._apart(a, b)
        full = fine(s, a, b, shortcut=False)
        assert np.array_equal(fine(s, a, b), full)
        assert not (found & full).any()
        apart, hits, asked = apart + int(found.sum()), hits + int(full.sum()), asked + len(a)
    assert apart > 20 and hits > 50 and asked > apart + hits, (apart, hits, asked)


def test_thickness_of_a_plate():
    plate = Polyhedron.box(np.array([0.0, 0, 0]), np.array([300.0, 4, 200]))
    assert abs(thickness(plate.vertices, plate.k) - 4.0) < 1e-9


ARM_OUT = (0.0, 0.0, 90.0, 0.0, 0.0, 0.0)    # the fingers ~1 m from the JT1 axis


def _plate_across_the_fingers(sim: Simulator, degrees: float, width: float = 3.0) -> Polyhedron:
    """A thin radial plate where the fingers pass when JT1 has turned ``degrees`` from now."""
    fingers = [p for p, name in zip(sim.robot_polyhedra(), sim.model.names) if name == "FINGER"]
    centre = np.mean([p.centre for p in fingers], axis=0)
    t = np.radians(degrees)
    turn = np.array([[np.cos(t), -np.sin(t), 0.0], [np.sin(t), np.cos(t), 0.0], [0.0, 0.0, 1.0]])
    at = turn @ centre
    radial = np.linalg.norm(at[:2])
    plate = Polyhedron.box(np.array([radial - 80.0, -width / 2, at[2] - 60.0]),
                           np.array([radial + 80.0, width / 2, at[2] + 60.0]))
    angle = np.arctan2(at[1], at[0])
    rz = np.array([[np.cos(angle), -np.sin(angle), 0.0], [np.sin(angle), np.cos(angle), 0.0], [0.0, 0.0, 1.0]])
    return plate.transformed(rz, np.zeros(3))


def test_a_step_straddling_a_thin_part_is_reported():
    sim = Simulator(WorkCell())
    sim.stand_at(list(ARM_OUT))
    sim.cell.objects.append(_plate_across_the_fingers(sim, 6.0))
    world = CollisionWorld(sim.model.names)
    start = list(sim.joints)
    # both ends of the one 12-degree step are clear of the plate: only the path meets it
    assert not any(f.b == 1 and f.kind == "collides" for f in _old(sim, world, (), 100.0))
    sim.stand_at([start[0] + 12.0, *start[1:]])
    assert not any(f.b == 1 and f.kind == "collides" for f in _old(sim, world, (), 100.0))
    sim.stand_at(start)
    sim.collision_checks = True
    events = list(sim.drive(1, 12.0))
    assert sum(type(e).__name__ == "PoseEvent" for e in events) == 1
    hits = [e.text for e in events if isinstance(e, Collision)]
    assert "FINGER COLLIDES WITH 1" in hits, hits


def _swept(sim: Simulator, turn: float) -> tuple[np.ndarray, np.ndarray]:
    """What ``RobotScene.swept`` says of a JT1 turn of ``turn`` degrees from where the arm is."""
    scene = sim._collision_scene()
    after = sim.model.link_frames([sim.joints[0] + turn, *sim.joints[1:]], sim.base)
    scene.check(after, sim.cell.objects)
    return scene.swept(after, [np.radians(turn), 0, 0, 0, 0, 0], sim.cell.objects)


def test_no_substeps_when_no_part_is_near_the_path():
    sim = Simulator(WorkCell())
    sim.stand_at(list(ARM_OUT))
    far = Polyhedron.box(np.array([3000.0, 3000, 0]), np.array([3001.0, 3100, 100]))  # thin, far away
    sim.cell.objects.append(far)
    moments, rows = _swept(sim, 12.0)
    assert len(moments) == 0 and rows.size == 0
    sim.cell.objects[0] = _plate_across_the_fingers(sim, 6.0)
    moments, rows = _swept(sim, 12.0)
    assert len(moments) > 10      # ~190 mm past a 3 mm plate
    pairs = sim._collision_scene().world.pairs(1)
    parties = {(pairs.a[i], pairs.b[i]) for i in np.flatnonzero(rows.any(axis=0)).tolist()}
    assert ("FINGER", 1) in parties and ("BASE", 1) not in parties


def test_a_far_part_costs_no_substep_checks():
    """A motion past a thin part out of reach is checked once a pose, as with no part at all."""
    sim = Simulator(WorkCell())
    sim.stand_at(list(ARM_OUT))
    sim.cell.objects.append(Polyhedron.box(np.array([1500.0, -500, -300]), np.array([1502.0, 500, 300])))
    sim.collision_checks = True
    scene = sim._collision_scene()
    calls = []
    between, batch = scene.collisions_between, scene.collisions_at     # moment by moment, or all at once
    scene.collisions_between = lambda *a, **k: calls.append(1) or between(*a, **k)  # type: ignore[method-assign]
    scene.collisions_at = lambda *a, **k: calls.append(1) or batch(*a, **k)  # type: ignore[method-assign]
    poses = sum(type(e).__name__ == "PoseEvent" for e in sim.drive(1, 90.0))
    assert poses >= 5 and len(calls) == 0
    # the same plate across the fingers' path: substeps, and the finger is found in it
    sim.stand_at(list(ARM_OUT))
    sim.cell.objects[0] = _plate_across_the_fingers(sim, 45.0, width=2.0)
    calls.clear()
    events = list(sim.drive(1, 90.0))
    assert len(calls) > 0
    assert "FINGER COLLIDES WITH 1" in [e.text for e in events if isinstance(e, Collision)]


def test_a_thin_part_straddled_with_a_carried_part_and_every_joint_turning():
    """Two poses both clear of a thin plate, the step between crossing it with the part the
    clamp holds: the swept check reports it (all six joints move, the bound is not JT1's)."""
    sim = Simulator(WorkCell())
    start = [10.0, -40.0, 120.0, 20.0, 30.0, 10.0]
    end = [-10.0, -44.0, 126.0, 28.0, 22.0, 40.0]
    sim.stand_at(list(start))
    frame = sim.model.clamp_frame(sim.joints, sim.base)
    sim.carried = 1
    sim._carried_local = np.array([[-15.0, -15, 250], [15, -15, 250], [15, 15, 250], [-15, 15, 250],
                                   [-15, -15, 330], [15, -15, 330], [15, 15, 330], [-15, 15, 330]])
    sim.cell.objects.append(Polyhedron.box(np.zeros(3), np.ones(3)))     # the carried part
    sim._follow_clamp()
    a = sim.cell.objects[0].centre
    sim.stand_at(list(end))
    sim._follow_clamp()
    b = sim.cell.objects[0].centre
    # a 2 mm plate across the carried part's path, half way, square to it
    mid, along = (a + b) / 2, (b - a) / np.linalg.norm(b - a)
    side = np.cross(along, [0.0, 0.0, 1.0])
    side /= np.linalg.norm(side)
    up = np.cross(side, along)
    corners = [mid + s * 1.0 * along + u * 40 * side + w * 40 * up
               for s in (-1, 1) for u, w in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
    sim.cell.objects.append(Polyhedron(np.array(corners)))
    world = CollisionWorld(sim.model.names)
    for pose in (start, end):
        sim.stand_at(list(pose))
        sim._follow_clamp()
        assert not any(f.b == 2 and f.a == 1 for f in _old(sim, world, (1,), 100.0)), pose
    sim.stand_at(list(start))
    sim._follow_clamp()
    sim.clamp_closed = True
    sim.collision_checks = True
    sim._findings = set()
    found = list(sim.check_collisions())        # the start pose, as the motion before left it
    sim.stand_at(list(end))
    sim._follow_clamp()
    found = [e.text for e in sim.check_collisions(start) if isinstance(e, Collision)]
    assert "1 COLLIDES WITH 2" in found, found
    del frame


def test_the_pairs_at_risk_hold_every_pair_met_between_two_poses():
    """Every pair the check finds colliding anywhere along a step (63 checks between its
    poses) is among the pairs ``swept`` puts at risk, over random steps in PROCESS's cell."""
    sim = Simulator(read_setup(resources.data_path("cells", "PROCESS.SET")))
    scene = sim._collision_scene()
    stops = robot_geometry().stops_array
    ready = np.asarray(sim.geometry.ready, dtype=float)
    rng = np.random.default_rng(25)
    at_risk = met = 0
    for n in range(300):
        q0 = ready + rng.normal(0.0, 45.0, 6) if n % 2 else rng.uniform(stops[:, 0], stops[:, 1])
        q1 = q0 + rng.normal(0.0, 8.0 if n % 3 else 1.0, 6)
        speed = float(rng.choice([10.0, 100.0]))
        scene.check(sim.model.link_frames(q0.tolist()), sim.cell.objects, (), speed)
        scene.swept(sim.model.link_frames(q0.tolist()), (), sim.cell.objects, now="start")
        scene.check(sim.model.link_frames(q1.tolist()), sim.cell.objects, (), speed)
        moments, rows = scene.swept(sim.model.link_frames(q1.tolist()), np.radians(q1 - q0).tolist(),
                                    sim.cell.objects, since="start")
        pairs = scene.world.pairs(len(sim.cell.objects))
        ends = set()
        for q_end in (q0, q1):
            ends |= {(f.a, f.b) for f in scene.check(sim.model.link_frames(q_end.tolist()),
                                                     sim.cell.objects, (), speed) if f.kind == "collides"}
        fine = np.linspace(0.0, 1.0, 65)[1:-1]
        for t in fine:
            q = (q0 + (q1 - q0) * t).tolist()
            found = {(f.a, f.b) for f in scene.check(sim.model.link_frames(q), sim.cell.objects, (), speed)
                     if f.kind == "collides"}
            on_parts = {p for p in found if isinstance(p[1], int)}
            # a pair met on the way is checked at some moment of the step, or met at a pose already
            allowed = {(pairs.a[i], pairs.b[i]) for i in np.flatnonzero(rows.any(axis=0)).tolist()}
            assert on_parts <= ends | allowed, (q0, q1, t, on_parts - ends - allowed)
            met += bool(on_parts - ends)
        at_risk += len(moments) > 0
    assert at_risk > 20 and met > 20, (at_risk, met)   # the test saw collisions between poses


def test_exact_from_frames_matches_the_exact_checker_on_polyhedra():
    """python-fcl fed by link frames (objects built once) against fcl on the placed polyhedra."""
    sim = Simulator(read_setup(resources.data_path("cells", "PROCESS.SET")))
    scene = RobotScene(sim.model.names, sim.model.frames.tolist(), checker="exact")
    scene.set_shapes(sim.model.shapes(sim.gap))
    world = CollisionWorld(sim.model.names, checker="exact")
    ready = np.asarray(sim.geometry.ready, dtype=float)
    rng = np.random.default_rng(13)
    kinds: set[tuple[str, str, bool]] = set()
    stops = robot_geometry().stops_array
    sim.locations.update(read_locations(resources.data_path("programs", "PROCESS.LOC")))
    sim.set_indicator("LEFTY")
    list(sim.move("A"))
    at_a = np.asarray(sim.joints)
    frame = sim.model.clamp_frame(sim.joints, sim.base)
    held = (sim.cell.objects[0].vertices - frame[:3, 3]) @ frame[:3, :3]
    for n in range(200):
        near = ready + rng.normal(0.0, 50.0, 6)
        pose = near if n % 2 else rng.uniform(stops[:, 0], stops[:, 1])
        sim.stand_at([float(v) for v in np.clip(pose, stops[:, 0], stops[:, 1])])  # the arm stays inside its stops
        carried: tuple[int, ...] = ()
        if n % 4 == 0:                  # part 1 held as grasped at A, the arm a few degrees off
            sim.stand_at([float(v) for v in np.clip(at_a + rng.normal(0.0, 4.0, 6), stops[:, 0], stops[:, 1])])
            sim.carried, sim._carried_local = 1, held
            sim._follow_clamp()
            carried = (1,)
        new = scene.check(sim.model.link_frames(sim.joints, sim.base), sim.cell.objects, carried)
        assert new == world.check(sim.robot_polyhedra(), sim.cell.objects, carried), sim.joints
        kinds.update((type(f.a).__name__, type(f.b).__name__, bool(carried) and f.a == 1) for f in new)
        sim.carried = None
    # links against parts and against links, and the carried part against parts, all seen
    assert {("str", "int", False), ("str", "str", False), ("int", "int", True)} <= kinds, kinds


def test_exact_from_frames_follows_a_carried_part_that_leaves_the_hand():
    """fcl keeps a carried part in the hand's frame while it rides the hand; a part moved any
    other way (set down elsewhere, swapped for another shape) is built again, not misplaced."""
    sim = Simulator(read_setup(resources.data_path("cells", "PROCESS.SET")))
    scene = RobotScene(sim.model.names, sim.model.frames.tolist(), checker="exact")
    scene.set_shapes(sim.model.shapes(sim.gap))
    world = CollisionWorld(sim.model.names, checker="exact")
    sim.locations.update(read_locations(resources.data_path("programs", "PROCESS.LOC")))
    sim.set_indicator("LEFTY")
    list(sim.move("A"))
    frames = sim.model.link_frames(sim.joints, sim.base)
    objects = list(sim.cell.objects)
    part = objects[0]
    others = objects[1:]
    found = []
    # held where it is, then dropped onto each other part in turn (not a move of the hand)
    for target in [None, *others]:
        if target is not None:
            objects[0] = Polyhedron(part.vertices - part.centre + target.centre, part.name)
        new = scene.check(frames, objects, (1,))
        assert new == world.check(sim.robot_polyhedra(), objects, (1,))
        found.append({f.b for f in new if f.a == 1 and f.kind == "collides"})
    # dropped onto part n, it meets part n: fcl saw each new place
    assert all(n in hit for n, hit in enumerate(found[1:], start=2)), found


def test_the_sweep_bound_holds_the_path_of_every_vertex():
    """No vertex of a link or of a carried part travels farther over a step (its path, measured
    at 200 points) than ``_sweep_bounds`` says, and the bound is not loose by more than 3x."""
    sim = Simulator(read_setup(resources.data_path("cells", "PROCESS.SET")))
    scene = sim._collision_scene()
    stops = robot_geometry().stops_array
    rng = np.random.default_rng(7)
    ratios = []
    for n in range(60):
        q0 = rng.uniform(stops[:, 0], stops[:, 1])
        q1 = np.clip(q0 + rng.normal(0.0, 10.0, 6), stops[:, 0], stops[:, 1])  # the arm stays inside its stops
        sim.stand_at(q0.tolist())
        sim.carried, sim._carried_local = 1, np.array([[-20.0, -10, 140], [20, -10, 140], [20, 10, 140],
                                                       [-20, 10, 140], [-20, -10, 300], [20, -10, 300],
                                                       [20, 10, 300], [-20, 10, 300]])
        path = []
        for t in np.linspace(0.0, 1.0, 200):
            sim.stand_at((q0 + (q1 - q0) * t).tolist())
            sim._follow_clamp()
            path.append(np.concatenate([scene.place(sim.model.link_frames(sim.joints)),
                                        sim.cell.objects[0].vertices]))
        scene.check(sim.model.link_frames(sim.joints), sim.cell.objects, (1,))
        bound = scene._sweep_bounds(sim.model.link_frames(sim.joints), np.abs(np.radians(q1 - q0)))
        steps = np.diff(np.array(path), axis=0)
        travel = np.sqrt((steps ** 2).sum(axis=2)).sum(axis=0)            # per vertex
        rows = np.repeat(np.arange(len(bound)), [*(2 * k for k in scene._link_ks), 8])
        most = np.maximum.reduceat(travel, np.flatnonzero(np.diff(np.r_[-1, rows])))
        assert np.all(most <= bound + 1e-6), (q0, q1, most - bound)
        ratios += list(bound[most > 1.0] / most[most > 1.0])
    assert np.median(ratios) < 3.0, np.median(ratios)


def test_the_arm_passing_through_itself_between_two_poses_is_reported():
    """A 44-degree JT3 step whose two poses are both clear of the base, the clamp and fingers
    passing through it between them: the swept check reports the arm against itself, as the
    pose check does (link x link pairs are swept too)."""
    sim = Simulator(WorkCell())
    start = [115.7, 37.7, 155.0, 166.5, -84.3, -246.6]
    end = [115.7, 37.7, 198.7, 166.5, -84.3, -246.6]
    world = CollisionWorld(sim.model.names)
    for pose in (start, end):
        sim.stand_at(list(pose))
        assert not [f for f in _old(sim, world, (), 100.0) if f.kind == "collides"], pose
    sim.stand_at([start[0], start[1], (start[2] + end[2]) / 2, *start[3:]])
    assert ("FINGER", "BASE") in {(f.a, f.b) for f in _old(sim, world, (), 100.0) if f.kind == "collides"}
    sim.stand_at(list(start))
    sim.collision_checks = True
    list(sim.check_collisions())                 # the start pose, as the motion before left it
    sim.stand_at(list(end))
    found = [e.text for e in sim.check_collisions(start) if isinstance(e, Collision)]
    assert {"FINGER COLLIDES WITH BASE", "CLAMP COLLIDES WITH BASE"} <= set(found), found


def test_a_step_that_bends_no_joint_between_two_links_costs_them_no_moments():
    """JT1 alone turns the arm about the base: the fingers move far past the upper arm's
    width, yet relative to the upper arm and forearm they do not move, so no link x link
    pair of theirs is checked between the poses (counted, not timed)."""
    sim = Simulator(WorkCell())
    sim.stand_at(list(ARM_OUT))
    moments, rows = _swept(sim, 30.0)
    pairs = sim._collision_scene().world.pairs(0)
    at_risk = {(pairs.a[i], pairs.b[i]) for i in np.flatnonzero(rows.any(axis=0)).tolist()} if rows.size else set()
    assert not {p for p in at_risk if p[1] in ("UPPER ARM", "FOREARM")}, at_risk
    # the JT3 step above does put the fingers against the base at risk
    sim.stand_at([115.7, 37.7, 155.0, 166.5, -84.3, -246.6])
    scene = sim._collision_scene()
    after = sim.model.link_frames([115.7, 37.7, 198.7, 166.5, -84.3, -246.6], sim.base)
    scene.check(after, sim.cell.objects)
    moments, rows = scene.swept(after, [0, 0, np.radians(43.7), 0, 0, 0], sim.cell.objects)
    assert len(moments) >= 1
    assert ("FINGER", "BASE") in {(pairs.a[i], pairs.b[i]) for i in np.flatnonzero(rows.any(axis=0)).tolist()}


def test_a_far_part_costs_no_substeps_when_every_joint_turns():
    """A MOVE turning all six joints past a thin part out of reach: no moment between poses is
    checked (the parts' pairs nor the arm's own), counted, as with the part taken away; the
    same motion with the part across the fingers' path checks moments and finds it."""
    sim = Simulator(WorkCell())
    goal = [60.0, -20.0, 110.0, 30.0, 20.0, 40.0]
    sim.stand_at(list(ARM_OUT))
    sim.cell.objects.append(Polyhedron.box(np.array([2500.0, -500, -300]), np.array([2502.0, 500, 300])))
    sim.collision_checks = True
    scene = sim._collision_scene()
    calls = []
    between, batch = scene.collisions_between, scene.collisions_at     # moment by moment, or all at once
    scene.collisions_between = lambda *a, **k: calls.append(1) or between(*a, **k)  # type: ignore[method-assign]
    scene.collisions_at = lambda *a, **k: calls.append(1) or batch(*a, **k)  # type: ignore[method-assign]
    events = list(sim.move_joints(goal))
    assert sum(type(e).__name__ == "PoseEvent" for e in events) >= 5 and calls == []
    assert not [e for e in events if isinstance(e, Collision)]
    # a thin plate where the fingers pass half way through the motion's second step
    path = [e.joints for e in events if type(e).__name__ == "PoseEvent"]
    c = sim.model.place([(a + b) / 2 for a, b in zip(path[0], path[1])], sim.gap, sim.base)[-1].centre
    sim.cell.objects[0] = Polyhedron.box(c - np.array([1.0, 60, 60]), c + np.array([1.0, 60, 60]))
    sim.stand_at(list(ARM_OUT))
    calls.clear()
    sim._findings = set()
    events = list(sim.move_joints(goal))
    assert len(calls) > 0
    assert any(isinstance(e, Collision) and e.b == "1" for e in events)


def test_each_movers_broad_phase_keeps_every_pair_the_coarse_test_finds():
    """On a dense cell (parts within reach, one carried) the per-mover broad phase picks a
    handful of pairs, holds every pair the coarse test calls near, and the findings are
    those of checking every pair."""
    from valterm.bench.collision import _poses, carried_boxes, dense_cell, move_program
    from valterm.core.collision.thesis import check_pairs, margin

    parts = dense_cell(120)
    sim = Simulator(WorkCell(objects=parts))
    broad = RobotScene(sim.model.names, sim.model.frames.tolist())
    every = RobotScene(sim.model.names, sim.model.frames.tolist())
    every.broad_phase_from = 10 ** 9
    for scene in (broad, every):
        scene.set_shapes(sim.model.shapes(sim.gap))
    rng = np.random.default_rng(25)
    picked, near, found = [], 0, 0
    for n, joints in enumerate(_poses(move_program(40), sim)):     # the hand among the parts
        sim.stand_at(joints)
        frames = sim.model.link_frames(sim.joints, sim.base)
        objects, held = parts, ()
        if n % 3 == 0:                       # a box in the clamp, checked against the parts
            flange = frames[-1]
            box = carried_boxes(1)[0].transformed(flange[:3, :3], flange[:3, 3])
            objects, held = [*parts, box], (len(parts) + 1,)
        speed = float(rng.choice([10.0, 100.0]))
        findings = broad.check(frames, objects, held, speed)
        assert findings == every.check(frames, objects, held, speed), sim.joints
        pairs, n_free = broad._pairs_now, len(broad._free)
        assert pairs is not None
        sel = broad._near_pairs(broad._movers, margin(speed), n_free)
        ruled = len(broad._movers) * n_free
        codes = check_pairs(broad._scene, pairs.moving[:ruled], pairs.stationary[:ruled], margin(speed))
        assert set(np.flatnonzero(codes).tolist()) <= set(sel.tolist())
        picked.append(len(set(sel.tolist())) / ruled)
        near += int(np.count_nonzero(codes))
        found += len(findings)
    assert near > 100 and found > 100, (near, found)   # the arm among the parts, not beside them
    assert float(np.mean(picked)) < 0.05           # a few pairs of the 1000-odd each pose


@pytest.mark.parametrize("cell", ["PROCESS", "ring"])
def test_steps_turning_alike_reuse_the_fixed_lengths_pass_with_the_same_moments(cell: str):
    """``swept``'s first pass (the fixed lengths' bound, and which parts' pairs move past their
    part's width) is kept for the next step turning the joints alike (a path's steps do): every
    step's moments and pairs are those of a scene that works the pass out afresh at every step,
    through PROCESS's cell (a broad phase) and the bench's ring of 30 parts (every pair's gaps
    measured), with moments on the way."""
    from valterm.bench.collision import ring_cell
    sim = Simulator(read_setup(resources.data_path("cells", "PROCESS.SET")) if cell == "PROCESS"
                    else WorkCell(objects=ring_cell(30)))
    kept = sim._collision_scene()
    fresh = RobotScene(sim.model.names, sim.model.frames.tolist())
    fresh.set_shapes(sim.model.shapes(sim.gap))
    rng = np.random.default_rng(29)
    ready = np.asarray(sim.geometry.ready, dtype=float)
    steps_with_moments = reused = 0
    for start in range(6):
        q = ready + rng.normal(0.0, 30.0, 6)
        turn = rng.normal(0.0, 4.0, 6) * (rng.random(6) < 0.5)
        turn[0] = 3.0
        for n in range(25):
            frames = sim.model.link_frames(q.tolist())
            turned = np.radians(turn).tolist()
            answers, known = [], kept._fixed_kept is not None and tuple(turned) in kept._fixed_kept[2]
            for scene in (kept, fresh):
                scene.check(frames, sim.cell.objects)
                fresh._fixed_kept, fresh._past_kept = None, {}
                answers.append(scene.swept(frames, turned, sim.cell.objects,
                                           since=(start, n - 1), now=(start, n)))
            (m0, r0), (m1, r1) = answers
            assert np.array_equal(m0, m1) and np.array_equal(r0, r1), (start, n)
            steps_with_moments += len(m0) > 0
            reused += known
            q = q + turn
    assert steps_with_moments > 10, steps_with_moments    # the test saw steps needing moments
    assert reused > 100, reused                           # and the kept pass used again


def test_the_frames_laid_out_in_one_call_are_those_of_stacked():
    """``_update`` lays the frames out for its product with one ``take``: the same numbers as
    ``_stacked``, for the simulator's seven frames and for a longer stack (its first frames)."""
    from valterm.core.collision.arrays import stacked as _stacked
    sim = Simulator(WorkCell())
    scene = sim._collision_scene()
    rng = np.random.default_rng(7)
    for _ in range(20):
        frames = sim.model.link_frames(rng.uniform(-180.0, 180.0, 6).tolist())
        longer = rng.normal(size=(scene._n_frames + 2, 4, 4))
        for f in (frames, longer):
            assert np.array_equal(f.take(scene._stack_pick), _stacked(f[: scene._n_frames]))
