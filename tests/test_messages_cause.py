"""Issue 35 item 3: a refusal names its real cause in the user's terms. A location taught in
another configuration says CONFIGURATION MISMATCH and names both (no garbled ``LOCATION THE
LOCATION``), in the core and where D_DEFINE reads a file; a joint beyond its stop on a WORLD/TOOL
step gives the angle the joint would need in the convention the screen shows, and the pendant's
hint is one that is true for the refusal."""

from __future__ import annotations

from pathlib import Path

import pytest

from valterm.core.files.locations import format_locations
from valterm.core.kinematics import Config
from valterm.core.simulator import ConfigMismatch, Simulator
from valterm.testing import Simulation

MISMATCH = ("CONFIGURATION MISMATCH: P1 WAS TAUGHT LEFTY ABOVE NOFLIP, THE INDICATORS ARE "
            "RIGHTY ABOVE NOFLIP (TYPE LEFTY, OR TEACH P1 AGAIN)")


def drain(events) -> list:  # type: ignore[no-untyped-def]
    return list(events)


def lefty_p1() -> tuple[Simulator, object]:
    """A location P1 taught LEFTY (joint 2 driven 60 degrees), then READY: the indicators are RIGHTY."""
    sim = Simulator()
    sim.set_indicator("LEFTY")
    drain(sim.drive(2, 60))
    taught = sim.here("P1")
    drain(sim.ready())
    assert taught.config == Config(-1, 1, 1) and sim.config == Config(1, 1, 1)
    return sim, taught


def test_a_mismatch_names_the_location_and_both_configurations() -> None:
    sim, taught = lefty_p1()
    with pytest.raises(ConfigMismatch) as by_name:
        drain(sim.move("P1"))
    assert str(by_name.value).upper() == MISMATCH
    with pytest.raises(ConfigMismatch) as by_value:  # a location read from a file, named by its caller
        drain(sim.move(taught, name="P1"))  # type: ignore[arg-type]
    assert str(by_value.value).upper() == MISMATCH
    with pytest.raises(ConfigMismatch) as unnamed:  # a computed location has no name
        drain(sim.appro(taught, 50))  # type: ignore[arg-type]
    assert str(unnamed.value).upper().startswith("CONFIGURATION MISMATCH: THE LOCATION WAS TAUGHT LEFTY ABOVE NOFLIP,")
    assert "TEACH IT AGAIN" in str(unnamed.value).upper() and "THE LOCATION IS" not in str(unnamed.value).upper()


async def test_d_define_reading_a_file_says_mismatch_not_cannot_reach(tmp_path: Path) -> None:
    _, taught = lefty_p1()
    (tmp_path / "PTS.LOC").write_text(format_locations({"P1": taught}))  # type: ignore[dict-item]
    async with Simulation(tmp_path, setup="PROCESS", size=(120, 40)) as sim:
        await sim.press("V")  # the VAL-II menu
        await sim.press("ctrl+t", "d")  # D_DEFINE, from a data file
        await sim.type("PTS.LOC", enter=True)
        await sim.settle()
        transcript = sim.transcript()
        text = " ".join(transcript)
        assert "CANNOT REACH" not in text and "LOCATION THE LOCATION" not in text, transcript[-6:]
        assert "*** " + MISMATCH in transcript, transcript[-6:]
        assert "P1: A_ACCEPT AND CONTINUE" in sim.text()  # the question goes on: R rejects it
