"""Issue 35, item 2: every finding of a motion is in view (the pendant's 64-degree JT2 move
into PROCESS's parts), the picture marks the colliding bodies, and a refusal goes with the
next good move."""

from __future__ import annotations

import re

import asyncio
import json
from pathlib import Path

import numpy as np
import pytest

from valterm.cli import main
from valterm.core.events import Collision, Near
from valterm.core.render.legend import HIGHLIGHT_COLOUR
from valterm.core.session import Session
from valterm.core.text.transcript import finding_line
from valterm.testing import Simulation
from valterm.ui.screens.pendant import PendantScreen

# increment 8: JT5 +16; then JT3 +16, +32, +64 (I doubles it: the controller rules; under the
# 1985 rules I adds 8, tests/test_fig_c12.py); then JT2 +64 into parts 2, 8, 11
RULES = "controller"  # collisions before near misses (the 1985 rules interleave them as Fig. C-12)
KEYS_BEFORE = ("5", "5", "I", "3", "I", "3", "I", "3")
MOVE = "2"


def run(coro) -> None:  # type: ignore[no-untyped-def]
    asyncio.run(coro)


def _core_findings(workspace: Path) -> tuple[list[str], list[str]]:
    """The last motion's COLLIDES and NEAR lines, from the core alone (the same keys)."""
    simulator = Session(workspace, "PROCESS").simulator
    simulator.set_rules(RULES)
    simulator.collision_checks = True
    for key in KEYS_BEFORE:
        if key == "I":
            simulator.change_pendant_increment(key)
        else:
            list(simulator.pendant_joint(int(key)))
    events = list(simulator.pendant_joint(int(MOVE)))
    collides = [finding_line(e) for e in events if isinstance(e, Collision)]
    near = [finding_line(e) for e in events if isinstance(e, Near)]
    return collides, near


def _run_collides(workspace: Path, capsys: pytest.CaptureFixture[str]) -> set[str]:
    """The COLLIDES findings `valterm run --collisions` reports for the same move (DRIVEs)."""
    program = workspace / "JT2.DAT"
    program.write_text("    DRIVE 5,16,100\n    DRIVE 3,112,100\n    DRIVE 2,64,100\n    STOP\n")
    capsys.readouterr()
    assert main(["--workspace", str(workspace), "run", "--collisions", "--json", "--rules", RULES,
                 "--cell", "PROCESS", str(program)]) == 0
    events = [json.loads(line) for line in capsys.readouterr().out.splitlines() if line.startswith("{")]
    return {e["text"] for e in events if e.get("event") == "collision" and e.get("step") == 3}


async def _to_pendant_with_checks(sim: Simulation) -> None:
    await sim.press("K", "S", "R", "P")
    assert isinstance(sim.screen, PendantScreen)
    assert sim.simulator.collision_checks


def _row_of(rows: list[str], line: str) -> int:
    found = [i for i, row in enumerate(rows) if row.strip().startswith(line)]
    assert found, f"{line!r} is not on the screen:\n" + "\n".join(rows)
    return found[0]


def test_the_pendant_shows_every_finding_of_the_jt2_move(tmp_path: Path,
                                                          capsys: pytest.CaptureFixture[str]) -> None:
    collides, near = _core_findings(tmp_path)
    assert len(collides) >= 6 and len(near) >= 3  # the move is the one the issue saw
    assert set(collides) == _run_collides(tmp_path, capsys)  # the run path says the same

    async def body() -> None:
        async with Simulation(tmp_path, size=(120, 40), rules=RULES) as sim:
            await _to_pendant_with_checks(sim)
            await sim.press(*KEYS_BEFORE)
            await sim.press(MOVE)
            rows = sim.rows()
            count = _row_of(rows, f"{len(collides)} COLLISIONS, {len(near)} NEAR")
            collide_rows = [_row_of(rows, line) for line in collides]
            near_rows = [_row_of(rows, line) for line in near]
            assert count < min(collide_rows)
            assert max(collide_rows) < min(near_rows)  # collisions before near misses
            assert collide_rows == sorted(collide_rows)  # in the order found

    run(body())


def test_at_80x24_the_collisions_are_in_view_and_the_rest_a_key_away(tmp_path: Path) -> None:
    collides, near = _core_findings(tmp_path)

    async def body() -> None:
        async with Simulation(tmp_path, size=(80, 24), rules=RULES) as sim:
            await _to_pendant_with_checks(sim)
            await sim.press(*KEYS_BEFORE)
            await sim.press(MOVE)
            rows = sim.rows()
            count = _row_of(rows, f"{len(collides)} COLLISIONS, {len(near)} NEAR")
            assert "SHIFT-UP/SHIFT-DOWN: SCROLL" in rows[count]  # the keys that scroll them
            for line in collides:
                _row_of(rows, line)
            sim.app.set_keymap({"menu.messages_on": "ctrl+down"})  # the user's keymap file
            await sim.press("N", MOVE, "N", MOVE)  # back, and into the parts again
            assert sim.rows()[count].strip() == f"{len(collides)} COLLISIONS, {len(near)} NEAR   SHIFT-UP/CTRL-DOWN: SCROLL THE MESSAGES"
            await sim.press("ctrl+down")
            rows = sim.rows()
            for line in near:  # scrolled on: the near misses are in view
                _row_of(rows, line)

    run(body())


def test_the_picture_marks_the_colliding_bodies(tmp_path: Path) -> None:
    async def body() -> None:
        async with Simulation(tmp_path, size=(120, 40), rules=RULES) as sim:
            await _to_pendant_with_checks(sim)
            await sim.press(*KEYS_BEFORE)
            view = sim.screen.model_view
            assert not np.any(view.frame.colours == HIGHLIGHT_COLOUR)  # nothing collides yet
            await sim.press(MOVE)
            assert np.any(sim.screen.model_view.frame.colours == HIGHLIGHT_COLOUR)
            # the bodies marked are those the move's collisions name (parts by number)
            collides, _ = _core_findings(tmp_path)
            named = {word for line in collides for word in line.split(" COLLIDES WITH ")}
            assert sim.app.player.collided == named

    run(body())


def test_a_refusal_and_its_hint_go_with_the_next_good_move(tmp_path: Path) -> None:
    async def body() -> None:
        async with Simulation(tmp_path, size=(80, 24), rules=RULES) as sim:
            await sim.press("P", "W", "X")  # WORLD X at READY: refused, with what to do
            assert any(line.startswith("MOTION REFUSED") for line in sim.messages()), sim.messages()
            assert any(line.startswith("HINT") for line in sim.messages()), sim.messages()
            await sim.press("1")  # a good move that says nothing
            assert sim.where().joints[0] == pytest.approx(8.0)
            shown = "\n".join(sim.rows())
            assert "REFUSED" not in shown and "HINT" not in shown, shown
            await sim.press("I", "I", "I", "3", "3", "3")  # JT3 90 -> 154 -> 218 -> beyond its stop
            assert any("BEYOND ITS STOP" in line for line in sim.messages()), sim.messages()
            await sim.press("2")
            assert "BEYOND ITS STOP" not in "\n".join(sim.rows())

    run(body())


def _step_findings(workspace: Path, before: tuple[float, ...], increment: float, joint: int) -> set[str]:
    """Every finding of one pendant step from ``before``, by a simulator that said none yet
    (the app's says each once, as it starts)."""
    simulator = Session(workspace, "PROCESS").simulator
    simulator.set_rules(RULES)
    simulator.collision_checks = True
    simulator.stand_at(before)
    simulator.pendant_increment = increment
    return {finding_line(e) for e in simulator.pendant_joint(joint) if isinstance(e, (Near, Collision))}


def _shown_findings(sim: Simulation) -> set[str]:
    return {line for line in sim.messages() if " COLLIDES WITH " in line or " IS NEAR " in line}


def test_a_move_that_stays_in_collision_still_lists_its_collisions(tmp_path: Path) -> None:
    async def body() -> None:
        async with Simulation(tmp_path, size=(120, 40), rules=RULES) as sim:
            await _to_pendant_with_checks(sim)
            await sim.press(*KEYS_BEFORE, MOVE, "D", "D", "D")
            before = tuple(sim.where().joints)
            await sim.press("6")  # 8 degrees of the clamp, still in the parts: the core says none again
            expected = _step_findings(tmp_path, before, 8.0, 6)
            collides = {line for line in expected if " COLLIDES WITH " in line}
            assert len(collides) >= 4
            assert _shown_findings(sim) == expected
            _row_of(sim.rows(), f"{len(collides)} COLLISIONS, {len(expected) - len(collides)} NEAR")
            assert np.any(sim.screen.model_view.frame.colours == HIGHLIGHT_COLOUR)

    run(body())


def test_a_move_out_of_the_parts_clears_their_findings(tmp_path: Path) -> None:
    async def body() -> None:
        async with Simulation(tmp_path, size=(120, 40), rules=RULES) as sim:
            await _to_pendant_with_checks(sim)
            await sim.press(*KEYS_BEFORE, MOVE, "N", "2")  # back up through the parts
            before = tuple(sim.where().joints)
            await sim.press("2")  # on, away from them
            expected = _step_findings(tmp_path, before, -64.0, 2)
            assert not any(" COLLIDES WITH " in line for line in expected)
            assert _shown_findings(sim) == expected
            assert "COLLIDES" not in "\n".join(sim.rows())
            assert not np.any(sim.screen.model_view.frame.colours == HIGHLIGHT_COLOUR)

    run(body())


def test_the_keyboard_shows_every_finding_of_a_typed_drive(tmp_path: Path,
                                                          capsys: pytest.CaptureFixture[str]) -> None:
    expected = _run_collides(tmp_path, capsys)  # DRIVE 5,16 / DRIVE 3,112 / DRIVE 2,64 through `run`

    async def body() -> None:
        async with Simulation(tmp_path, size=(80, 24), rules=RULES) as sim:  # the collisions fit even here
            await sim.press("K", "S")
            assert sim.simulator.collision_checks
            for command in ("DRIVE 5,16,100", "DRIVE 3,112,100", "DRIVE 2,64,100"):
                await sim.press("V")
                await sim.type(command, enter=True)
            rows = sim.rows()
            shown = {line for line in sim.messages() if " COLLIDES WITH " in line}
            assert expected <= shown
            near = [line for line in sim.messages() if " IS NEAR " in line]
            count = _row_of(rows, f"{len(shown)} COLLISIONS, {len(near)} NEAR")
            assert count < min(_row_of(rows, line) for line in shown)  # in view, under the count
            lines = sim.messages()  # the area's lines, those scrolled out of view too
            assert max(lines.index(line) for line in shown) < min(lines.index(line) for line in near)

    run(body())


def test_help_names_the_keys_that_scroll_the_messages(tmp_path: Path) -> None:
    async def body() -> None:
        async with Simulation(tmp_path, size=(120, 40), rules=RULES) as sim:
            await sim.press("P", "question_mark")
            assert re.search(r"SHIFT-UP +BACK A PAGE IN THE MESSAGES", sim.text())
            assert re.search(r"SHIFT-DOWN +ON A PAGE IN THE MESSAGES", sim.text())

    run(body())
