"""The collision check fed by link frames (``RobotScene``) against the polyhedra path, and swept motion.

The reference is the path the simulator used before: ``robot_polyhedra()`` (ten ``Polyhedron``
objects per pose) into ``CollisionWorld.check``. The new path must give identical findings.
"""

from __future__ import annotations

import numpy as np

from valterm.core import resources
from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.cell.workcell import WorkCell
from valterm.core.collision import CollisionWorld
from valterm.core.collision.frames import RobotScene, thickness
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
        sim.joints = [float(v) for v in joints]
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
    part = sim.move_part(5, hand - sim.cell.objects[4].centre)     # part 5 brought to the wrist
    assert part is sim.cell.objects[4]
    after = scene.check(frames, sim.cell.objects)
    assert after != before and any(f.b == 5 for f in after)
    assert after == CollisionWorld(sim.model.names).check(sim.robot_polyhedra(), sim.cell.objects)


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
    sim.joints = list(ARM_OUT)
    sim.cell.objects.append(_plate_across_the_fingers(sim, 6.0))
    world = CollisionWorld(sim.model.names)
    start = list(sim.joints)
    # both ends of the one 12-degree step are clear of the plate: only the path meets it
    assert not any(f.b == 1 and f.kind == "collides" for f in _old(sim, world, (), 100.0))
    sim.joints = [start[0] + 12.0, *start[1:]]
    assert not any(f.b == 1 and f.kind == "collides" for f in _old(sim, world, (), 100.0))
    sim.joints = start
    sim.collision_checks = True
    events = list(sim.drive(1, 12.0))
    assert sum(type(e).__name__ == "PoseEvent" for e in events) == 1
    hits = [e.text for e in events if isinstance(e, Collision)]
    assert "FINGER COLLIDES WITH 1" in hits, hits


def test_no_substeps_when_no_thin_part_is_near_the_path():
    sim = Simulator(WorkCell())
    sim.joints = list(ARM_OUT)
    far = Polyhedron.box(np.array([3000.0, 3000, 0]), np.array([3001.0, 3100, 100]))  # thin, far away
    sim.cell.objects.append(far)
    scene = sim._collision_scene()
    before = sim.model.link_frames(sim.joints, sim.base)
    after = sim.model.link_frames([sim.joints[0] + 12.0, *sim.joints[1:]], sim.base)
    scene.check(after, sim.cell.objects)
    assert scene.substeps(before, after, sim.cell.objects) == 1
    sim.cell.objects[0] = _plate_across_the_fingers(sim, 6.0)
    scene.check(after, sim.cell.objects)
    assert scene.substeps(before, after, sim.cell.objects) > 10      # ~190 mm past a 3 mm plate


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
        sim.joints = [float(v) for v in (near if n % 2 else rng.uniform(stops[:, 0], stops[:, 1]))]
        carried: tuple[int, ...] = ()
        if n % 4 == 0:                  # part 1 held as grasped at A, the arm a few degrees off
            sim.joints = [float(v) for v in at_a + rng.normal(0.0, 4.0, 6)]
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
