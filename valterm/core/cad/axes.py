"""The one axis convention between the world (Z up, millimetres) and glTF (Y up, metres).

glTF says +Y is up; the VAL-II SIMULATOR's world has +Z up. Export and import both use this
matrix, so a part exported to GLB and read back stands as it stood: world X, Y, Z -> glTF
X, Z, -Y, and back.
"""

from __future__ import annotations

import numpy as np

# world (Z up) -> glTF (Y up): X stays, Y_gltf = Z_w, Z_gltf = -Y_w
Z_UP_TO_Y_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])


def world_to_gltf(points: np.ndarray) -> np.ndarray:
    """(..., 3) world points -> the same points in glTF axes (units unchanged)."""
    out: np.ndarray = np.asarray(points, dtype=float) @ Z_UP_TO_Y_UP.T
    return out


def gltf_to_world(points: np.ndarray) -> np.ndarray:
    """(..., 3) points in glTF axes (Y up) -> world axes (Z up), units unchanged."""
    out: np.ndarray = np.asarray(points, dtype=float) @ Z_UP_TO_Y_UP
    return out
