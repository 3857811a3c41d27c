"""The thesis's case studies run headless through `valterm run` (issue 4 "Done when")."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from valterm.core.events import Collision, Near
from valterm.core.files.locations import read_locations
from valterm.core.files.setup import read_setup
from valterm.core.motion import MotionRefused
from valterm.core.session import Session
from valterm.core.simulator import Simulator

ROOT = Path(__file__).resolve().parent.parent  # the repository: the bundled data (cells/, programs/)
def run(workspace: Path, *argv: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "valterm", "--workspace", str(workspace), "run", *argv],
                          capture_output=True, text=True, timeout=120)


def events(result: subprocess.CompletedProcess[str]) -> list[dict]:
    return [json.loads(line) for line in result.stdout.splitlines()]


def test_process_grasps_carries_and_releases_both_parts(tmp_path: Path) -> None:
    result = run(tmp_path, "PROCESS.DAT", "--cell", "PROCESS.SET", "--loc", "PROCESS.LOC", "--json")
    assert result.returncode == 0, result.stderr
    ev = events(result)
    assert not [e for e in ev if e["event"] == "error"]
    hand = [(e["event"], e["part"]) for e in ev if e["event"] in ("grasp", "release")]
    assert hand == [("grasp", 1), ("release", 1), ("grasp", 2), ("release", 2)]
    released = {e["part"]: np.array(e["position"]) for e in ev if e["event"] == "release"}
    # each part was latched at A / B and carried; the clamp put it down at C / D, so its
    # reference corner keeps its offset from the TCS at the grasp, now about C / D
    locs = read_locations(ROOT / "programs" / "PROCESS.LOC")
    cell = read_setup(ROOT / "cells" / "PROCESS.SET")
    for part, pick, place in ((1, "A", "C"), (2, "B", "D")):
        offset_at_pick = cell.object(part).reference - np.array(locs[pick].xyz)
        moved = released[part] - np.array(locs[place].xyz)
        assert np.linalg.norm(moved) == pytest.approx(np.linalg.norm(offset_at_pick), abs=1e-6)
        # it now stands on the left-hand table (object 3, top at Z = -280)
        assert released[part][2] == pytest.approx(-280.0, abs=1.0)
    end = ev[-1]
    assert end["event"] == "end"
    assert end["where"]["joints"] == [0.0, -90.0, 90.0, 0.0, 0.0, 0.0]  # READY
    assert [e for e in ev if e["event"] == "motion"]  # it moved
    assert not any(e["event"] in ("near", "collision") for e in ev)  # checks were off


# Each pair the 1985 check reports for the PROCESS run, with the step that first shows it
# and why the geometry makes it so (SPEC §3: APPRO x, -50 stops 50 mm PAST x along the
# tool's approach vector, which points down here).
PROCESS_COLLISIONS = {
    # APPRO A, -50: the TCS goes to Z -295, 45 mm below part 1's top (-250): the clamp palm
    # and the wrist flange enter part 1 and the fingertips (50.8 mm further) pass the top of
    # the right-hand table (object 8, top -320)
    "CLAMP COLLIDES WITH 1": 6, "WRIST COLLIDES WITH 1": 6, "FINGER COLLIDES WITH 8": 6,
    # ... and on the way down a finger passes through part 1 between two poses (the swept
    # check's substeps find it; python-fcl agrees at those joints)
    "FINGER COLLIDES WITH 1": 6,
    # MOVES F: F (Z -400) lies inside the part processor, a solid column (objects 13, 14)
    "1 COLLIDES WITH 13": 12, "1 COLLIDES WITH 14": 12, "CLAMP COLLIDES WITH 13": 12,
    "FINGER COLLIDES WITH 13": 12, "WRIST COLLIDES WITH 13": 12,
    # APPROS C, -50: part 1 is pushed 50 mm into the left-hand table top (object 3)
    "1 COLLIDES WITH 3": 16, "FINGER COLLIDES WITH 3": 16,
    # APPROS B, -50: as at A, for part 2; the fingertips below the table top meet leg 11
    "CLAMP COLLIDES WITH 2": 20, "FINGER COLLIDES WITH 2": 20, "WRIST COLLIDES WITH 2": 20,
    "FINGER COLLIDES WITH 11": 20,
    # MOVES E after SHIFT E, 0, 0, -200: E is now Z -420, inside the processor
    "2 COLLIDES WITH 13": 29, "2 COLLIDES WITH 14": 29, "FINGER COLLIDES WITH 14": 29,
    # APPROS D, -50: part 2 into the left-hand table top
    "2 COLLIDES WITH 3": 30, "CLAMP COLLIDES WITH 3": 30,
}


def test_process_with_collision_checks_reports_exactly_these_pairs(tmp_path: Path) -> None:
    result = run(tmp_path, "PROCESS.DAT", "--json", "--collisions")
    assert result.returncode == 0, result.stderr
    first: dict[str, int] = {}
    step = 0
    for e in events(result):
        if e["event"] == "step":
            step = e["step"]
        elif e["event"] == "collision":
            first.setdefault(e["text"], step)
    assert first == PROCESS_COLLISIONS
    hand = [(e["event"], e["part"]) for e in events(result) if e["event"] in ("grasp", "release")]
    assert hand == [("grasp", 1), ("release", 1), ("grasp", 2), ("release", 2)]


def test_open_clamp_straddling_a_part_is_near_not_colliding() -> None:
    sim = Simulator(read_setup(ROOT / "cells" / "PROCESS.SET"))
    sim.locations.update(read_locations(ROOT / "programs" / "PROCESS.LOC"))
    sim.set_indicator("LEFTY")
    list(sim.move("A"))
    sim.collision_checks = True
    found = list(sim.check_collisions())
    texts = {e.text for e in found}
    assert "CLAMP IS NEAR PART 1" in texts
    assert not [e for e in found if isinstance(e, Collision) and e.b == "1"]
    assert all(isinstance(e, (Near, Collision)) for e in found)


def test_stop_on_collision_stops_the_motion_where_it_collides() -> None:
    sim = Simulator(read_setup(ROOT / "cells" / "PROCESS.SET"))
    sim.locations.update(read_locations(ROOT / "programs" / "PROCESS.LOC"))
    sim.set_indicator("LEFTY")
    sim.collision_checks = sim.stop_on_collision = True
    with pytest.raises(MotionRefused, match="stopped on collision"):
        list(sim.appro("A", -50))
    # stopped short of the goal, above Z -295
    assert sim.where().xyz[2] > -295.0


def test_conv1_with_conv2_runs_to_its_end_under_the_1985_rules(tmp_path: Path) -> None:
    """The thesis's second example completes (§6.1.2: the angles are a function of the pose).

    CONV1's MOVES L leaves JT4 at 153.47 (WHERE's angle, the one the stop check uses), so CONV2's
    MOVES B starts there and stays inside the stops (issue 22: it used to start from a hidden
    -206.53 and stop at -268.34).
    """
    result = run(tmp_path, "CONV1.DAT", "--cell", "CONV.SET", "--loc", "CONV.LOC", "--json")
    assert result.returncode == 0, result.stdout[-2000:]
    ev = events(result)
    typed = [e["text"] for e in ev if e["event"] == "type"]
    assert typed == ["COL = 2", "ROW = 3", "COL = 3", "ROW = 3", "COL = 3"]
    assert not [e for e in ev if e["event"] == "error"]
    assert {e["program"] for e in ev if e["event"] == "step"} == {"CONV1", "CONV2"}
    assert ev[-1]["where"]["config"]["arm"] == "RIGHTY"  # CONV1 ends RIGHTY at A
    # one joint state: every pose's angles are inside the stops as printed
    stops = [(-160, 160), (-225, 45), (-45, 225), (-180, 180), (-100, 100), (-180, 180)]
    for pose in (e["joints"] for e in ev if e["event"] == "pose"):
        assert all(lo - 1e-6 <= j <= hi + 1e-6 for j, (lo, hi) in zip(pose, stops)), pose


def test_conv1_under_the_controller_rules_stops_where_the_real_wrist_meets_its_stop(tmp_path: Path) -> None:
    """A real PUMA's joints wind: MOVES L rolls JT4 to -206.53 and WHERE shows that; CONV2's
    MOVES B would roll it on past -266 at the line's 10th step (the angle named is WHERE's)."""
    result = run(tmp_path, "CONV1.DAT", "--cell", "CONV.SET", "--loc", "CONV.LOC", "--json",
                 "--rules", "controller")
    assert result.returncode == 1, result.stderr
    ev = events(result)
    [error] = [e for e in ev if e["event"] == "error"]
    assert (error["program"], error["step"]) == ("CONV2", 8)
    assert "joint 4 beyond its stop (-268.34 deg" in error["message"] and "-266" in error["message"]
    assert "step 10 of the line" in error["message"]
    assert ev[-1]["where"]["joints"][3] == pytest.approx(-206.53, abs=0.01)  # shown as it is


def test_run_time_error_exits_1_with_program_and_step(tmp_path: Path) -> None:
    result = run(tmp_path, "CONV1.DAT", "--json")  # no CONV.LOC: location A undefined
    assert result.returncode == 1
    errors = [e for e in events(result) if e["event"] == "error"]
    assert errors[0]["program"] == "CONV1" and errors[0]["step"] == 11
    assert "A" in errors[0]["message"]


def test_bad_input_file_exits_1_with_a_located_message(tmp_path: Path) -> None:
    bad = tmp_path / "BAD.SET"
    bad.write_text("2\nMM\nW\n1,7\n0 0 0\n")
    result = run(tmp_path, "PROCESS.DAT", "--cell", str(bad))
    assert result.returncode == 1
    assert "valterm: BAD.SET:4:" in result.stderr
    assert "Traceback" not in result.stderr


def test_variables_are_kept_across_sessions_in_check_dat(tmp_path: Path) -> None:
    first = Session(tmp_path, setup=None)
    list(first.interpreter.command("ROW=10"))
    assert "ROW=10" in (tmp_path / "CHECK.DAT").read_text().replace(" ", "")
    second = Session(tmp_path, setup=None)
    typed = [e.text for e in second.interpreter.command("TYPE ROW=") if e.event == "type"]
    assert typed == ["ROW = 10"]
