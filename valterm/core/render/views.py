"""Where the model is seen from: azimuth / elevation presets, orbiting and zooming.

A view is given by the direction towards the viewer: ``azimuth`` in the world XY plane
from +X towards +Y, ``elevation`` above that plane (degrees). Azimuth 0, elevation 0 looks
back along the world X axis with Y to the right and Z up: the SCS mapping of the thesis's
side view (Fig. 2-5). Only the view transform changes; world data never do.
"""

from __future__ import annotations

import math

import numpy as np

from valterm.core.errors import ValtermError
from valterm.core.render.raster import SCS_OFFSET, WORLD_TO_SCS, ViewTransform

# name -> (azimuth, elevation). "iso" is the default oblique three-quarter view: the PUMA's
# forward reach (+X) runs across the picture and the tables are seen from above.
PRESETS: dict[str, tuple[float, float]] = {
    "iso": (-40.0, 30.0),
    "side": (0.0, 0.0),
    "front": (-90.0, 0.0),
    "top": (-90.0, 90.0),
}
PRESET_CYCLE = ("iso", "side", "front", "top")
DEFAULT_VIEW = "iso"
MAX_ELEVATION = 90.0

ORBIT_STEP = 15.0  # degrees an arrow key turns the view
ZOOM_STEP = 1.25  # factor a +/- key zooms


class ViewError(ValtermError):
    """A view name or angle that cannot be used."""


def preset_angles(name: str) -> tuple[float, float]:
    """(azimuth, elevation) of a preset, by name (case-insensitive)."""
    try:
        return PRESETS[name.strip().lower()]
    except KeyError:
        raise ViewError(f"no view {name!r}: use one of {', '.join(PRESET_CYCLE)}") from None


def view_axes(azimuth: float, elevation: float) -> np.ndarray:
    """(3, 3) world directions of the screen's right, up and towards-the-viewer axes."""
    if not (math.isfinite(azimuth) and math.isfinite(elevation)):
        raise ViewError("the azimuth and the elevation must be numbers")
    if abs(elevation) > MAX_ELEVATION:
        raise ViewError(f"the elevation must lie within -{MAX_ELEVATION:g}..{MAX_ELEVATION:g} degrees")
    az, el = math.radians(azimuth), math.radians(elevation)
    towards = np.array([math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)])
    right = np.array([-math.sin(az), math.cos(az), 0.0])
    up = np.cross(towards, right)
    return np.stack([right, up, towards])


def orient(view: ViewTransform, azimuth: float, elevation: float) -> ViewTransform:
    """Turn ``view`` to look from (azimuth, elevation) about its pivot, keeping its zoom and pan."""
    # the view rotation acts after the SCS mapping: R @ WORLD_TO_SCS = the view axes
    view.rotation = view_axes(azimuth, elevation) @ WORLD_TO_SCS.T
    return view


def fit_points(view: ViewTransform, points: np.ndarray, margin: float = 0.04) -> ViewTransform:
    """Frame world ``points`` as seen with the view's rotation (tighter than a box's corners)."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    if not len(pts):
        return view
    view.fit((pts.min(axis=0), pts.max(axis=0)), margin)  # pivot and home box
    assert view.pivot is not None
    scs = pts @ WORLD_TO_SCS.T + SCS_OFFSET
    seen = (scs - view.pivot) @ view.rotation.T
    view.half_extent = np.maximum(np.abs(seen[:, :2]).max(axis=0), 1.0) * (1 + margin)
    return view


def angles(view: ViewTransform) -> tuple[float, float]:
    """(azimuth, elevation) the view looks from (a roll given by ORIENT is ignored)."""
    axes = view.rotation @ WORLD_TO_SCS
    towards, right = axes[2], axes[0]
    elevation = math.degrees(math.asin(max(-1.0, min(1.0, float(towards[2])))))
    if math.hypot(float(towards[0]), float(towards[1])) > 1e-6 and abs(elevation) < 89.0:
        azimuth = math.degrees(math.atan2(float(towards[1]), float(towards[0])))
    else:  # looking straight down (or up): the right axis still tells the azimuth
        azimuth = math.degrees(math.atan2(-float(right[0]), float(right[1])))
    return _round(azimuth), _round(elevation)


def _round(degrees: float) -> float:
    value = round(degrees, 6) + 0.0  # no -0.0
    return value - 360.0 if value > 180.0 else value


def orbit(view: ViewTransform, d_azimuth: float, d_elevation: float) -> ViewTransform:
    """Turn the view about the world's vertical and its own horizontal axis (arrow keys)."""
    azimuth, elevation = angles(view)
    elevation = max(-MAX_ELEVATION, min(MAX_ELEVATION, elevation + d_elevation))
    azimuth = (azimuth + d_azimuth + 180.0) % 360.0 - 180.0
    return orient(view, azimuth, elevation)


def zoom(view: ViewTransform, factor: float) -> ViewTransform:
    if not factor > 0:
        raise ViewError("the zoom factor must be positive")
    return view.scale_by(factor)


def make_view(points: np.ndarray, azimuth: float, elevation: float) -> ViewTransform:
    """A view from (azimuth, elevation) framing the world ``points``."""
    return fit_points(orient(ViewTransform(), azimuth, elevation), points)


def next_preset(view: ViewTransform) -> str:
    """The preset after the one ``view`` shows (the first one if it shows none)."""
    now = angles(view)
    for i, name in enumerate(PRESET_CYCLE):
        az, el = PRESETS[name]
        if abs(now[1] - el) < 0.5 and (abs(el) >= 89.5 or abs((now[0] - az + 180) % 360 - 180) < 0.5):
            return PRESET_CYCLE[(i + 1) % len(PRESET_CYCLE)]
    return PRESET_CYCLE[0]
