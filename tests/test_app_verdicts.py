"""Issue 22 in the app, keys pressed and the screen read back: CONV1 runs to its end, a location
taught LEFTY is refused after READY (1985 rules) naming both, STATUS and the status line name the
rules, D_DEFINE's S stores the locations, and quitting with taught locations asks."""

from __future__ import annotations

from pathlib import Path

from valterm.core.files.locations import read_locations
from valterm.core.kinematics import Config
from valterm.testing import Simulation


async def to_val_line(sim: Simulation) -> None:
    await sim.press("escape", "escape", "V", "V")  # MAIN, VAL-II mode, its command line


async def test_conv1_with_conv2_completes_in_the_app(tmp_path: Path) -> None:
    async with Simulation(tmp_path, setup="CONV", size=(160, 50)) as sim:
        sim.session.load_locations("CONV")
        await to_val_line(sim)
        await sim.type("EXEC CONV1", enter=True)
        await sim.settle()
        transcript = sim.transcript()
        assert "PROGRAM CONV1 COMPLETED: 1 LOOP" in transcript, transcript[-12:]
        assert [line for line in transcript if line.startswith(("COL =", "ROW ="))] == \
            ["COL = 2", "ROW = 3", "COL = 3", "ROW = 3", "COL = 3"]
        assert not [line for line in transcript if line.startswith("***")]
        assert "RULES 1985" in sim.status()


async def test_a_location_taught_lefty_is_refused_after_ready_naming_both(tmp_path: Path) -> None:
    async with Simulation(tmp_path, setup="PROCESS", size=(80, 24)) as sim:
        await to_val_line(sim)
        for line in ("LEFTY", "DRIVE 2,60,100", "HERE P2", "READY", "APPRO P2, 80", "STATUS"):
            await sim.type(line, enter=True)
            await sim.settle()
        assert sim.simulator.location("P2").config == Config(-1, 1, 1)
        text = " ".join(sim.transcript())
        assert "READY: CONFIGURATION INDICATORS LEFTY TO RIGHTY" in text
        assert "ARM CONFIGURATION CHANGED: LEFTY TO RIGHTY" in text  # READY, said
        assert ("CONFIGURATION MISMATCH: P2 WAS TAUGHT LEFTY ABOVE NOFLIP, THE INDICATORS ARE RIGHTY ABOVE NOFLIP"
                " (TYPE LEFTY, OR TEACH P2 AGAIN)") in text
        assert "RULES 1985 (THE THESIS" in text
        assert sim.where().config["arm"] == "RIGHTY"  # nothing moved


async def test_define_s_stores_the_locations_and_quit_asks_only_before(tmp_path: Path) -> None:
    async with Simulation(tmp_path, setup="PROCESS", size=(80, 24)) as sim:
        await to_val_line(sim)
        await sim.type("HERE P1", enter=True)
        await sim.settle()
        await sim.press("ctrl+q")
        assert "1 LOCATION (P1): STOREL NAME SAVES THEM" in sim.text()
        await sim.press("n")
        await sim.press("escape", "D", "S")  # the VAL-II menu, D_DEFINE, S_STORE
        await sim.type("KEPT", enter=True)
        await sim.settle()
        assert "1 LOCATION STORED IN KEPT.LOC" in sim.transcript()
        assert read_locations(tmp_path / "KEPT.LOC")["P1"].config == Config(1, 1, 1)
        assert sim.simulator.unsaved_locations() == []
        await sim.press("ctrl+q")
        assert "NOT SAVED" not in sim.text()
        assert sim.app.return_code == 0 or not sim.app.is_running


async def test_storel_over_the_thesis_file_is_refused_on_the_val_ii_screen_then_replaced(tmp_path: Path) -> None:
    """Issue 35: STOREL PROCESS in a fresh session keeps the thesis's PROCESS.LOC and says how to
    replace it; the same STOREL again replaces it; another session's store since is told."""
    async with Simulation(tmp_path, setup="PROCESS", size=(80, 24)) as sim:
        thesis = (tmp_path / "PROCESS.LOC").read_bytes()
        await to_val_line(sim)
        for line in ("STOREL PROCESS", "HERE P1", "STOREL PROCESS"):
            await sim.type(line, enter=True)
            await sim.settle()
        text = " ".join(sim.transcript())
        assert "NO LOCATIONS ARE DEFINED: PROCESS.LOC (6 LOCATIONS) IS KEPT AS IT IS" in text
        assert ("PROCESS.LOC (6 LOCATIONS) WAS NOT STORED BY THIS SESSION: NOTHING WRITTEN. "
                "STOREL PROCESS AGAIN REPLACES IT") in text
        assert (tmp_path / "PROCESS.LOC").read_bytes() == thesis
        await sim.type("STOREL PROCESS", enter=True)
        await sim.settle()
        assert sim.transcript()[-1] == "1 LOCATION STORED IN PROCESS.LOC"
        assert list(read_locations(tmp_path / "PROCESS.LOC")) == ["P1"]
        (tmp_path / "PROCESS.LOC").write_text("POINT Q, 1, 2, 3, 4, 5, 6\n")  # another session stores
        await sim.type("STOREL PROCESS", enter=True)
        await sim.settle()
        assert "PROCESS.LOC CHANGED ON DISK SINCE THIS SESSION LAST SAW IT" in " ".join(sim.transcript()[-3:])
        assert list(read_locations(tmp_path / "PROCESS.LOC")) == ["Q"]
        await sim.type("LOAD PROCESS.LOC", enter=True)
        await sim.settle()
        assert "1 LOCATION READ FROM PROCESS.LOC: Q" in sim.transcript()
