"""Issue 39 item 2: Fig. C-12 a-d, the pendant with collision checks on, typed as Tables
C-1 and C-2 type it (assets/DEMO.KEYS, the thesis's keys: valterm --keys 1985).

The seed prints the figures' lines (OCR text, read as printed: no slips in them):

    a  CLAMP IS NEAR PART 10
    b  CLAMP IS NEAR PART 10 / 10 COLLIDES WITH 7 / 10 COLLIDES WITH 6
    c  CLAMP IS NEAR PART 10 / 10 COLLIDES WITH 6 / PART 10 IS NEAR PART 5 / 10 COLLIDES WITH 5
    d  CLAMP IS NEAR PART 10 / 10 COLLIDES WITH 6 / 10 COLLIDES WITH 7 /
       PART 10 IS NEAR PART 5 / 10 COLLIDES WITH 5

Table C-2 names the figures on the rows `3` (a), `3` (b), `2` (c) and `N` (d); N moves
nothing and d's lines are not c's, so d is the screen after N and the next row's `3`.
The 1985 screen numbers the robot's bodies base to fingers (WRIST 5, CLAMP 6, FINGER 7):
docs/MOTION.md, "Fig. C-12".
"""

from __future__ import annotations

import asyncio
from pathlib import Path

from valterm.core.files.demokeys import load_demo
from valterm.core.simulator import Simulator
from valterm.testing import Simulation
from valterm.ui.screens.pendant import PendantScreen

FIGURE = {
    "a": ["CLAMP IS NEAR PART 10"],
    "b": ["CLAMP IS NEAR PART 10", "10 COLLIDES WITH 7", "10 COLLIDES WITH 6"],
    "c": ["CLAMP IS NEAR PART 10", "10 COLLIDES WITH 6", "PART 10 IS NEAR PART 5", "10 COLLIDES WITH 5"],
    "d": ["CLAMP IS NEAR PART 10", "10 COLLIDES WITH 6", "10 COLLIDES WITH 7",
          "PART 10 IS NEAR PART 5", "10 COLLIDES WITH 5"],
}
# the lines valterm's DEMO3 adds (docs/MOTION.md, "Fig. C-12": the forearm, 4, reaches part 10
# on the moves of c and d, and the fingers, 7, start c inside it)
EXTRA = {"c": ["10 COLLIDES WITH 7", "PART 10 IS NEAR PART 4"],
         "d": ["PART 10 IS NEAR PART 4", "10 COLLIDES WITH 4"]}
# after I,I,I (Table C-2 prints "1,1,1": an OCR slip), the keys each figure follows
AFTER = {"a": ("3",), "b": ("3",), "c": ("2",), "d": ("n", "3")}


def _keys_to_fig_c12() -> list[str]:
    """Tables C-1 and C-2 as DEMO.KEYS types them, up to the row that raises the increment."""
    keys: list[str] = []
    typed: list[str] = []
    for item in load_demo():
        if item.kind in ("key", "text"):
            keys += item.keys()
            typed.append(item.value)
        if typed[-3:] == ["I", "I", "I"]:
            return keys
    raise AssertionError("DEMO.KEYS has no I,I,I row (Table C-2)")


def _findings(lines: list[str]) -> list[str]:
    return [line for line in lines if " COLLIDES WITH " in line or " IS NEAR " in line]


def test_table_c2_shows_fig_c12_a_to_d(tmp_path: Path) -> None:
    shown: dict[str, list[str]] = {}
    refused: list[str] = []

    async def body() -> None:
        async with Simulation(tmp_path / "ws", None, size=(140, 48), keys="1985") as sim:
            for key in _keys_to_fig_c12():
                await sim.press(key)
                if isinstance(sim.screen, PendantScreen):
                    refused.extend(line for line in sim.messages() if "REFUSED" in line)
            assert isinstance(sim.screen, PendantScreen) and sim.simulator.collision_checks
            assert sim.simulator.pendant_increment == 32.0  # 8 + 8 + 8 + 8 (docs/MOTION.md)
            for figure, keys in AFTER.items():
                await sim.press(*keys)
                shown[figure] = _findings(sim.messages())
                refused.extend(line for line in sim.messages() if "REFUSED" in line)

    asyncio.run(body())
    assert not refused, refused
    for figure, printed in FIGURE.items():
        lines = shown[figure]
        assert set(printed) <= set(lines), (figure, lines)  # every line the figure prints
        # in the printed order (b prints 7 before 6, d 6 before 7: one order cannot give
        # both, d's is kept) ...
        order = printed if figure != "b" else [printed[0], printed[2], printed[1]]
        assert [line for line in lines if line in printed] == order, (figure, lines)
        # ... and no other line but those docs/MOTION.md lists
        assert [line for line in lines if line not in printed] == EXTRA.get(figure, []), (figure, lines)


def test_i_adds_eight_degrees_under_the_1985_rules_and_doubles_under_the_controllers() -> None:
    thesis, controller = Simulator(), Simulator()
    controller.set_rules("controller")
    assert [thesis.change_pendant_increment(k) for k in "IIINDD"] == [16, 24, 32, -32, -24, -16]
    assert [thesis.change_pendant_increment(k) for k in "DD"] == [-8, -4]  # halves below 16
    assert [controller.change_pendant_increment(k) for k in "IIIND"] == [16, 32, 64, -64, -32]


def test_the_1985_words_number_the_robots_bodies_and_leave_the_rest() -> None:
    from valterm.core.collision.world import Finding, bodies, figure_order
    from valterm.core.text.transcript import figure_lines

    names = Simulator().model.names
    numbers = {body: n for n, body in enumerate(bodies(names), start=1)}
    assert numbers == {"BASE": 1, "WAIST": 2, "UPPER ARM": 3, "FOREARM": 4, "WRIST": 5, "CLAMP": 6, "FINGER": 7}
    words = {f: figure_lines(f.event(), numbers) for f in (
        Finding("near", "FINGER", 10), Finding("collides", "CLAMP", 10), Finding("near", "WRIST", 10),
        Finding("collides", "WRIST", 10), Finding("collides", 1, 13), Finding("collides", "CLAMP", "BASE"))}
    assert list(words.values()) == [
        ["CLAMP IS NEAR PART 10"], ["CLAMP IS NEAR PART 10", "10 COLLIDES WITH 6"],
        ["PART 10 IS NEAR PART 5"], ["PART 10 IS NEAR PART 5", "10 COLLIDES WITH 5"],
        ["1 COLLIDES WITH 13"], ["CLAMP COLLIDES WITH BASE"]]  # a carried part, the arm itself: as always
    found = [Finding("collides", "WRIST", 10), Finding("collides", 1, 13), Finding("near", "WRIST", 10),
             Finding("collides", "FINGER", 10), Finding("near", "CLAMP", 10)]
    assert [(f.kind, f.a) for f in figure_order(found, names)] == [
        ("near", "CLAMP"), ("collides", "FINGER"), ("near", "WRIST"), ("collides", "WRIST"), ("collides", 1)]
