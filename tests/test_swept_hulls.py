"""A path's steps skip the moments nothing can be found at (issue 40): a link x part pair whose
link's hulls over the step keep clear of the part (``RobotScene.hulls_clear``, the bend of
``arrays.sweep_bends``), and a pair that collides at both poses of a step. What is said stays
the same, in the same order; what the hulls clear, fcl finds apart all along the step."""

from __future__ import annotations

from typing import Any, Callable

import fcl
import numpy as np
import pytest

from valterm.bench.collision import move_program
from valterm.bench.collision_scenes import FclPeer, crowded_cell, heavy_cell
from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.cell.workcell import WorkCell
from valterm.core.collision import arrays
from valterm.core.collision.frames import RobotScene
from valterm.core.collision.thesis import SEPARATED
from valterm.core.events import Collision, Near, PoseEvent
from valterm.core.simulator import Simulator

SAMPLES = 65      # moments a step is sampled at, its poses included


def _step(sim: Simulator, q0: np.ndarray, q1: np.ndarray) -> tuple[RobotScene, np.ndarray, np.ndarray]:
    """The robot scene checked at ``q1``, the joints' turns from ``q0`` (degrees, the shorter
    way) and each link's bend over the step from where the links are at ``q1``."""
    list(sim.check_collisions(at=[float(v) for v in q1]))
    robot = sim._collision_scene()
    turns = (q1 - q0 + 180.0) % 360.0 - 180.0
    radians = np.radians(np.abs(turns))
    frames = sim._frames_at([float(v) for v in q1])
    terms = robot._sweep_terms(frames, radians, robot._travel_table(frames) * radians)
    return robot, turns, arrays.sweep_bends(terms[None], radians[None])[0]


@pytest.mark.parametrize("make", [crowded_cell, heavy_cell])
def test_a_point_of_a_link_leaves_its_chord_by_no_more_than_the_bend(make: Any) -> None:
    scene = make(30)
    sim = Simulator(WorkCell(objects=list(scene.parts)))
    t = np.linspace(0.0, 1.0, SAMPLES)
    worst = 0.0
    for k in range(1, len(scene.poses), 7):
        q0, q1 = scene.poses[k - 1], scene.poses[k]
        robot, turns, bend = _step(sim, q0, q1)
        frames = sim._frames_batch(q0 + t[:, None] * turns)[:, robot.owners]          # (moments, links, 4, 4)
        local = robot._apart_tables()[0]                                            # (links, vertices, 3)
        at = np.einsum("mlij,lvj->mlvi", frames[..., :3, :3], local) + frames[:, :, None, :3, 3]
        chord = at[:1] + t[:, None, None, None] * (at[-1:] - at[:1])
        off = np.linalg.norm(at - chord, axis=3).max(axis=(0, 2))                    # per link
        assert (off <= bend[: len(off)] + 1e-9).all(), (k, off, bend)
        worst = max(worst, float((off / np.maximum(bend[: len(off)], 1e-9)).max()))
    assert worst > 0.05          # the bound is not so loose as to say nothing


def _fcl_apart(peer: FclPeer, q: np.ndarray, link: int, part: int) -> float:
    """fcl's distance between a link and a part at the joints ``q``."""
    rot, at = peer._placements([float(v) for v in q])
    mover = fcl.CollisionObject(peer.geoms[link], fcl.Transform(rot[link], at[link]))
    result = fcl.DistanceResult()
    return float(fcl.distance(mover, peer.parts[part], fcl.DistanceRequest(), result))


def _moments_of(sim: Simulator, q0: np.ndarray, turns: np.ndarray) -> Callable[[np.ndarray, np.ndarray], np.ndarray]:
    """The link frames at fractions of the step from ``q0`` turning the joints by ``turns``."""
    return lambda step, t: sim._frames_batch(q0 + t[:, None] * turns)


@pytest.mark.parametrize("make", [crowded_cell, heavy_cell])
def test_a_pair_the_hulls_clear_is_apart_all_along_the_step(make: Any) -> None:
    """Every link x part pair of a step, its hulls asked; those cleared sampled along the step
    against fcl, never nearer than ``SEPARATED``."""
    scene = make(30)
    sim = Simulator(WorkCell(objects=list(scene.parts)))
    peer = FclPeer(scene)
    rng = np.random.default_rng(40)
    cleared = asked = 0
    for k in range(2, len(scene.poses), 9):
        q0, q1 = scene.poses[k - 1], scene.poses[k]
        robot, turns, bend = _step(sim, q0, q1)
        pairs, nl = robot._pairs_now, len(robot._link_ks)
        assert pairs is not None
        p = np.flatnonzero(pairs.stationary >= nl)
        poses = np.stack([sim._frames_at([float(v) for v in q]) for q in (q0, q1)])
        clear = robot.hulls_clear(np.zeros(len(p), dtype=np.intp), p, bend.take(pairs.moving.take(p)), poses,
                                  _moments_of(sim, q0, turns))
        asked, cleared = asked + len(p), cleared + int(clear.sum())
        for i in rng.choice(np.flatnonzero(clear), size=min(6, int(clear.sum())), replace=False):
            link, part = int(pairs.moving[p[i]]), int(pairs.stationary[p[i]]) - nl
            for t in np.linspace(0.0, 1.0, SAMPLES):
                assert _fcl_apart(peer, q0 + t * turns, link, part) >= SEPARATED - 1e-6, (k, link, part, t)
    assert cleared > asked // 2                           # it clears most pairs
    assert cleared < asked or make is crowded_cell        # and not those that meet


def _said(parts: list[Polyhedron], goals: np.ndarray, rules: str, prune: bool, monkeypatch: pytest.MonkeyPatch,
          robot: str | None = None, base: tuple[float, float, float, float] | None = None
          ) -> tuple[list[tuple[Any, ...]], int]:
    """What a program's MOVEs (to ``goals``, the first the start) say among ``parts``, pose by
    pose, and how many items were left out (``robot``: a robot file's arm; ``base``: BASE dx,
    dy, dz, rz)."""
    monkeypatch.setattr(RobotScene, "prune_moments", prune)
    left = [0]
    needless = RobotScene.needless

    def counted(self: RobotScene, *args: Any) -> np.ndarray | None:
        found = needless(self, *args)
        left[0] += 0 if found is None else int(found.sum())
        return found

    monkeypatch.setattr(RobotScene, "needless", counted)
    sim = Simulator(WorkCell(objects=list(parts)), robot=robot)
    sim.set_rules(rules)
    if base is not None:
        list(sim.set_base(*base))
    stops = np.asarray(sim.arm.stops)
    goals = np.clip(goals, stops[:, 0] + 1.0, stops[:, 1] - 1.0)     # within another arm's stops
    sim.stand_at(goals[0])
    sim.collision_checks = True
    said, k = [], 0
    for goal in goals[1:]:
        for event in sim.move_joints(goal):
            if isinstance(event, PoseEvent):
                k += 1
            elif isinstance(event, (Collision, Near)):
                said.append((k, type(event).__name__, event.a, event.b))
    return said, left[0]


@pytest.mark.parametrize("make", [crowded_cell, heavy_cell])
@pytest.mark.parametrize("rules", ["1985", "controller"])
def test_moments_left_out_change_nothing_said(make: Any, rules: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """The same findings at the same poses in the same order (the controller rules say a
    step's in the order its moments find them) with the items left out as with none."""
    scene = make(30)
    pruned, left = _said(scene.parts, scene.goals, rules, True, monkeypatch)
    whole, none_left = _said(scene.parts, scene.goals, rules, False, monkeypatch)
    assert left > 100 and none_left == 0
    assert any(kind == "Collision" for _, kind, _, _ in whole) or make is crowded_cell
    assert pruned == whole


@pytest.mark.parametrize(("robot", "base"), [(None, (40.0, -25.0, 15.0, 12.0)), ("PUMA560", None)])
def test_moments_left_out_change_nothing_said_on_a_moved_base_or_another_arm(
        robot: str | None, base: tuple[float, float, float, float] | None, monkeypatch: pytest.MonkeyPatch) -> None:
    """The frames then come with a BASE product, or a DH table's (its bends from the chain's
    lengths alone): the same findings as with no item left out."""
    scene = heavy_cell(30)
    pruned, left = _said(scene.parts, scene.goals, "controller", True, monkeypatch, robot, base)
    whole, _ = _said(scene.parts, scene.goals, "controller", False, monkeypatch, robot, base)
    assert left > 20 and any(kind == "Collision" for _, kind, _, _ in whole)
    assert pruned == whole


def _random_cell(seed: int) -> list[Polyhedron]:
    """5 to 60 boxes, 10 to 240 mm a side, half of them turned, anywhere round the robot."""
    rng = np.random.default_rng(seed)
    parts = []
    for i in range(int(rng.integers(5, 60))):
        at, half = rng.uniform([-900.0, -900.0, -300.0], [900.0, 900.0, 900.0]), rng.uniform(5.0, 120.0, 3)
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
        angle = rng.uniform(0.0, np.pi) if rng.random() < 0.5 else 0.0
        turn = np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * k @ k
        parts.append(Polyhedron.box(-half, half, str(i + 1)).transformed(turn, at))
    return parts


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(8))
def test_moments_left_out_change_nothing_said_in_random_cells(seed: int, monkeypatch: pytest.MonkeyPatch) -> None:
    """Random cells and programs (60 of them and 59 of the bench's scenes from other seeds,
    both rules, were compared when this was built): the same findings either way."""
    parts, goals = _random_cell(seed), move_program(5 + seed * 2, seed=seed)
    for rules in ("1985", "controller"):
        pruned, left = _said(parts, goals, rules, True, monkeypatch)
        whole, _ = _said(parts, goals, rules, False, monkeypatch)
        assert left > 0 and pruned == whole
