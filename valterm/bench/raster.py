"""Timing of the model-view rasterizer (wired into `valterm bench`). No textual import."""

from __future__ import annotations

import time
from typing import Callable

import numpy as np

from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.render.raster import Scene, ViewTransform, object_colour, rasterize


def synthetic_scene(n: int = 25, seed: int = 1) -> Scene:
    """``n`` boxes scattered over the cell (12 edges each: 25 boxes ~ 300 edges)."""
    rng = np.random.default_rng(seed)
    lo = rng.uniform([-900, -900, -650], [700, 700, 800], size=(n, 3))
    size = rng.uniform(60, 300, size=(n, 3))
    return Scene.build((Polyhedron.box(lo[i], lo[i] + size[i]), object_colour(i + 1)) for i in range(n))


def bench_raster(width: int = 200, height: int = 60, back_faces: bool = False, repeats: int = 50,
                 n_polyhedra: int = 25, with_build: bool = False) -> float:
    """Median milliseconds of one ``rasterize`` of the synthetic scene at width x height cells.

    ``back_faces=False`` (hidden-surface removal, polygon by polygon) is the costlier mode.
    ``with_build`` also times ``Scene.build`` (done once per robot pose in the app).
    """
    scene = synthetic_scene(n_polyhedra)
    view = ViewTransform().rotate_by("y", 25).rotate_by("x", 15)
    boxes = [(Polyhedron(scene.vertices[8 * i: 8 * i + 8]), int(c)) for i, c in enumerate(scene.colours)]
    rasterize(scene, view, width, height, back_faces=back_faces, axes=True)  # warm caches
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        if with_build:
            scene = Scene.build(boxes)
        rasterize(scene, view, width, height, back_faces=back_faces, axes=True)
        times.append(time.perf_counter() - t0)
    return float(np.median(times) * 1000)


if __name__ == "__main__":  # pragma: no cover - manual timing
    for w, h in ((80, 24), (200, 60)):
        for bf in (False, True):
            print(f"{w}x{h} back_faces={bf}: {bench_raster(w, h, bf):.3f} ms, "
                  f"with build {bench_raster(w, h, bf, with_build=True):.3f} ms")


def process_scenes(width: int = 200, height: int = 60) -> tuple[Scene, Scene, ViewTransform]:
    """The PROCESS cell and the robot at READY as the app draws them: the whole scene, and the
    robot alone over the cell as a background (what each frame of a motion draws)."""
    from valterm.core import resources
    from valterm.core.files.setup import read_setup
    from valterm.core.render.legend import LED_COLOUR
    from valterm.core.render.raster import link_colour
    from valterm.core.simulator import Simulator

    sim = Simulator(read_setup(resources.data_path("cells", "PROCESS.SET")))
    cell = [(p, object_colour(i)) for i, p in enumerate(sim.cell.objects, start=1)]
    robot = [(p, link_colour(i)) for i, p in enumerate(sim.robot_polyhedra())]
    p0, p1 = sim.model.led_segment(sim.joints, sim.gap, sim.base)
    led = np.stack([np.stack([p0, p1])])
    whole = Scene.build(cell + robot, led, LED_COLOUR)
    framed = Scene.build(robot, led, LED_COLOUR, background=Scene.build(cell))
    view = ViewTransform().rotate_by("y", 25).rotate_by("x", 15).fit(whole.bounds())
    return whole, framed, view


def _drawille_segments(scene: Scene, view: ViewTransform, width: int, height: int) -> np.ndarray:
    """The segments ``rasterize`` draws (all edges, back faces on), in dot coordinates."""
    segs, _ = scene.segments(view, back_faces=True)
    a_mat, b_vec = view.affine()
    assert view.half_extent is not None
    wd, hd = 2 * width, 4 * height
    ppm = min(wd / (2 * view.half_extent[0]), hd / (2 * view.half_extent[1]))
    flat = segs.reshape(-1, 3) @ a_mat[:2].T + b_vec[:2]
    pts = flat * [ppm, -ppm] + [wd / 2, hd / 2]
    clipped: np.ndarray = np.clip(pts, 0, [wd - 1, hd - 1]).reshape(-1, 4)
    return clipped


def bench_raster_vs_drawille(width: int = 200, height: int = 60, rounds: int = 7) -> dict[str, float]:
    """Milliseconds per frame of the PROCESS cell at width x height (back faces on): ours for
    the whole scene, ours per motion frame (cell as background), drawille on the same edges.

    The goal's figure (issue 25) is like-for-like: the same edges, the whole frame drawn
    (no background kept from the frame before) and its text made, as drawille's ``frame()``
    makes its text: ``raster_vs_drawille_x``. A motion's frame, the cell kept per view, is
    ``raster_frame_vs_drawille_x``. Each of the ``rounds`` times all four in turn.

    Raises ImportError when drawille (the ``bench`` extra) is not installed."""
    import drawille

    whole, framed, view = process_scenes(width, height)
    edges = _drawille_segments(whole, view, width, height).tolist()

    def with_drawille() -> str:
        canvas = drawille.Canvas()
        for x1, y1, x2, y2 in edges:
            for x, y in drawille.line(x1, y1, x2, y2):
                canvas.set(x, y)
        return str(canvas.frame(0, 0, 2 * width, 4 * height))

    measured: list[tuple[Callable[[], object], int]] = [
        (lambda: rasterize(whole, view, width, height, back_faces=True), 20),
        (lambda: rasterize(whole, view, width, height, back_faces=True).text(), 20),
        (lambda: rasterize(framed, view, width, height, back_faces=True), 20),
        (with_drawille, 2),
    ]
    for func, _ in measured:
        func()
    # the rounds of ours and drawille's in turn (the order reversed every other round), so a
    # machine that slows down or speeds up during the run moves both sides' medians alike
    runs: list[list[float]] = [[] for _ in measured]
    for r in range(rounds):
        for i in range(len(measured))[:: -1 if r % 2 else 1]:
            func, number = measured[i]
            t0 = time.perf_counter()
            for _ in range(number):
                func()
            runs[i].append((time.perf_counter() - t0) / number)
    whole_ms, text_ms, frame_ms, drawille_ms = (float(np.median(r) * 1000) for r in runs)
    return {
        "raster_process_ms_200x60": whole_ms,
        "raster_process_text_ms_200x60": text_ms,
        "raster_process_frame_ms_200x60": frame_ms,
        "drawille_process_ms_200x60": drawille_ms,
        "raster_vs_drawille_x": drawille_ms / text_ms,
        "raster_frame_vs_drawille_x": drawille_ms / frame_ms,
        "raster_whole_vs_drawille_x": drawille_ms / whole_ms,
        "raster_process_edges": float(len(edges)),
    }
