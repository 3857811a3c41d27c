"""Transformations as 4x4 matrices with O/A/T read-outs (issue 14 item 3)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, strategies as st

from valterm.core.kinematics import Location
from valterm.core.transform import (
    Transform, TransformError, distance, frame, inverse, rx, ry, rz, shift, trans,
)

coordinate = st.floats(-900, 900)
angle = st.floats(-179, 179)


def test_a_process_location_round_trips() -> None:
    a = Location((465.0, -45.0, -245.0), (89.0, 91.0, 0.0))
    back = Transform.of(a).location()
    assert np.allclose(back.xyz, a.xyz) and np.allclose(Transform.of(back).matrix, Transform.of(a).matrix)


@given(coordinate, coordinate, coordinate, angle, st.floats(-89, 89), angle)
def test_inverse_undoes_and_compound_composes(x: float, y: float, z: float, o: float, a: float, t: float) -> None:
    loc = trans(x, y, z, o, a, t)
    assert np.allclose((loc @ inverse(loc)).matrix, np.eye(4), atol=1e-9)
    assert np.allclose((inverse(loc) @ loc).matrix, np.eye(4), atol=1e-9)


def test_compound_expresses_the_second_in_the_first() -> None:
    # 100 mm along the tool's a axis of a location pointing straight down (A = 90 -> a = -Z)
    down = trans(300.0, 200.0, 100.0, 0.0, 90.0, 0.0)
    assert np.allclose(down.rotation[:, 2], [0.0, 0.0, -1.0], atol=1e-9)
    below = down @ trans(0.0, 0.0, 100.0)
    assert np.allclose(below.xyz, (300.0, 200.0, 0.0))


def test_axis_rotations_turn_about_the_world_axes() -> None:
    assert np.allclose((rz(90) @ trans(100.0, 0.0, 0.0)).xyz, (0.0, 100.0, 0.0), atol=1e-9)
    assert np.allclose((rx(90) @ trans(0.0, 100.0, 0.0)).xyz, (0.0, 0.0, 100.0), atol=1e-9)
    assert np.allclose((ry(90) @ trans(0.0, 0.0, 100.0)).xyz, (100.0, 0.0, 0.0), atol=1e-9)


def test_shift_decompose_distance() -> None:
    moved = shift(trans(1.0, 2.0, 3.0, 10.0, 20.0, 30.0), 10.0, 0.0, -5.0)
    x, y, z, o, a, t = moved.decompose()
    assert (x, y, z) == pytest.approx((11.0, 2.0, -2.0))
    assert (o, a, t) == pytest.approx((10.0, 20.0, 30.0))
    assert distance(trans(0, 0, 0), trans(3, 4, 0)) == pytest.approx(5.0)


def test_frame_of_three_points_and_an_origin() -> None:
    f = frame(trans(0, 0, 0), trans(10, 0, 0), trans(0, 10, 0), trans(5, 5, 5))
    assert np.allclose(f.rotation, np.eye(3)) and f.xyz == (5.0, 5.0, 5.0)
    tilted = frame(trans(0, 0, 0), trans(0, 10, 0), trans(-3, 7, 0), trans(0, 0, 0))
    assert np.allclose(tilted.rotation[:, 0], [0, 1, 0]) and np.allclose(tilted.rotation[:, 1], [-1, 0, 0])
    with pytest.raises(TransformError, match="two distinct points"):
        frame(trans(1, 1, 1), trans(1, 1, 1), trans(0, 1, 0), trans(0, 0, 0))
    with pytest.raises(TransformError, match="off the X axis"):
        frame(trans(0, 0, 0), trans(1, 0, 0), trans(5, 0, 0), trans(0, 0, 0))


def test_non_finite_values_are_refused() -> None:
    with pytest.raises(TransformError):
        trans(float("nan"), 0, 0)
