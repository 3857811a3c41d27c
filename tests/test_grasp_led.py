"""The LED sensor: the lowest-numbered object it meets latches; nothing when it misses."""

from __future__ import annotations

import numpy as np

from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.collision.grasp import led_hits


def box(lo, hi) -> Polyhedron:
    return Polyhedron.box(np.array(lo, float), np.array(hi, float))


LED = (np.array([-10.0, 0, 50]), np.array([10.0, 0, 50]))   # across between the fingers


def test_led_through_a_part():
    part = box([-5, -15, 0], [5, 15, 70])                     # thinner than the LED is long
    assert led_hits(*LED, [box([300, 0, 0], [310, 10, 10]), part]) == 2


def test_led_wholly_inside_a_part_between_the_fingers():
    part = box([-25, -15, 0], [25, 15, 70])                   # contains the short LED segment
    assert led_hits(*LED, [part]) == 1


def test_lowest_numbered_object_wins():
    part = box([-5, -15, 0], [5, 15, 70])
    other = box([-25, -30, 40], [25, 30, 60])                 # also met by the LED
    assert led_hits(*LED, [box([300, 0, 0], [310, 10, 10]), other, part]) == 2
    assert led_hits(*LED, [part, other]) == 1


def test_no_latch_when_the_led_misses():
    below = box([-25, -15, 0], [25, 15, 45])                  # 5 mm under the LED
    aside = box([20, -5, 40], [40, 5, 60])                    # beyond the LED's end
    assert led_hits(*LED, [below, aside]) is None
    assert led_hits(*LED, []) is None
