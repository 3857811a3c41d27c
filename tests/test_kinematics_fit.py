"""ik's stop fit (issue 25: three candidates a joint, wrap and fit in one pass) gives what
fit_to_stops gives on the angles wrap180 gives, on any angles ik_fast can return; and ik()
as a whole gives what ik_fast, wrap180 and fit_to_stops give one after the other."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from valterm.core import kinematics as K
from valterm.core.kinematics import BeyondStop, fit_to_stops, robot_geometry, wrap180

GEOMETRY = robot_geometry()
wrapped = st.floats(min_value=-179.999999, max_value=180.0, allow_nan=False)
turn = st.floats(min_value=-2 * math.pi, max_value=2 * math.pi, allow_nan=False)


def outcome(fit, *args):  # type: ignore[no-untyped-def]
    try:
        return fit(*args)
    except BeyondStop as stop:
        return ("beyond", stop.joint)


currents = st.one_of(st.none(), st.lists(st.floats(min_value=-300, max_value=300), min_size=6, max_size=6))


def wrapped_degrees(radians: list[float]) -> list[float]:
    return [wrap180(math.degrees(v)) for v in radians]


@settings(max_examples=500, deadline=None)
@given(st.lists(wrapped, min_size=6, max_size=6), currents)
def test_the_fast_fit_is_fit_to_stops(angles: list[float], current: list[float] | None) -> None:
    radians = [math.radians(a) for a in angles]
    expected = outcome(fit_to_stops, wrapped_degrees(radians), current, GEOMETRY)
    assert outcome(K._fit_turns, radians, current, GEOMETRY.fit_bounds) == expected


@settings(max_examples=500, deadline=None)
@given(st.lists(st.one_of(turn, st.sampled_from([0.0, math.pi, -math.pi, math.pi / 2, 2 * math.pi])),
                min_size=6, max_size=6), currents)
def test_the_fast_fit_takes_any_turn_ik_fast_gives(radians: list[float], current: list[float] | None) -> None:
    """Unwrapped angles (JT1 is a difference of two atan2, a flipped wrist adds half a turn),
    stops met exactly (-180 wraps to 180; 180 - 360 is JT2's -180)."""
    radians = [v + math.pi if i in (3, 5) else v for i, v in enumerate(radians)]
    expected = outcome(fit_to_stops, wrapped_degrees(radians), current, GEOMETRY)
    assert outcome(K._fit_turns, radians, current, GEOMETRY.fit_bounds) == expected


joint_sets = st.tuples(*(st.one_of(st.floats(min_value=low - 20, max_value=high + 20), st.sampled_from([low, high, 0.0]))
                         for low, high in GEOMETRY.stops))


@settings(max_examples=1000, deadline=None)
@given(joint_sets, st.tuples(*(st.sampled_from([-1, 1]) for _ in range(3))), st.one_of(st.none(), joint_sets),
       st.booleans())
def test_ik_is_ik_fast_then_wrap180_then_fit_to_stops(
    joints: tuple[float, ...], config: tuple[int, int, int], current: tuple[float, ...] | None, stops: bool
) -> None:
    """The fused path (issue 25) against the general one it replaced, angle for angle
    (singular wrists at JT5 = 0, joints at their stops and beyond, all eight configurations)."""
    pose = K.fk(list(joints))
    chosen = K.Config(*config)
    hint = math.radians(current[3]) if current is not None else 0.0
    try:
        radians = K.ik_fast(*pose.xyz.tolist(), pose.rotation.tolist(), *chosen, hint, GEOMETRY)
    except K.IKError as error:
        expected: object = ("refused", str(error))
    else:
        expected = wrapped_degrees(list(radians))
        if stops:
            expected = outcome(fit_to_stops, expected, current, GEOMETRY)
    try:
        got: object = K.ik(pose.xyz, pose.rotation, chosen, current, enforce_stops=stops)
    except BeyondStop as error:
        got = ("beyond", error.joint)
    except K.IKError as error:
        got = ("refused", str(error))
    assert got == expected


@settings(max_examples=500, deadline=None)
@given(turn)
def test_the_fast_wrap_is_wrap180(radians: float) -> None:
    degrees = math.degrees(radians + math.pi)  # ik_fast's widest: a wrist turned half a turn on
    assert K._wrap_turn(degrees) == wrap180(degrees)


def test_a_tie_between_two_equivalents_goes_to_the_lower_as_fit_to_stops_does() -> None:
    """JT4 and JT6 (stops +-266) at -100 or 100 degrees have a second equivalent inside; a
    current angle exactly half way between the two is a tie, which fit_to_stops breaks low."""
    for joint in (3, 5):
        for degrees in (-100.0, 100.0):
            radians = [0.0, -math.pi / 2, math.pi / 2, 0.0, 0.5, 0.0]
            radians[joint] = math.radians(degrees)
            angle = wrap180(math.degrees(radians[joint]))
            other = angle + 360.0 if angle < 0 else angle - 360.0
            current = [0.0, -90.0, 90.0, 0.0, 28.6, 0.0]
            current[joint] = (angle + other) / 2
            assert abs(angle - current[joint]) == abs(other - current[joint])      # a true tie
            fitted = K._fit_turns(radians, current, GEOMETRY.fit_bounds)
            assert fitted == fit_to_stops(wrapped_degrees(radians), current, GEOMETRY)
            assert fitted[joint] == min(angle, other)


def radians_giving(degrees: float) -> float:
    """A float whose degrees (as the fit turns them) are ``degrees`` exactly, where one is near."""
    radians = degrees / K._DEGREES
    for _ in range(4):
        if radians * K._DEGREES == degrees:
            break
        radians = math.nextafter(radians, math.inf if radians * K._DEGREES < degrees else -math.inf)
    return radians


def test_a_settled_angle_is_its_own_fit_and_the_edges_around_it_are_fit_as_before() -> None:
    """fit_bounds' settled range (an angle that needs no wrap, clamp or choice costs one
    comparison): at its edges, one float either side of them and where the range meets the
    stops, -180, 180 and +-94 (JT4, JT6), the fast fit gives what fit_to_stops gives."""
    edges = {-180.0, 180.0, -94.0, 94.0}
    for settled_low, settled_high, (_, _, low, high, _, _) in GEOMETRY.fit_bounds:
        assert low <= settled_low <= settled_high <= high
        assert -180.0 < settled_low <= settled_high <= 180.0
        edges |= {settled_low, settled_high, low, high, low + 360.0, high - 360.0}
    angles = {math.nextafter(edge, toward) for edge in edges for toward in (-math.inf, math.inf)} | edges
    for angle in sorted(angles):
        for joint in range(6):
            radians = [0.0, -math.pi / 2, math.pi / 2, 0.0, 0.5, 0.0]
            radians[joint] = radians_giving(angle)
            for current in (None, [0.0, -90.0, 90.0, 0.0, 28.6, 0.0], [150.0, -200.0, 200.0, -250.0, 90.0, 250.0]):
                expected = outcome(fit_to_stops, wrapped_degrees(radians), current, GEOMETRY)
                assert outcome(K._fit_turns, radians, current, GEOMETRY.fit_bounds) == expected


def test_ik_fast_refuses_a_coordinate_that_is_not_a_number() -> None:
    """The finite check lives in ik_fast (on the rows it unpacks): NaN and inf anywhere in the
    position or the rotation are refused there, before any arithmetic, as ik refused them."""
    pose = K.fk([10.0, -100.0, 120.0, 130.0, 40.0, -150.0])
    for bad in (math.nan, math.inf, -math.inf):
        for where in range(12):
            xyz, rotation = pose.xyz.tolist(), pose.rotation.tolist()
            if where < 3:
                xyz[where] = bad
            else:
                rotation[(where - 3) // 3][(where - 3) % 3] = bad
            with pytest.raises(K.OutOfReach, match="not a finite number"):
                K.ik_fast(*xyz, rotation, 1, 1, 1, 0.0, GEOMETRY)
            with pytest.raises(K.OutOfReach, match="not a finite number"):
                K.ik(np.array(xyz), np.array(rotation), K.Config(), None)
