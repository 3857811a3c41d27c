"""The model view's picture as SVG vector lines (``valterm render --svg``): the same segments
the rasterizer draws (hidden faces removed), in the same view, coloured like the terminal."""

from __future__ import annotations

import numpy as np

from valterm.core.render.legend import DIM_OFFSET
from valterm.core.render.raster import Scene, ViewTransform

# colour index -> SVG colour, by range (robot warm, objects cool, overlays distinct)
_FIXED = {1: "#9e9e9e", 2: "#ff0000", 3: "#ff3030", 4: "#00d7ff", 5: "#ff00ff", 6: "#ffd700"}
_LINK = "#d7af00"
_OBJECT = ("#00afff", "#00ff87", "#ff87ff", "#87d7ff", "#87ff87", "#ffafff", "#87ffd7", "#af87ff")


def _colour(index: int) -> str:
    dim = index >= DIM_OFFSET
    index = index - DIM_OFFSET if dim else index
    if index in _FIXED:
        colour = _FIXED[index]
    elif 8 <= index < 16:
        colour = _LINK
    else:
        colour = _OBJECT[(index - 16) % len(_OBJECT)]
    return colour + ("80" if dim else "")


def scene_svg(scene: Scene, view: ViewTransform, width_cells: int, height_cells: int,
              cell_px: tuple[int, int] = (8, 16)) -> str:
    """An SVG document of ``scene`` framed as ``rasterize`` frames it at that many cells."""
    wpx, hpx = width_cells * cell_px[0], height_cells * cell_px[1]
    segs, prio = scene.segments(view, back_faces=False)
    palette = scene.palette_indices()
    a_mat, b_vec = view.affine()
    half = view.half_extent
    assert half is not None
    ppm = min(wpx / (2 * half[0]), hpx / (2 * half[1]))
    flat = segs.reshape(-1, 3) @ a_mat[:2].T + b_vec[:2]
    xy = (flat * np.array([ppm, -ppm]) + np.array([wpx / 2, hpx / 2])).reshape(-1, 2, 2)
    lines = [
        f'<line x1="{p[0, 0]:.1f}" y1="{p[0, 1]:.1f}" x2="{p[1, 0]:.1f}" y2="{p[1, 1]:.1f}" '
        f'stroke="{_colour(int(palette[q]))}"/>'
        for p, q in zip(xy, prio)
    ]
    return "\n".join([
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{wpx}" height="{hpx}" viewBox="0 0 {wpx} {hpx}">',
        f'<rect width="{wpx}" height="{hpx}" fill="black"/>',
        '<g stroke-width="1" stroke-linecap="round">',
        *lines,
        "</g>",
        "</svg>",
        "",
    ])
