"""Issue 36, item 5 (part): SCALE, NORM, INRANGE, CALLS, TIMER's special timers and read-only
timer 0, TYPE /S and small numbers, each against a value computed here independently (numpy,
the joint stops) rather than valterm's own output."""

from __future__ import annotations

import math

import numpy as np
import pytest

from test_vplus_lang import body, check_errors, completed, errors, typed, vplus
from valterm.core.arms import thesis_arm
from valterm.core.kinematics import Location, rotation_to_oat
from valterm.core.simulator import Simulator
from valterm.core.transform import Transform, normalized

# -- independent Z-Y-Z transformations (numpy) -------------------------------------------------


def _rz(deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _ry(deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _trans(x: float, y: float, z: float, yaw: float, pitch: float, roll: float) -> np.ndarray:
    matrix = np.eye(4)
    matrix[:3, :3] = _rz(yaw) @ _ry(pitch) @ _rz(roll)
    matrix[:3, 3] = (x, y, z)
    return matrix


def numbers(line: str) -> list[float]:
    return [float(word) for word in line.split()]


# -- SCALE --------------------------------------------------------------------------------------

def test_scale_multiplies_the_position_and_keeps_the_orientation() -> None:
    a, b = (100, 200, 300, 30, 40, 50), (-50, 25, 10, 10, 80, -120)
    _, events = vplus(body(f"SET a = TRANS{a}", f"SET b = TRANS{b}", "SET s = SCALE(a:b BY 2.5)",
                           "DECOMPOSE v[1] = s", "DECOMPOSE w[1] = a:b",
                           "TYPE /F12.6, v[1], v[2], v[3]", "TYPE /F12.6, v[4], v[5], v[6]",
                           "TYPE /F12.6, w[4], w[5], w[6]"))
    position, turned, unscaled = (numbers(line) for line in typed(events))
    expected = _trans(*a) @ _trans(*b)
    assert np.allclose(position, 2.5 * expected[:3, 3], atol=1e-5)
    assert np.allclose(turned, unscaled, atol=1e-5)  # the orientation is the compound's


def test_scale_of_the_references_kind_of_example() -> None:
    _, events = vplus(body("SET s = SCALE(TRANS(10, 20, 30, 0, 90, 0) BY -2)", "TYPE DX(s), DY(s), DZ(s)"))
    assert numbers(typed(events)[0]) == [-20, -40, -60]


# -- NORM -------------------------------------------------------------------------------------

def test_norm_of_a_transformation_is_the_same_transformation() -> None:
    _, events = vplus(body("SET a = TRANS(100, 200, 300, 30, 40, 50):RX(17):RY(-33)", "SET n = NORM(a)",
                           "TYPE /F12.6, DISTANCE(a, n)", "DECOMPOSE v[1] = INVERSE(a):n",
                           "TYPE /F10.6, v[1], v[2], v[3], v[4], v[5], v[6]"))
    assert numbers(typed(events)[0]) == [0.0]
    assert np.allclose(numbers(typed(events)[1]), 0.0, atol=1e-5)


def test_norm_makes_the_rotation_orthonormal_keeping_the_approach_and_position() -> None:
    rng = np.random.default_rng(36)
    for _ in range(20):
        matrix = _trans(*rng.uniform(-500, 500, 3), *rng.uniform(-180, 180, 3))
        skewed = matrix.copy()
        skewed[:3, :3] += rng.normal(0.0, 0.05, (3, 3))  # drift: no longer a rotation
        result = normalized(Transform(skewed)).matrix
        rotation = result[:3, :3]
        assert np.allclose(rotation.T @ rotation, np.eye(3), atol=1e-12)
        assert np.linalg.det(rotation) == pytest.approx(1.0)
        approach = skewed[:3, 2] / np.linalg.norm(skewed[:3, 2])
        assert np.allclose(rotation[:, 2], approach, atol=1e-12)  # a keeps its direction
        # o stays in the plane of the old o and a, on the same side
        plane = np.cross(skewed[:3, 1], skewed[:3, 2])
        assert abs(np.dot(rotation[:, 1], plane)) < 1e-9 and np.dot(rotation[:, 1], skewed[:3, 1]) > 0
        assert np.array_equal(result[:3, 3], skewed[:3, 3]) and np.array_equal(result[3], [0, 0, 0, 1])


# -- INRANGE ------------------------------------------------------------------------------------

STOPS = thesis_arm().stops


def _beyond(joints: tuple[float, ...]) -> int:
    """The bits INRANGE sets for these joints: joint n beyond its stop is bit n (value 2^(n-1))."""
    return sum(1 << index for index, (angle, (low, high)) in enumerate(zip(joints, STOPS))
               if not low <= angle <= high)


@pytest.mark.parametrize("joints", [
    (0.0, -120.0, 60.0, 10.0, 30.0, 20.0),   # inside every stop
    (10.0, -130.0, 80.0, 0.0, -60.0, 0.0),
    (0.0, -90.0, 90.0, 0.0, 120.0, 0.0),      # JT5 past its 100-degree stop
    (10.0, -130.0, 80.0, 0.0, -115.0, 0.0),   # likewise, the other way
    (0.0, -100.0, -60.0, 0.0, 30.0, 0.0),     # JT3 past its -45 stop
    (170.0, -120.0, 60.0, 0.0, 120.0, 0.0),   # JT1 and JT5 past theirs
])
def test_inrange_names_the_joints_beyond_their_stops(joints: tuple[float, ...]) -> None:
    arm, sim = thesis_arm(), Simulator(None)
    assert arm.indicators(list(joints)) == sim.config  # the configuration a motion would use
    pose = arm.fk(list(joints))  # the pose as a location of a .LOC file (the thesis's O A T):
    sim.locations["P"] = Location(tuple(float(v) for v in pose.xyz), rotation_to_oat(np.asarray(pose.rotation)))
    _, events = vplus(body("TYPE INRANGE(p)", "SET q = p", "TYPE INRANGE(q:TRANS(0, 0, 0))"), sim)
    assert [numbers(line) for line in typed(events)] == [[_beyond(joints)], [_beyond(joints)]]


def test_inrange_under_the_controller_rules_uses_the_configuration_asked_for() -> None:
    arm, sim = thesis_arm(), Simulator(None)
    sim.set_rules("controller")
    joints = (0.0, -90.0, 90.0, 0.0, 120.0, 0.0)  # RIGHTY,ABOVE,NOFLIP with JT5 past its stop
    pose = arm.fk(list(joints))
    sim.locations["P"] = Location(tuple(float(v) for v in pose.xyz), rotation_to_oat(np.asarray(pose.rotation)))
    _, events = vplus(body("RIGHTY", "ABOVE", "NOFLIP", "TYPE INRANGE(p)"), sim)
    assert numbers(typed(events)[0]) == [_beyond(joints)] == [16]


def test_inrange_of_a_location_out_of_reach() -> None:
    _, events = vplus(body("TYPE INRANGE(TRANS(5000, 0, 0, 0, 180, 0))", "TYPE INRANGE(HERE)"))
    far, here = (numbers(line)[0] for line in typed(events))
    assert far == -1  # not reachable at all: no joint values
    assert here == 0


# -- CALLS --------------------------------------------------------------------------------------

def test_calls_calls_the_program_a_string_names() -> None:
    text = body('$p = "show"', 'CALLS $p("Mixed Case", 2)', 'CALLS "SH" + "OW"("again", 3)', "x = 5",
                '$q = "twice"', "CALLS $q(x)", "TYPE x") + (
        ".PROGRAM show($t, n)\n    TYPE $t, n\n.END\n.PROGRAM twice(v)\n    v = 2*v\n.END\n")
    _, events = vplus(text)
    assert typed(events) == ["Mixed Case2", "again3", "10"] and completed(events)


def test_calls_of_a_string_naming_no_program_stops() -> None:
    _, events = vplus(body('$p = "no such"', "CALLS $p", 'TYPE "AFTER"'))
    assert typed(events) == [] and errors(events)[0].step == 2 and "NO SUCH" in errors(events)[0].message.upper()


# -- TIMER ------------------------------------------------------------------------------------

def test_timer_minus_one_counts_ticks_and_minus_two_milliseconds() -> None:
    _, events = vplus(body("a = TIMER(-2)", "t = TIMER(-1)", "DELAY 1.5", "TYPE TIMER(-2)-a, TIMER(-1)-t, TPS()",
                           "TYPE TIMER(0)"))
    milliseconds, ticks, per_second = numbers(typed(events)[0])
    assert milliseconds == pytest.approx(1500, abs=1)
    assert per_second == 62.5 and ticks == pytest.approx(1.5 * per_second, abs=1)
    assert numbers(typed(events)[1])[0] == pytest.approx(1.5)


def test_timer_zero_is_read_only() -> None:
    assert any("TIMER 0" in e for e in check_errors(body("TIMER 0 = 5")))
    _, events = vplus(body("n = 0", "TIMER n = 5", 'TYPE "AFTER"'))
    assert typed(events) == [] and "TIMER 0" in errors(events)[0].message
    _, events = vplus(body("TIMER 3 = 5", "TYPE TIMER(3)"))
    assert numbers(typed(events)[0]) == [5.0]


# -- TYPE /S and small numbers ------------------------------------------------------------------

def test_type_s_suppresses_the_line_end() -> None:
    _, events = vplus(body('TYPE "a", /S', 'TYPE "b", 2', 'TYPE /S, "p"', 'TYPE "q", /S', 'TYPE "r"',
                           'TYPE "last", /S'))
    assert typed(events) == ["ab2", "pqr", "last"]  # what is left at the end is not lost


def test_small_numbers_are_typed() -> None:
    _, events = vplus(body("TYPE 1E-10", "TYPE -2.5E-7, 3E-12", "TYPE COS(90), SIN(180), TAN(-180), COS(-270)",
                           "TYPE DX(RZ(90):TRANS(100, 0, 0))"))
    # what is left as 0: rounding noise of millimetre-sized arithmetic (below 1e-12)
    assert [numbers(line) for line in typed(events)] == [[1e-10], [-2.5e-7, 3e-12], [0, 0, 0, 0], [0]]
