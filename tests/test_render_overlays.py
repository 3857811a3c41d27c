"""The overlays that answer "did it reach?": ghost, collisions, LED part, depth cue (issue 12)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from valterm.core.events import PoseEvent
from valterm.core.render.legend import DIM_OFFSET, GHOST_COLOUR, HIGHLIGHT_COLOUR, SEEN_COLOUR
from valterm.core.render.overlays import Overlays, clamp_point, picture_scene
from valterm.core.render.raster import link_colour, object_colour
from valterm.core.render.views import make_view, preset_angles
from valterm.core.session import Session
from valterm.core.simulator import Simulator


def test_the_ghost_is_a_frame_at_the_motions_target(tmp_path: Path) -> None:
    session = Session(tmp_path)
    session.load_locations("PROCESS")
    sim = session.simulator
    events = session.command("MOVE B")
    first = next(e for e in events if isinstance(e, PoseEvent))
    assert first.seconds > 0 and len(first.goal) == 6 and first.index == 1
    scene = picture_scene(sim, Overlays(goal=first.goal))
    ghost = scene.lines[scene.line_colours == GHOST_COLOUR]
    assert ghost.shape == (3, 2, 3)
    for _ in events:  # the motion ends where the ghost stood
        pass
    assert np.allclose(ghost[0, 0], sim.model.clamp_frame(sim.joints, sim.base)[:3, 3], atol=1e-6)
    # the next motion's ghost stands at its own target (made once a goal, not kept from the last)
    second = next(e for e in session.command("MOVE C") if isinstance(e, PoseEvent))
    again = picture_scene(sim, Overlays(goal=second.goal))
    ghost_c = again.lines[again.line_colours == GHOST_COLOUR]
    assert np.allclose(ghost_c[0, 0], sim.model.clamp_frame(list(second.goal), sim.base)[:3, 3], atol=1e-6)
    assert not np.allclose(ghost_c[0, 0], ghost[0, 0])


def test_collided_parts_and_links_take_the_highlight_and_are_drawn_last(tmp_path: Path) -> None:
    sim = Session(tmp_path).simulator
    scene = picture_scene(sim, Overlays(collided=frozenset({"8", "CLAMP"})))
    names = sim.model.names
    n = len(sim.cell.objects)
    assert scene.n_polyhedra == n + len(names)
    # the others in their order and colours, then part 8 and the clamp on top of them
    others = [object_colour(k) for k in range(1, n + 1) if k != 8]
    others += [link_colour(i) for i, name in enumerate(names) if name != "CLAMP"]
    assert list(scene.colours[:-2]) == others
    assert list(scene.colours[-2:]) == [HIGHLIGHT_COLOUR, HIGHLIGHT_COLOUR]
    clamp = sim.model.place(sim.joints, sim.gap, sim.base)[names.index("CLAMP")]
    part = sim.cell.objects[7]
    tail = scene.vertices[-(len(part.vertices) + len(clamp.vertices)):]
    assert np.allclose(tail, np.concatenate([part.vertices, clamp.vertices]))


def _at_a(tmp_path: Path) -> Simulator:
    """PROCESS's simulator with the hand at A (LEFTY), where the LED sensor sees part 1."""
    session = Session(tmp_path)
    session.load_locations("PROCESS")
    for command in ("LEFTY", "MOVE A"):
        for _ in session.command(command):
            pass
    return session.simulator


def test_the_part_the_led_sees_is_highlighted(tmp_path: Path) -> None:
    sim = _at_a(tmp_path)
    assert sim.led_part() == 1
    assert picture_scene(sim).colours[0] == SEEN_COLOUR
    assert picture_scene(sim, Overlays(led_part=False)).colours[0] == object_colour(1)


def test_the_led_is_asked_once_a_pose(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The in-between pictures of a motion (the simulator has not moved) ask the LED sensor
    nothing; a pose, a moved part or the hand opened asks it again, and the answer follows."""
    sim = _at_a(tmp_path)
    asked: list[int | None] = []
    led_part = type(sim).led_part

    def counted(simulator: object) -> int | None:
        asked.append(led_part(simulator))  # type: ignore[arg-type]
        return asked[-1]

    monkeypatch.setattr(type(sim), "led_part", counted)
    drawn = tuple(a + 1.0 for a in sim.joints)
    for _ in range(3):
        assert picture_scene(sim, Overlays(drawn=drawn)).colours[0] == SEEN_COLOUR
    assert asked == [1]
    part = sim.cell.objects[0]
    part.vertices = part.vertices + np.array([0.0, 0.0, 500.0])  # lifted out of the gap
    assert picture_scene(sim).colours[0] == object_colour(1) and asked == [1, None]
    part.vertices = part.vertices - np.array([0.0, 0.0, 500.0])
    assert picture_scene(sim).colours[0] == SEEN_COLOUR and asked[-1] == 1
    sim.stand_at([sim.joints[0] + 30.0, *sim.joints[1:]])
    assert picture_scene(sim).colours[0] == object_colour(1) and asked[-1] is None


def test_far_parts_are_dimmer(tmp_path: Path) -> None:
    sim = Session(tmp_path).simulator
    points = np.concatenate([p.vertices for p in sim.cell.objects])
    view = make_view(points, *preset_angles("iso"))
    colours = picture_scene(sim, Overlays(depth=view)).colours
    dim = colours >= DIM_OFFSET
    assert dim.any() and not dim.all()
    depth = [float(p.vertices.mean(axis=0) @ view.depth_axis()) for p in sim.cell.objects]
    n = len(depth)
    # every dimmed part is further from the viewer than every undimmed one
    assert max(d for d, k in zip(depth, dim[:n]) if k) < min(d for d, k in zip(depth, dim[:n]) if not k)
    assert clamp_point(sim).shape == (3,)


def test_the_standing_parts_as_background_draw_the_same_picture(tmp_path: Path) -> None:
    """PROCESS's poses (a part carried, a collision marked, the in-between pictures, faces
    hidden or not): the scene with the standing parts as its kept background rasterizes to
    the same characters and colours as the scene holding every part, and the next picture
    keeps that background while no part moves."""
    from valterm.core.render.raster import ViewTransform, rasterize

    session = Session(tmp_path, setup="PROCESS")
    session.load_locations("PROCESS")
    sim = session.simulator
    view = ViewTransform()
    view.fit(picture_scene(sim).bounds())
    carried: set[int | None] = set()
    previous: tuple[float, ...] | None = None
    for number, event in enumerate(e for e in session.interpreter.execute("PROCESS") if isinstance(e, PoseEvent)):
        drawn: tuple[float, ...] | None = None if previous is None else tuple((a + b) / 2 for a, b in zip(previous, sim.joints))
        previous = tuple(sim.joints)
        if number % 3:
            continue
        carried.add(sim.carried)
        collided = frozenset({"3", "CLAMP"}) if number % 2 else frozenset()
        kept = None
        for hidden in (False, True):
            shown = Overlays(goal=event.goal or None, collided=collided, axes=True, depth=view, drawn=drawn)
            whole = rasterize(picture_scene(sim, shown), view, 88, 49, back_faces=not hidden)
            standing = picture_scene(sim, Overlays(**{**shown.__dict__, "static_cell": True}))
            assert standing.background is not None and (kept is None or kept is standing.background)
            kept = standing.background  # the same object while the parts stand: drawn once
            split = rasterize(standing, view, 88, 49, back_faces=not hidden)
            assert np.array_equal(whole.chars, split.chars) and np.array_equal(whole.colours, split.colours)
    assert len(carried) > 1  # with a part in the clamp and without
