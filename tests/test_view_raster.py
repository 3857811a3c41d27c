"""The model view's rasterizer: pure numpy, no Textual."""

from __future__ import annotations

import time

import numpy as np
import pytest

from valterm.core.cell.polyhedron import Polyhedron
from valterm.bench.raster import bench_raster
from valterm.core.render.legend import AXES_COLOUR
from valterm.core.render.raster import BRAILLE_BASE, Scene, ViewTransform, object_colour, rasterize


def unit_view() -> ViewTransform:
    """1 mm = 1 dot on a 10 x 10 cell canvas (20 x 40 dots): dot x = 10 + Y_w, dot y = 20 - Z_w."""
    return ViewTransform(pivot=np.array([0.0, 26.0, 0.0]), half_extent=np.array([10.0, 20.0]))


def cell_codes(lit: np.ndarray, w: int, h: int) -> np.ndarray:
    """The braille code of each of the w x h cells from the lit dots (their bits in the bit
    map, ``_row_bits``); the sampling numbers cells in rows of w + 1 (the last, never lit, is
    where the text's newline goes)."""
    from valterm.core.render.raster import _PACKED_TO_BRAILLE, _dots_to_codes

    codes: np.ndarray = _PACKED_TO_BRAILLE.take(_dots_to_codes(lit, h * (w + 1))).reshape(h, w + 1)
    assert not codes[:, w].any()
    return codes[:, :w]


def line_scene(*segments: tuple[tuple[float, float, float], tuple[float, float, float]]) -> Scene:
    return Scene.build([], lines=np.array(segments, dtype=float), line_colours=5)


def test_single_horizontal_segment_lights_bottom_dot_row() -> None:
    # Z_w = 0.5 -> dot row 19 = cell row 4, dot row 3 (bits 64 + 128); Y_w -9.5..-0.5 -> dots 0..9
    frame = rasterize(line_scene(((0, -9.5, 0.5), (0, -0.5, 0.5))), unit_view(), 10, 10)
    expected = np.full((10, 10), 0x20)
    expected[4, :5] = BRAILLE_BASE + 64 + 128
    assert (frame.chars == expected).all()
    assert frame.row_text(4) == "⣀⣀⣀⣀⣀     "
    assert (frame.colours[4, :5] == 5).all() and frame.colours.sum() == 5 * 5


def test_single_vertical_segment_lights_left_column() -> None:
    # Y_w = -9.5 -> dot col 0; Z_w 19.5..12.5 -> dot rows 0..7 -> cells (0, 0), (1, 0) left column
    frame = rasterize(line_scene(((0, -9.5, 19.5), (0, -9.5, 12.5))), unit_view(), 10, 10)
    assert frame.chars[0, 0] == frame.chars[1, 0] == BRAILLE_BASE + 1 + 2 + 4 + 64
    assert (frame.chars != 0x20).sum() == 2


def test_braille_bit_order_single_dots() -> None:
    # dot (row, col) inside cell (0, 0) -> bit
    bits = {(0, 0): 1, (1, 0): 2, (2, 0): 4, (0, 1): 8, (1, 1): 16, (2, 1): 32, (3, 0): 64, (3, 1): 128}
    for (r, c), bit in bits.items():
        y_w, z_w = c + 0.5 - 10, 20 - (r + 0.5)
        frame = rasterize(line_scene(((0, y_w, z_w), (0, y_w, z_w))), unit_view(), 10, 10)
        assert frame.chars[0, 0] == BRAILLE_BASE + bit, (r, c)


def test_clipping_keeps_far_away_and_huge_segments_cheap() -> None:
    view = unit_view().scale_by(1e6)
    t0 = time.perf_counter()
    frame = rasterize(line_scene(((0, -50, -50), (0, 50, 50)), ((0, 1e9, 0), (0, 2e9, 0))), view, 10, 10)
    assert time.perf_counter() - t0 < 0.5
    assert frame.chars.shape == (10, 10)


def box() -> Polyhedron:
    return Polyhedron.box(np.array([-100.0, -100.0, -100.0]), np.array([100.0, 100.0, 100.0]))


def test_back_face_of_a_box_seen_head_on_is_hidden() -> None:
    scene = Scene.build([(box(), 1)])
    normals = scene.face_normals()
    visible = scene.visible_faces(ViewTransform())  # default view: from +X_w
    far = np.flatnonzero(normals[:, 0] < -0.99)
    near = np.flatnonzero(normals[:, 0] > 0.99)
    assert len(far) == len(near) == 1
    assert not visible[far[0]] and visible[near[0]]
    assert visible.sum() == 5  # the near face and four edge-on sides


def test_back_faces_on_draws_all_12_edges_off_hides_far_corner() -> None:
    scene = Scene.build([(box(), 1)])
    view = ViewTransform().rotate_by("y", 30).rotate_by("x", 20)
    full, _ = scene.segments(view, back_faces=True)
    assert len(full) == 12
    culled, _ = scene.segments(view, back_faces=False)
    assert len(culled) == 12  # three front quads polygon by polygon: 3 shared edges twice (Fig. 2-5)
    unique = {tuple(sorted(map(tuple, np.round(s, 6)))) for s in culled}
    assert len(unique) == 9
    depth = scene.vertices @ view.depth_axis()
    far_corner = tuple(np.round(scene.vertices[depth.argmin()], 6))
    assert all(far_corner not in edge for edge in unique)
    dots_full = rasterize(scene, view, 40, 20, back_faces=True).chars
    dots_culled = rasterize(scene, view, 40, 20, back_faces=False).chars
    assert (dots_culled != 0x20).sum() < (dots_full != 0x20).sum()


def test_view_transform_never_mutates_world_data() -> None:
    poly = box()
    before = poly.vertices.copy()
    scene = Scene.build([(poly, 1)], lines=[[(0, 0, 0), (0, 0, 500)]])
    scene_before = scene.vertices.copy(), scene.lines.copy()
    view = ViewTransform()
    for step in range(6):
        view.rotate_by("xyz"[step % 3], 17).scale_by(1.3).pan_by(10, -5)
        rasterize(scene, view, 50, 20, back_faces=bool(step % 2), axes=True)
    assert (poly.vertices == before).all()
    assert (scene.vertices == scene_before[0]).all() and (scene.lines == scene_before[1]).all()
    view.reset()
    assert np.allclose(view.rotation, np.eye(3)) and view.scale == 1.0 and not view.pan.any()


def test_ascii_fallback_is_ascii_and_draws() -> None:
    scene = Scene.build([(box(), 1), (box().translated(np.array([0, 500.0, 300])), 2)])
    view = ViewTransform().rotate_by("y", 30).rotate_by("x", 20)
    for back_faces in (True, False):
        frame = rasterize(scene, view, 60, 20, back_faces=back_faces, axes=True, ascii=True)
        text = frame.text()
        assert text.isascii()
        assert sum(ch not in " \n" for ch in text) > 20


def centre_of(frame_colours: np.ndarray, colour: int) -> tuple[float, float]:
    rows, cols = np.nonzero(frame_colours == colour)
    assert len(rows), f"colour {colour} not drawn"
    return float(rows.mean()), float(cols.mean())


def test_default_view_places_boxes_as_scs_says() -> None:
    lo, size = np.array([-50.0, -50.0, -50.0]), np.array([100.0, 100.0, 100.0])
    left = Polyhedron.box(lo + [0, -600, 0], lo + size + [0, -600, 0])  # -Y_w
    right = Polyhedron.box(lo + [0, 600, 0], lo + size + [0, 600, 0])  # +Y_w
    high = Polyhedron.box(lo + [0, 0, 800], lo + size + [0, 0, 800])  # higher Z_w
    scene = Scene.build([(left, object_colour(1)), (right, object_colour(2)), (high, object_colour(3))])
    frame = rasterize(scene, ViewTransform(), 80, 24)
    (rl, cl), (rr, cr), (rh, ch) = (centre_of(frame.colours, object_colour(n)) for n in (1, 2, 3))
    assert cr > cl + 10  # +Y_w to the right
    assert rh < rl - 3 and rh < rr - 3  # higher Z_w higher up (smaller row)
    assert abs(rl - rr) < 0.5  # same height, same row


def dot_grid(chars: np.ndarray) -> np.ndarray:
    """Decode braille cells back into their (4H, 2W) dots."""
    code = np.where(chars >= BRAILLE_BASE, chars - BRAILLE_BASE, 0).astype(np.uint8)
    weights = np.array([[1, 8], [2, 16], [4, 32], [64, 128]], dtype=np.uint8)
    dots = (code[:, None, :, None] & weights[None, :, None, :]) > 0  # (H, 4, W, 2)
    return dots.reshape(4 * chars.shape[0], 2 * chars.shape[1])


def test_square_stays_square() -> None:
    # braille dots are about square on a 1:2 cell, so a cube seen head-on spans equal dots
    cube = Polyhedron.box(np.array([-200.0, -200, 0]), np.array([200.0, 200, 400]))
    for w, h in ((80, 24), (200, 60), (40, 40)):
        dots = dot_grid(rasterize(Scene.build([(cube, 1)]), ViewTransform(), w, h).chars)
        rows, cols = np.nonzero(dots)
        assert abs(np.ptp(rows) - np.ptp(cols)) <= 1, (w, h)


def test_default_view_fits_ready_robot_and_cell() -> None:
    # a READY arm reaching up to 990.6 mm and a cell corner at Y_w = +-1000 are on the canvas
    pts = [((0, 0, 0), (0, 0, 990.6)), ((0, -1000, -610), (0, 1000, -610))]
    frame = rasterize(line_scene(*pts), ViewTransform(), 80, 24)
    lit_rows = np.flatnonzero((frame.chars != 0x20).any(axis=1))
    lit_cols = np.flatnonzero((frame.chars != 0x20).any(axis=0))
    assert lit_rows.min() >= 0 and lit_rows.max() <= 23 and len(lit_rows) > 12
    assert lit_cols.min() > 0 and lit_cols.max() < 79  # nothing cut at the sides


def test_axes_are_drawn_and_labelled() -> None:
    scene = Scene.build([])
    frame = rasterize(scene, ViewTransform().rotate_by("y", 30).rotate_by("x", 20), 60, 20, axes=True)
    text = frame.text()
    assert all(name in text for name in "XYZ")
    assert (frame.colours == AXES_COLOUR).sum() > 5
    assert "X" not in rasterize(scene, ViewTransform(), 60, 20, axes=False).text()


def test_later_items_win_shared_cells() -> None:
    a = box()
    scene = Scene.build([(a, 4), (a, 9)])
    frame = rasterize(scene, ViewTransform(), 40, 12)
    drawn = frame.colours[frame.chars != 0x20]
    assert (drawn == 9).all()


def test_changed_spans_report_only_changed_rows() -> None:
    lo, hi = np.array([-50.0, -50, -50]), np.array([50.0, 50, 50])
    top = Polyhedron.box(lo + [0, 0, 700], hi + [0, 0, 700])
    bottom = Polyhedron.box(lo + [0, 0, -400], hi + [0, 0, -400])
    view = ViewTransform()
    first = rasterize(Scene.build([(top, 1), (bottom, 2)]), view, 80, 24)
    moved = rasterize(Scene.build([(top, 1), (bottom.translated(np.array([0, 200.0, 0])), 2)]), view, 80, 24)
    rows, x0, x1 = moved.changed_spans(first)
    top_rows = np.flatnonzero((first.colours == 1).any(axis=1))
    assert len(rows) and not set(rows) & set(top_rows)
    assert (x0 < x1).all()
    assert len(moved.changed_spans(moved)[0]) == 0


def test_bench_raster_is_fast() -> None:
    ms = bench_raster(200, 60, repeats=10)
    assert 0 < ms < 20  # the budget is 2 ms; generous here for loaded CI machines


def test_raster_clock_and_bench_import_no_textual_or_rich() -> None:
    import subprocess
    import sys

    code = (
        "import sys, valterm.core.render.raster, valterm.core.render.clock, valterm.bench.raster\n"
        "bad = [m for m in sys.modules if m.split('.')[0] in ('textual', 'rich')]\n"
        "assert not bad, bad\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


def test_static_background_draws_the_same_frame_as_one_scene() -> None:
    """The cell rasterised once as a background, the robot over a copy: the same picture."""
    from valterm.core.render.raster import _BACKGROUNDS, link_colour, object_colour

    rng = np.random.default_rng(5)
    cell = [(Polyhedron.box(lo, lo + rng.uniform(40, 300, 3)), object_colour(i + 1))
            for i, lo in enumerate(rng.uniform(-900, 700, (20, 3)))]
    robot = [(Polyhedron.box(lo, lo + rng.uniform(20, 120, 3)), link_colour(i))
             for i, lo in enumerate(rng.uniform(-300, 300, (8, 3)))]
    led = np.array([[[0.0, 0, 500], [0, 70, 500]]])
    background = Scene.build(cell)
    _BACKGROUNDS.clear()
    for turn, (w, h) in ((0.0, (80, 24)), (35.0, (200, 60)), (-70.0, (33, 17))):
        view = ViewTransform().rotate_by("y", turn).rotate_by("x", 20)
        for back_faces in (True, False):
            for axes, ascii in ((False, False), (True, False), (True, True)):
                whole = rasterize(Scene.build(cell + robot, led), view, w, h, back_faces, axes, ascii)
                split = rasterize(Scene.build(robot, led, background=background), view, w, h, back_faces, axes, ascii)
                assert np.array_equal(whole.chars, split.chars) and np.array_equal(whole.colours, split.colours)
                assert (whole.chars != 0x20).sum() > 50
    assert len(_BACKGROUNDS) == 6          # one per view, size and face mode: the rest were reused


def test_each_point_projected_once_lights_the_dots_of_the_world_segments() -> None:
    """``rasterize`` projects each vertex once and pairs the points into edges; the dots it
    lights are those of the scene's world segments sampled one by one (``_samples``)."""
    from valterm.core.render.raster import _row_bits, _samples, _to_dots, link_colour

    rng = np.random.default_rng(11)
    for trial in range(12):
        boxes = [(Polyhedron.box(lo, lo + rng.uniform(20, 400, 3)), link_colour(i % 7))
                 for i, lo in enumerate(rng.uniform(-900, 700, (15, 3)))]
        lines = rng.uniform(-800, 800, (3, 2, 3))
        scene = Scene.build(boxes, lines)
        view = ViewTransform().rotate_by("y", rng.uniform(-180, 180)).rotate_by("x", rng.uniform(-90, 90))
        view.scale_by(rng.uniform(0.7, 2.5))  # some edges leave the canvas: the clipped path too
        w, h = (80, 24) if trial % 2 else (150, 41)
        for back_faces in (True, False):
            frame = rasterize(scene, view, w, h, back_faces=back_faces)
            idx = scene.index  # the world segments, fetched one by one from the topology
            edges = idx.edges if back_faces else idx.face_edges[scene.visible_faces(view)[idx.face_edge_face]]
            segs = np.concatenate([scene.vertices[edges], lines])
            cells, lit, _ = _samples(segs, np.ones(len(segs), dtype=np.intp), _to_dots(view, 2 * w, 4 * h, 1.0), w, h)
            codes = cell_codes(lit, w, h)
            assert np.array_equal(frame.chars != 0x20, codes != 0)
            assert np.array_equal(frame.chars[codes != 0] - 0x2800, codes[codes != 0])
            assert len(np.unique(cells)) > 100
    assert _row_bits(80, 24).shape == (4 * 24,)


def test_frame_text_and_lines_are_its_rows() -> None:
    """``text`` decodes the whole grid at once (issue 25): the same rows ``row_text`` gives."""
    from valterm.core.render.raster import Frame

    scene = Scene.build([(Polyhedron.box([-300, -200, -100], [250, 300, 400]), 3)])
    frame = rasterize(scene, ViewTransform().rotate_by("y", 25), 37, 11, axes=True)
    rows = [frame.row_text(y) for y in range(frame.height)]
    assert any(ch not in " " for row in rows for ch in row)
    assert frame.lines() == rows and frame.text() == "\n".join(rows)
    # the text drawn as UTF-16 units, the characters a view of them (the axes' labels too):
    # the same text and rows as a frame of the same characters made from scratch
    assert frame.text_units is not None and np.shares_memory(frame.chars, frame.text_units)
    plain = Frame(frame.chars.astype(np.uint32), frame.colours)
    assert plain.text_units is None and plain.text() == frame.text()
    assert [plain.row_text(y) for y in range(frame.height)] == rows
    assert all(label in frame.text() for label in "XYZ") and frame.text().count("\n") == frame.height - 1
    # ASCII, a kept background (its grid copied, the touched cells redrawn), odd and even
    # cell counts (one lookup a cell or a pair): the same text as from scratch
    robot = Scene.build([(Polyhedron.box([-50, -50, 0], [60, 40, 500]), 9)], background=scene)
    for drawn, (w, h) in ((robot, (37, 11)), (robot, (40, 12)), (scene, (1, 1)), (scene, (12, 5))):
        for ascii in (False, True):
            got = rasterize(drawn, ViewTransform().rotate_by("x", 30), w, h, axes=True, ascii=ascii)
            made = Frame(got.chars.astype(np.uint32), got.colours)
            assert got.text() == made.text() and got.lines() == made.lines(), (w, h, ascii)
            assert [got.row_text(y) for y in range(h)] == made.lines()
    for h, w in ((0, 4), (3, 0)):
        empty = Frame(np.full((h, w), 0x20, dtype=np.uint32), np.zeros((h, w), dtype=np.uint8))
        assert (empty.lines(), empty.text()) == ([""] * h, "\n" * max(h - 1, 0))


def _reference_dot_samples(pts: np.ndarray, prio: np.ndarray, w: int, h: int) -> tuple[np.ndarray, ...]:
    """The sampling as it was before issue 25's third pass (kept here to compare against):
    per segment n = ceil(longest side) + 1 samples at t = k / max(n - 1, 1), each dot the
    truncation of start + t * direction, clipped segments clamped to the canvas."""
    from valterm.core.render.raster import _clip

    wd, hd = 2 * w, 4 * h
    hi = np.array([wd - 1e-6, hd - 1e-6])
    inside = len(pts) == 0 or (pts.min() >= 0.0 and pts[:, :, 0].max() <= hi[0] and pts[:, :, 1].max() <= hi[1])
    if inside:
        a, b, p = pts[:, 0], pts[:, 1], prio
    else:
        a, b, keep = _clip(pts[:, 0], pts[:, 1], hi)
        a, b, p = a[keep], b[keep], prio[keep]
    d = b - a
    n = np.ceil(np.abs(d).max(axis=1, initial=0.0)).astype(np.intp) + 1
    first = np.repeat(np.cumsum(n) - n, n)
    t = (np.arange(int(n.sum()), dtype=float) - first) / np.repeat(np.maximum(n - 1, 1), n)
    x = (np.repeat(a[:, 0], n) + t * np.repeat(d[:, 0], n)).astype(np.intp)
    y = (np.repeat(a[:, 1], n) + t * np.repeat(d[:, 1], n)).astype(np.intp)
    if not inside:
        x, y = np.clip(x, 0, wd - 1), np.clip(y, 0, hd - 1)
    # bit 4 c + r (column c, row r in the cell) of the cell's byte (round 11; the braille
    # weights' bit before: the same dots, ``_PACKED_TO_BRAILLE`` maps one to the other)
    lit = ((y >> 2) * (w + 1) + (x >> 1)) * 8 + 4 * (x & 1) + (y & 3)
    return lit >> 3, lit, np.repeat(p, n)


def test_sampling_lights_the_dots_it_lit_before_the_third_pass() -> None:
    """Issue 25's third pass samples the segments from contiguous rows of their ends: every
    sample (its cell, bit and owner) is the one the earlier sampling gave, on random segment
    sets inside, across and outside the canvas, with ends on whole and half dots (cell edges)."""
    from valterm.core.render.raster import _dot_samples

    rng = np.random.default_rng(25)
    clipped = 0
    for trial in range(150):
        w, h = int(rng.integers(1, 220)), int(rng.integers(1, 70))
        span = np.array([2 * w, 4 * h]) * (1.0 if trial % 2 else 1.4)
        pts = rng.uniform(-0.2, 1.0, (int(rng.integers(0, 300)), 2, 2)) * span
        if trial % 3 == 0:
            pts = np.round(pts * 2) / 2             # whole and half dots: the cell edges
        if trial % 4 == 0:
            pts = np.clip(pts, 0, [2 * w - 1e-6, 4 * h - 1e-6])
        prio = rng.integers(1, 40, len(pts))
        got, want = _dot_samples(pts, prio, w, h), _reference_dot_samples(pts, prio, w, h)
        for g, r in zip(got, want):
            assert np.array_equal(g, r), trial
        clipped += int(len(pts) > 0 and (pts.min() < 0 or (pts.max(axis=(0, 1)) >= [2 * w, 4 * h]).any()))
    assert 30 < clipped < 150       # both paths ran


def test_frames_are_those_of_the_earlier_sampling() -> None:
    """Whole frames of random scenes and views (some edges off the canvas): the dots of the
    earlier sampling applied to the scene's world segments, projected one by one."""
    from valterm.core.render.raster import _projection, _to_dots, link_colour

    rng = np.random.default_rng(52)
    for trial in range(16):
        boxes = [(Polyhedron.box(lo, lo + rng.uniform(5, 500, 3)), link_colour(i % 7))
                 for i, lo in enumerate(rng.uniform(-900, 700, (int(rng.integers(1, 25)), 3)))]
        scene = Scene.build(boxes, rng.uniform(-800, 800, (2, 2, 3)))
        view = ViewTransform().rotate_by("y", rng.uniform(-180, 180)).rotate_by("x", rng.uniform(-90, 90))
        view.scale_by(rng.uniform(0.6, 2.5))
        w, h = (200, 60) if trial % 2 else (77, 23)
        for back_faces in (True, False):
            frame = rasterize(scene, view, w, h, back_faces=back_faces)
            segs, prio = scene.segments(view, back_faces)
            project, offset = _projection(_to_dots(view, 2 * w, 4 * h, 1.0))
            pts = (segs.reshape(-1, 3) @ project + offset).reshape(-1, 2, 2)
            cells, lit, owner = _reference_dot_samples(pts, prio, w, h)
            codes = cell_codes(lit, w, h).ravel()
            colours = np.zeros(h * (w + 1), dtype=np.uint8)
            colours[cells] = scene.palette_indices()[owner]
            assert np.array_equal(frame.chars.ravel(), np.where(codes > 0, BRAILLE_BASE + codes.astype(np.uint32), 0x20))
            assert np.array_equal(frame.colours, colours.reshape(h, w + 1)[:, :w])
            assert (codes > 0).sum() > 20


def test_characters_two_cells_a_lookup_and_text_beyond_the_braille_block() -> None:
    """Odd and even cell counts give the characters of one lookup per cell; a frame holding
    characters above the surrogates still makes its text (UTF-32, not UTF-16)."""
    from valterm.core.render.raster import _BRAILLE_TABLE, _PACKED_TO_BRAILLE, Frame, _ascii_table, _chars

    codes = np.random.default_rng(3).integers(0, 256, 101).astype(np.uint8)
    for ascii, table in ((False, _BRAILLE_TABLE), (True, _ascii_table().take(_PACKED_TO_BRAILLE))):
        for part in (codes, codes[:100], codes[1:], codes[::2]):
            assert np.array_equal(_chars(part, ascii), table[part])
    wide = np.array([[0x1F916, 0x2800 + 7], [0x41, 0xFFFF]], dtype=np.uint32)
    frame = Frame(wide, np.zeros((2, 2), dtype=np.uint8))
    assert frame.text() == "\U0001F916\u2807\nA\uffff"
    assert frame.lines() == [frame.row_text(0), frame.row_text(1)]


def test_sample_fractions_are_the_quotients_of_whole_numbers() -> None:
    """Issue 25, fourth pass: a sample's t is looked up, not divided; row s of the table holds
    k / max(s, 1) for k = 0 .. s, bit for bit, and a bigger canvas grows the table."""
    from valterm.core.render.raster import _fractions

    for longest in (3, 40, 17, 130):
        table, row_ends = _fractions(longest)
        assert len(row_ends) > longest
        for s in (0, 1, 2, 3, longest // 2, longest):
            row = table[row_ends[s] - (s + 1): row_ends[s]]
            k = np.arange(s + 1, dtype=float)
            assert row.tobytes() == (k / max(s, 1)).tobytes(), s


def test_a_scene_of_many_points_keeps_its_offsets_long_enough() -> None:
    """The view's offset is kept repeated for the flat products (issue 25, fourth pass): a
    scene with more points than first kept (1200 vertices) draws the earlier sampling's dots."""
    from valterm.core.render.raster import _projection, _to_dots

    rng = np.random.default_rng(1200)
    view = ViewTransform().rotate_by("y", 35).rotate_by("x", -20)
    small = Scene.build([(Polyhedron.box([0, 0, 0], [100, 100, 100]), 3)])
    rasterize(small, view, 80, 24)                   # the offsets kept for 8 points first
    boxes = [(Polyhedron.box(lo, lo + rng.uniform(5, 200, 3)), 3) for lo in rng.uniform(-900, 700, (150, 3))]
    scene = Scene.build(boxes)
    for back_faces in (True, False):
        frame = rasterize(scene, view, 80, 24, back_faces=back_faces)
        segs, prio = scene.segments(view, back_faces)
        project, offset = _projection(_to_dots(view, 160, 96, 1.0))
        pts = (segs.reshape(-1, 3) @ project + offset).reshape(-1, 2, 2)
        codes = cell_codes(_reference_dot_samples(pts, prio, 80, 24)[1], 80, 24).ravel()
        assert np.array_equal(frame.chars.ravel(), np.where(codes > 0, BRAILLE_BASE + codes.astype(np.uint32), 0x20))
        assert (codes > 0).sum() > 200


def test_the_kept_canvas_follows_every_change_of_the_view() -> None:
    """One record per view state and canvas, found by one lookup a frame (round 11): the
    same state finds the same record; a turn, a zoom, a pan, a refit, another size or dot
    aspect finds another, and draws the frame drawn with every kept record dropped."""
    from valterm.core.render import raster

    scene = Scene.build([(Polyhedron.box(np.array([0.0, 0, 0]), np.array([300.0, 200, 100])), 3),
                         (Polyhedron.box(np.array([-400.0, 50, 0]), np.array([-300.0, 90, 500])), 5)])
    view = ViewTransform().rotate_by("y", 20)
    first = raster._canvas(view, 80, 24, 1.0)
    assert raster._canvas(view.copy(), 80, 24, 1.0) is first
    changes = [
        (view.copy().rotate_by("x", 5), 80, 24, 1.0), (view.copy().scale_by(1.5), 80, 24, 1.0),
        (view.copy().pan_by(40, 0), 80, 24, 1.0), (view.copy().fit(scene.bounds()), 80, 24, 1.0),
        (view, 81, 24, 1.0), (view, 80, 25, 1.0), (view, 80, 24, 1.2),
    ]
    for changed, w, h, aspect in changes:
        rasterize(scene, view, 80, 24)              # the record of the view before the change
        assert raster._canvas(changed, w, h, aspect) is not first
        kept = rasterize(scene, changed, w, h, dot_aspect=aspect)
        raster._CANVASES.clear()
        fresh = rasterize(scene, changed, w, h, dot_aspect=aspect)
        assert kept.text() == fresh.text() and np.array_equal(kept.colours, fresh.colours)
        assert kept.text() != rasterize(scene, view, 80, 24).text() or (w, h) != (80, 24)


# projecting an infinite end warns (inf times 0 in the matrix product) before the clip drops it
@pytest.mark.filterwarnings("ignore:invalid value encountered in matmul:RuntimeWarning")
def test_segments_with_ends_not_finite_are_left_out_of_the_frame() -> None:
    drawn = ((0, -9.5, 0.5), (0, -0.5, 0.5))
    expected = rasterize(line_scene(drawn), unit_view(), 10, 10)
    for bad in (np.nan, np.inf, -np.inf):
        frame = rasterize(line_scene(drawn, ((0, bad, 3.0), (0, 2.0, 3.0)), ((0, 1.0, 1.0), (0, 1.0, bad))),
                          unit_view(), 10, 10)
        assert (frame.chars == expected.chars).all(), bad
        assert (frame.colours == expected.colours).all(), bad


def test_row_bits_and_pair_tables_are_each_dot_and_pair_as_defined() -> None:
    """The bit map's layout and the character tables hold what their definitions say, dot
    by dot and pair by pair: dot (y, x) of a w x h canvas lies in cell (y // 4, x // 2) of
    rows of w + 1, bit 4 * (x % 2) + y % 4 of its byte (``_row_bits``: its row's bit plus
    4 x), and that byte's bits are the braille weights of the same dots (``_PACKED_TO_BRAILLE``);
    the pair of packed codes first + 256 * second is the first's character in the low half,
    the second's in the high."""
    from valterm.core.render.raster import BRAILLE_WEIGHTS, _PACKED_TO_BRAILLE, _ascii_table, _pair_table, _row_bits

    for w, h in ((1, 1), (3, 2), (7, 5), (80, 24)):
        rows = _row_bits(w, h)
        assert rows.shape == (4 * h,)
        for y in range(4 * h):
            for x in range(2 * w):
                expected_cell = (y // 4) * (w + 1) + x // 2
                assert rows[y] + 4 * x == expected_cell * 8 + 4 * (x % 2) + y % 4
    for row in range(4):
        for column in range(2):      # the one dot of bit 4 c + r is braille's dot (r, c)
            assert _PACKED_TO_BRAILLE[1 << (4 * column + row)] == BRAILLE_WEIGHTS[row, column]
    assert sorted(_PACKED_TO_BRAILLE) == list(range(256))
    for ascii in (False, True):
        braille = [int(b) for b in _PACKED_TO_BRAILLE]
        chars = ([int(_ascii_table()[b]) for b in braille] if ascii
                 else [BRAILLE_BASE + b if b else 0x20 for b in braille])
        pairs = _pair_table(ascii)
        assert pairs.shape == (65536,) and pairs.dtype == np.dtype("<u4")
        for first, second in ((0, 0), (1, 0), (0, 1), (255, 3), (17, 200), (255, 255)):
            assert int(pairs[first + 256 * second]) == chars[first] | (chars[second] << 16)
