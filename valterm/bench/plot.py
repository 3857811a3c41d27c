"""The collision scaling curve of ``valterm bench`` as a small SVG, written with plain code.

Log-log axes: parts (5 .. 300) across, microseconds per motion pose up; one line per path,
and a dashed "linear in parts" guide from the old path's first point.
"""

from __future__ import annotations

import math
from typing import Any

PARTS = (5, 30, 100, 300)
W, H, LEFT, RIGHT, TOP, BOTTOM = 560, 360, 70, 150, 30, 50


def scaling_series(entries: dict[str, Any]) -> dict[str, list[tuple[float, float]]]:
    """(parts, µs per pose) for the new path and the old one, from a ``run_all`` result."""
    series: dict[str, list[tuple[float, float]]] = {}
    for label, prefix in (("frames + broad phase (now)", "collision_thesis_us_"),
                          ("polyhedra per pose (before)", "collision_old_us_")):
        points = [(float(n), float(entries[f"{prefix}{n}parts"])) for n in PARTS if f"{prefix}{n}parts" in entries]
        if points:
            series[label] = points
    return series


def scaling_svg(series: dict[str, list[tuple[float, float]]], title: str) -> str:
    """An SVG document of the series on log-log axes."""
    ys = [y for points in series.values() for _, y in points] or [1.0]
    y_lo = 10 ** math.floor(math.log10(min(ys) / 1.5))
    y_hi = 10 ** math.ceil(math.log10(max(ys) * 1.5 * 20))
    x_lo, x_hi = 3.0, 500.0

    def px(x: float) -> float:
        return LEFT + (math.log10(x) - math.log10(x_lo)) / (math.log10(x_hi) - math.log10(x_lo)) * (W - LEFT - RIGHT)

    def py(y: float) -> float:
        return H - BOTTOM - (math.log10(y) - math.log10(y_lo)) / (math.log10(y_hi) - math.log10(y_lo)) * (H - TOP - BOTTOM)

    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="12">',
           f'<rect width="{W}" height="{H}" fill="white"/>',
           f'<text x="{W / 2}" y="18" text-anchor="middle" font-size="13">{title}</text>',
           f'<line x1="{LEFT}" y1="{H - BOTTOM}" x2="{W - RIGHT}" y2="{H - BOTTOM}" stroke="black"/>',
           f'<line x1="{LEFT}" y1="{TOP}" x2="{LEFT}" y2="{H - BOTTOM}" stroke="black"/>',
           f'<text x="{(LEFT + W - RIGHT) / 2}" y="{H - 12}" text-anchor="middle">parts in the cell (log)</text>',
           f'<text x="16" y="{(TOP + H - BOTTOM) / 2}" text-anchor="middle" '
           f'transform="rotate(-90 16 {(TOP + H - BOTTOM) / 2})">µs per motion pose (log)</text>']
    for n in PARTS:
        out.append(f'<line x1="{px(n):.1f}" y1="{H - BOTTOM}" x2="{px(n):.1f}" y2="{H - BOTTOM + 5}" stroke="black"/>')
        out.append(f'<text x="{px(n):.1f}" y="{H - BOTTOM + 18}" text-anchor="middle">{n}</text>')
    decade = y_lo
    while decade <= y_hi:
        out.append(f'<line x1="{LEFT}" y1="{py(decade):.1f}" x2="{W - RIGHT}" y2="{py(decade):.1f}" stroke="#ddd"/>')
        out.append(f'<text x="{LEFT - 6}" y="{py(decade) + 4:.1f}" text-anchor="end">{decade:g}</text>')
        decade *= 10
    colours = ("#1f77b4", "#d62728")
    for (label, points), colour, row in zip(series.items(), colours, range(len(series))):
        path = " ".join(f"{px(x):.1f},{py(y):.1f}" for x, y in points)
        out.append(f'<polyline points="{path}" fill="none" stroke="{colour}" stroke-width="2"/>')
        for x, y in points:
            out.append(f'<circle cx="{px(x):.1f}" cy="{py(y):.1f}" r="3" fill="{colour}"/>')
        ly = TOP + 20 + 36 * row
        out.append(f'<line x1="{W - RIGHT + 10}" y1="{ly}" x2="{W - RIGHT + 30}" y2="{ly}" stroke="{colour}" stroke-width="2"/>')
        out.append(f'<text x="{W - RIGHT + 34}" y="{ly + 4}" font-size="10">{label}</text>')
    if series:
        x0, y0 = next(iter(series.values()))[0]
        out.append(f'<line x1="{px(x0):.1f}" y1="{py(y0):.1f}" x2="{px(300):.1f}" y2="{py(y0 * 300 / x0):.1f}" '
                   'stroke="grey" stroke-dasharray="5,4"/>')
        ly = TOP + 20 + 36 * len(series)
        out.append(f'<line x1="{W - RIGHT + 10}" y1="{ly}" x2="{W - RIGHT + 30}" y2="{ly}" stroke="grey" stroke-dasharray="5,4"/>')
        out.append(f'<text x="{W - RIGHT + 34}" y="{ly + 4}" font-size="10">linear in parts</text>')
    out.append("</svg>")
    return "\n".join(out) + "\n"
