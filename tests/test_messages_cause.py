"""Issue 35 item 3: a refusal names its real cause in the user's terms. A location taught in
another configuration says CONFIGURATION MISMATCH and names both (no garbled ``LOCATION THE
LOCATION``), in the core and where D_DEFINE reads a file; a joint beyond its stop on a WORLD/TOOL
step gives the angle the joint would need in the convention the screen shows, and the pendant's
hint is one that is true for the refusal."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from valterm.core.files.locations import format_locations
from valterm.core.errors import MotionRefused
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


# -- a joint beyond its stop on a WORLD/TOOL step (1985 rules) ----------------------------------
# JT3 held at 223.60 (the readout shows its (-180, 180] equivalent -136.40, SPEC §3a):
# a 24-degree (30 mm) TOOL X step would carry it past 225.
NEAR_JT3_STOP = [-136.95, -31.19, 223.6, 33.55, -19.15, -118.67]
STOP_ANGLE = re.compile(r"JOINT 3 BEYOND ITS STOP \((-?\d+\.\d+) DEG(?:, SHOWN AS (-?\d+\.\d+))?, STOP -45\.\.225\)")


def near_the_stop() -> Simulator:
    sim = Simulator()
    sim.stand_at(NEAR_JT3_STOP)
    sim.change_pendant_increment("I")
    sim.change_pendant_increment("I")  # 24 degrees, 30 mm (the 1985 rules: I adds 8)
    return sim


def test_a_tool_step_past_a_stop_gives_the_angle_the_joint_would_need() -> None:
    sim = near_the_stop()
    assert sim.where().joints[2] == pytest.approx(223.6 - 360.0)  # what the screen shows (SPEC §3a, 1985)
    with pytest.raises(MotionRefused) as refused:
        drain(sim.pendant_tool(0))
    assert refused.value.joint == 3
    found = STOP_ANGLE.search(str(refused.value).upper())
    assert found, str(refused.value)
    needed = float(found.group(1))
    # beside the stop it passes, within one step of where the joint is (not its -131-odd equivalent)
    assert 225.0 < needed < 223.6 + 32.0
    assert float(found.group(2)) == pytest.approx(needed - 360.0, abs=0.006)  # and as the readout shows it
    assert sim.joints == tuple(NEAR_JT3_STOP)  # nothing moved


def test_the_controller_rules_show_the_wound_angle_too() -> None:
    sim = near_the_stop()
    sim.set_rules("CONTROLLER")
    with pytest.raises(MotionRefused) as refused:
        drain(sim.pendant_tool(0))
    found = STOP_ANGLE.search(str(refused.value).upper())
    assert found and 225.0 < float(found.group(1)) < 223.6 + 32.0, str(refused.value)


async def test_the_pendant_shows_the_needed_angle_and_no_bend_the_arm_hint(tmp_path: Path) -> None:
    async with Simulation(tmp_path, setup="PROCESS", size=(120, 40)) as sim:
        sim.simulator.stand_at(NEAR_JT3_STOP)
        await sim.press("P", "I", "I", "T", "X")  # PENDANT, increment 32, TOOL X
        messages = sim.messages()
        text = " ".join(messages)
        assert "-136.40" in " ".join(sim.readout())  # JT3 as the readout shows it (SPEC §3a, 1985 rules)
        found = STOP_ANGLE.search(text)
        assert found and 225.0 < float(found.group(1)) < 255.6, messages
        assert "BEND IT" not in text and "STRETCHED" not in text, messages  # the elbow is bent
        assert "HINT: THE STEP WOULD TURN JOINT 3 PAST ITS STOP AT 225" in text, messages  # the hint that is true
        assert sim.simulator.joints == tuple(NEAR_JT3_STOP)


async def test_the_stretched_arm_hint_stays_where_it_is_true(tmp_path: Path) -> None:
    async with Simulation(tmp_path, setup="PROCESS", size=(120, 40)) as sim:
        await sim.press("P", "W", "X")  # WORLD X at READY: the arm straight up, JT5 = 0
        text = " ".join(sim.messages())
        assert "MOTION REFUSED" in text and "SINGULARITY" in text, text
        assert "BEND IT FIRST" in text, text


# -- the PUMA 560: WHERE (the cell's frame) and kin fk (the robot's base frame) -------------------
Q560 = (10.0, 45.0, -60.0, 20.0, 30.0, -15.0)


def test_where_and_kin_fk_on_the_560_each_name_their_frame(capsys: pytest.CaptureFixture[str]) -> None:
    """The toolbox's fkine, computed here, is kin's (frame 0: the 560's base on its mounting
    surface); WHERE is the cell's, whose robot origin is the shoulder, d1 above that base."""
    from valterm.cli import main as cli

    models = pytest.importorskip("roboticstoolbox.models.DH")
    puma = models.Puma560()
    tool = puma.fkine(np.radians(Q560)).A
    base_xyz = tool[:3, 3] * 1000.0
    d1 = puma.links[0].d * 1000.0  # 671.83 mm: the pedestal
    sim = Simulator(robot="PUMA560")
    drain(sim.move_joints(Q560))
    assert np.allclose(sim.where().xyz, base_xyz - [0.0, 0.0, d1], atol=1e-6)  # WHERE: the cell's
    capsys.readouterr()
    assert cli(["kin", "fk", "--robot", "PUMA560", *map(str, Q560)]) == 0
    lines = capsys.readouterr().out.splitlines()
    # kin names its frame and how WHERE's follows from it, and its columns are not WHERE's
    assert lines[0] == f"PUMA 560 BASE FRAME (FRAME 0 OF ITS DH TABLE): WHERE IN THE CELL HAS ZW = Z0 - {d1:.2f}"
    assert lines[1].split()[1:4] == ["X0", "Y0", "Z0"]
    assert np.allclose([float(v) for v in lines[2].split()[1:4]], base_xyz, atol=0.006)
    # the thesis's robot: one frame, the readout as in Fig. 2-8
    assert cli(["kin", "fk", "0", "-90", "90", "0", "0", "0"]) == 0
    assert capsys.readouterr().out.splitlines()[0].split()[1:4] == ["XW", "YW", "ZW"]


def test_a_typed_joint_angle_past_its_stop_is_named_as_typed() -> None:
    """A precision point with JT3 230 (stop 225): the refusal says 230.00, not its -130.00."""
    sim = Simulator()
    with pytest.raises(MotionRefused) as refused:
        drain(sim.move_joints([0.0, -90.0, 230.0, 0.0, 0.0, 0.0]))
    assert "joint 3 beyond its stop (230.00 deg, stop -45..225)" in str(refused.value)
