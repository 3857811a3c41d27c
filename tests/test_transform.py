"""Transformations as 4x4 matrices: V+'s yaw pitch roll (issue 23), the thesis's O A T, and the
one conversion between them."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, strategies as st

from valterm.core.kinematics import Location
from valterm.core.transform import (
    Transform, TransformError, convert_orientation, distance, frame, inverse, rotation_to_ypr, rx, ry,
    rz, shift, trans, translation, ypr_to_rotation,
)
from valterm.core.kinematics import oat_to_rotation

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
    # 100 mm along the tool's a axis of a location pointing straight down (pitch 180 -> a = -Z)
    down = trans(300.0, 200.0, 100.0, 0.0, 180.0, 0.0)
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


# -- V+'s yaw pitch roll (issue 23): expected values computed from the V+ definitions ------------

def test_the_issue_s_table() -> None:
    # TRANS(0,0,0,0,0,0) is the null transformation: the tool's Z along the world's Z
    assert trans(0, 0, 0, 0, 0, 0).xyz == (0.0, 0.0, 0.0)
    assert np.allclose((trans(0, 0, 0, 0, 0, 0) @ translation(0, 0, 50)).xyz, (0, 0, 50))
    b = trans(100, 200, 300, 30, 40, 50)
    assert np.allclose((b @ translation(0, 0, 50)).xyz, (127.83, 216.07, 338.30), atol=0.01)
    assert np.allclose(inverse(b).xyz, (-62.31, -117.41, -349.76), atol=0.01)
    assert np.allclose(translation().decompose(), (0, 0, 0, 0, 0, 0))
    assert np.allclose((b @ inverse(b)).decompose(), (0, 0, 0, 0, 0, 0), atol=1e-9)


@pytest.mark.parametrize(("built", "expected"), [
    # compound: a 100 mm tool offset of a tool pointing down lands 100 mm lower
    (lambda: trans(300, 200, 100, 0, 180, 0) @ translation(0, 0, 100), (300, 200, 0, 0, 180, 0)),
    # yaw turns the tool's X: a 10 mm step along it after yaw 90 is along world Y
    (lambda: trans(0, 0, 0, 90, 0, 0) @ translation(10, 0, 0), (0, 10, 0, 0, 0, 90)),
    # pitch 90 tips the tool's Z onto world X
    (lambda: trans(0, 0, 0, 0, 90, 0) @ translation(0, 0, 10), (10, 0, 0, 0, 90, 0)),
    # roll turns about the tool's own Z after yaw and pitch
    (lambda: trans(0, 0, 0, 0, 90, 90) @ translation(10, 0, 0), (0, 10, 0, 0, 90, 90)),
    # RX/RY/RZ are rotations with no translation
    (lambda: rz(45), (0, 0, 0, 0, 0, 45)),
    (lambda: ry(30), (0, 0, 0, 0, 30, 0)),
    (lambda: rx(90) @ translation(0, 10, 0), (0, 0, 10, -90, 90, 90)),
    # inverse of a pure yaw with an offset
    (lambda: inverse(trans(10, 0, 0, 90, 0, 0)), (0, 10, 0, 0, 0, -90)),
    (lambda: inverse(trans(100, 200, 300, 30, 40, 50)), (-62.31, -117.41, -349.76, 130, 40, 150)),
    # SHIFT moves along the world axes and keeps the orientation
    (lambda: shift(trans(1, 2, 3, 10, 20, 30), 10, 0, -5), (11, 2, -2, 10, 20, 30)),
    # a negative pitch is reported with pitch in [0, 180]: yaw and roll turn by 180
    (lambda: trans(0, 0, 0, 10, -20, 30), (0, 0, 0, -170, 20, -150)),
    # pitch 180: only yaw - roll is defined; yaw is reported 0, roll carries the turn
    (lambda: trans(5, 6, 7, 0, 180, 45), (5, 6, 7, 0, 180, 45)),
    (lambda: trans(5, 6, 7, -45, 180, 0), (5, 6, 7, 0, 180, 45)),
    (lambda: rz(30) @ rz(40), (0, 0, 0, 0, 0, 70)),
    # FRAME: X towards the second point, Y towards the third, origin at the fourth
    (lambda: frame(translation(0, 0, 0), translation(0, 10, 0), translation(-5, 0, 0), translation(1, 2, 3)),
     (1, 2, 3, 0, 0, 90)),
])
def test_vplus_cases(built: object, expected: tuple[float, ...]) -> None:
    assert callable(built)
    got = built().decompose()
    assert np.allclose(got, expected, atol=0.01), got


def test_distance_and_dx_dy_dz() -> None:
    a, b = trans(100, 200, 300, 30, 40, 50), trans(100, 200, 300, 30, 40, 50) @ translation(0, 0, 50)
    assert distance(a, b) == pytest.approx(50.0)
    assert (b.xyz[0], b.xyz[1], b.xyz[2]) == pytest.approx((127.83, 216.07, 338.30), abs=0.01)


@given(st.floats(-179, 179), st.floats(1, 179), st.floats(-179, 179))
def test_yaw_pitch_roll_round_trip(yaw: float, pitch: float, roll: float) -> None:
    assert np.allclose(rotation_to_ypr(ypr_to_rotation(yaw, pitch, roll)), (yaw, pitch, roll), atol=1e-6)
    assert np.allclose(trans(0, 0, 0, yaw, pitch, roll).decompose()[3:], (yaw, pitch, roll), atol=1e-6)


@given(angle, angle, angle)
def test_any_yaw_pitch_roll_is_the_same_rotation_after_decompose(yaw: float, pitch: float, roll: float) -> None:
    again = ypr_to_rotation(*rotation_to_ypr(ypr_to_rotation(yaw, pitch, roll)))
    assert np.allclose(again, ypr_to_rotation(yaw, pitch, roll), atol=1e-9)


@given(angle, angle, angle)
def test_the_conversion_keeps_the_pose_both_ways(first: float, second: float, third: float) -> None:
    as_ypr = convert_orientation((first, second, third), "OAT", "YPR")
    assert np.allclose(ypr_to_rotation(*as_ypr), oat_to_rotation(first, second, third), atol=1e-9)
    back = convert_orientation(as_ypr, "YPR", "OAT")
    assert np.allclose(oat_to_rotation(*back), oat_to_rotation(first, second, third), atol=1e-9)
    as_oat = convert_orientation((first, second, third), "YPR", "OAT")
    assert np.allclose(oat_to_rotation(*as_oat), ypr_to_rotation(first, second, third), atol=1e-9)
    again = convert_orientation(as_oat, "OAT", "YPR")
    assert np.allclose(ypr_to_rotation(*again), ypr_to_rotation(first, second, third), atol=1e-9)


def test_known_poses_in_both_conventions() -> None:
    # the thesis's tool straight down (O 90, A 90, T 0) is V+'s pitch 180
    assert np.allclose(convert_orientation((90, 90, 0), "OAT", "YPR"), (0, 180, 0))
    # READY (tool straight up, O 90 A -90) is V+'s null orientation
    assert np.allclose(convert_orientation((90, -90, 0), "OAT", "YPR"), (0, 0, 0))
    assert np.allclose(convert_orientation((0, 0, 0), "YPR", "OAT"), (90, -90, 0))
    with pytest.raises(TransformError, match="not an orientation convention"):
        convert_orientation((0, 0, 0), "OAT", "RPY")
