"""valterm.testing: the example in docs/TESTING.md runs as written, and the parts it reads."""

from __future__ import annotations

import asyncio
import re
from pathlib import Path

import numpy as np

from valterm.core.cycletime import joint_motion_seconds

from valterm.testing import ScriptClock, Simulation

DOC = Path(__file__).resolve().parent.parent / "docs" / "TESTING.md"
README = Path(__file__).resolve().parent.parent / "README.md"


def test_the_documented_example_runs_as_written(capsys) -> None:  # type: ignore[no-untyped-def]
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(encoding="utf-8"), flags=re.DOTALL)
    assert blocks, "docs/TESTING.md has no python example"
    exec(compile(blocks[0], str(DOC), "exec"), {"__name__": "__main__"})  # our own doc's example, run as a reader would
    printed = capsys.readouterr().out
    assert "JT 1" in printed and "8.00" in printed  # the Fig. 2-8 readout after joint 1 turned


def test_the_readme_example_runs_as_written(capsys) -> None:  # type: ignore[no-untyped-def]
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), flags=re.DOTALL)
    assert blocks, "README.md has no python example"
    exec(compile(blocks[0], str(README), "exec"), {"__name__": "__main__"})  # our own doc's example, run as a reader would
    printed = capsys.readouterr().out
    assert ". WHERE" in printed and "JT 1" in printed  # the screen's rows, VAL-II mode's WHERE


def test_rows_are_the_terminal_and_the_start_screen_works(tmp_path: Path) -> None:
    async def body() -> None:
        async with Simulation(tmp_path, setup=None, size=(80, 24)) as sim:
            rows = sim.rows()
            assert len(rows) == 24 and all(len(row) <= 80 for row in rows)
            assert any("C COPYRIGHT Lehigh University, 1985." in row for row in rows)
            await sim.press("E")
            assert sim.prompt() == "ENTER SET-UP FILE NAME (RETURN: PROCESS):"
            await sim.press("enter")
            assert "MAIN MENU" in sim.text() and sim.prompt() == ""

    asyncio.run(body())


def test_the_script_clock_paces_motions(tmp_path: Path) -> None:
    async def body() -> None:
        async with Simulation(tmp_path, size=(120, 40), animate=True, rate=10.0) as sim:
            await sim.press("P")
            # five steps of 12 degrees, played in the real PUMA's time for them (cycle time)
            seconds = joint_motion_seconds(np.zeros(6), np.array([60.0, 0, 0, 0, 0, 0]), 100.0)
            sim.app.run_events(sim.simulator.drive(1, 60.0))
            await sim.pilot.pause()
            assert sim.moving and round(sim.where().joints[0]) == 12
            await sim.advance(seconds * 2.2 / 5)  # a little past the third step's time
            assert round(sim.where().joints[0]) == 36
            await sim.settle()
            assert not sim.moving and round(sim.where().joints[0]) == 60

    asyncio.run(body())


def test_script_clock_moves_only_when_told() -> None:
    clock = ScriptClock(5.0)
    assert clock() == 5.0 == clock()
    clock.advance(1.5)
    assert clock() == 6.5
