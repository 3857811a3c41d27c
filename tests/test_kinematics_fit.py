"""ik's stop fit (issue 25: three candidates a joint) gives what fit_to_stops gives, and its
angle wrap what wrap180 gives, on any angles ik_fast can return."""

from __future__ import annotations

import math

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


@settings(max_examples=500, deadline=None)
@given(st.lists(wrapped, min_size=6, max_size=6),
       st.one_of(st.none(), st.lists(st.floats(min_value=-300, max_value=300), min_size=6, max_size=6)))
def test_the_fast_fit_is_fit_to_stops(angles: list[float], current: list[float] | None) -> None:
    assert outcome(K._fit_wrapped, angles, current, GEOMETRY.stops) == outcome(fit_to_stops, angles, current, GEOMETRY)


@settings(max_examples=500, deadline=None)
@given(turn)
def test_the_fast_wrap_is_wrap180(radians: float) -> None:
    degrees = math.degrees(radians + math.pi)  # ik_fast's widest: a wrist turned half a turn on
    assert K._wrap_turn(degrees) == wrap180(degrees)
