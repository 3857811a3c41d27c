"""Timing of the model-view rasterizer (wired into `valterm bench`). No textual import."""

from __future__ import annotations

import time

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
