"""Verdicts you can trust (issue 22, SPEC §3a): one joint state, two sets of rules, locations
that keep their configuration, STOREL, and refusals that answer at once."""

from __future__ import annotations

import tracemalloc
from pathlib import Path

import pytest

from valterm.core.errors import ValtermError
from valterm.core.events import Collision, Message, Motion
from valterm.core.files.errors import FileFormatError
from valterm.core.files.locations import format_locations, parse_locations, read_locations
from valterm.core.files.setup import read_setup
from valterm.core.kinematics import (
    Config,
    Location,
    canonical_joints,
    fk,
    ik,
    indicators,
    oat_to_rotation,
    readout_joints,
    robot_geometry,
)
from valterm.core.motion import MotionRefused, straight_path
from valterm.core.rules import CONTROLLER, RULES_1985
from valterm.core.session import Session
from valterm.core.simulator import Simulator

DATA = Path(__file__).resolve().parent / "data" / "verdicts"
STOPS = robot_geometry().stops


def inside(joints: tuple[float, ...] | list[float]) -> bool:
    return all(lo - 1e-6 <= j <= hi + 1e-6 for j, (lo, hi) in zip(joints, STOPS))


def messages(events: list) -> list[str]:  # type: ignore[type-arg]
    return [e.text for e in events if isinstance(e, Message)]


# -- one joint state ---------------------------------------------------------------------

def test_the_1985_rules_keep_each_joint_the_equivalent_inside_its_stops() -> None:
    assert canonical_joints([0, 172.08, -144.96, 190, 0, -200]) == pytest.approx([0, -187.92, 215.04, -170, 0, 160])
    with pytest.raises(ValtermError, match="joint 1 beyond its stop"):
        canonical_joints([170, 0, 90, 0, 0, 0])  # no equivalent of JT1 170 lies in -160..160


def test_where_and_the_stop_check_use_the_same_angles_drive_after_a_wound_wrist() -> None:
    # the 7 lines: JT4 turned past 180 shows -170; DRIVE 4,80 goes to -90, not 270
    sim = Simulator()
    list(sim.drive(4, 190.0))
    assert sim.where().joints[3] == pytest.approx(-170.0)
    assert sim.joints[3] == pytest.approx(-170.0)  # the state is what WHERE shows
    list(sim.drive(4, 80.0))
    assert sim.where().joints[3] == pytest.approx(-90.0)


def test_under_the_controller_rules_joints_wind_and_where_shows_the_wound_angle() -> None:
    sim = Simulator()
    sim.set_rules(CONTROLLER)
    list(sim.drive(4, 190.0))
    assert sim.where().joints[3] == pytest.approx(190.0)
    with pytest.raises(MotionRefused, match=r"joint 4 beyond its stop \(270.00 deg"):
        list(sim.drive(4, 80.0))  # the angle named is the one WHERE shows, plus 80


def test_a_joint_moving_from_179_to_minus_179_moves_2_degrees_under_the_1985_rules() -> None:
    sim = Simulator()
    list(sim.drive(4, 179.0))
    target = fk([0, -90, 90, -179, 30, 0])
    location = Location(tuple(float(v) for v in target.xyz), target.oat)  # type: ignore[arg-type]
    list(sim.drive(5, 30.0))
    events = list(sim.move(location))
    poses = [e for e in events if type(e).__name__ == "PoseEvent"]
    assert len(poses) == 1  # 2 degrees: one step at 12 degrees a step
    assert sim.where().joints[3] == pytest.approx(-179.0)


def test_every_pose_of_a_program_is_inside_the_stops_as_printed(tmp_path: Path) -> None:
    session = Session(tmp_path, setup="CONV")
    session.load_locations("CONV")
    events = list(session.command("EXEC CONV1"))
    poses = [e.joints for e in events if type(e).__name__ == "PoseEvent"]
    assert poses and all(inside(p) for p in poses)
    assert not [e for e in events if type(e).__name__ == "Error"]


# -- angles printed are angles accepted ------------------------------------------------

def test_a_precision_point_copied_from_kin_ik_or_where_is_never_refused_for_a_stop() -> None:
    joints = ik([400.0, 0.0, 0.0], oat_to_rotation(90, 90, 0), Config(-1, 1, 1))
    shown = readout_joints(joints)
    assert shown[2] == pytest.approx(215.04, abs=0.01)  # the controller's readout, not -144.96
    for copy in (shown, [shown[0], shown[1], shown[2] - 360.0, *shown[3:]]):  # either way it was printed
        sim = Simulator()
        list(sim.move_joints([round(v, 2) for v in copy]))
        assert sim.joints[2] == pytest.approx(215.04, abs=0.01)  # held inside the stop -45..225
        assert sim.where().joints[2] == pytest.approx(-144.96, abs=0.01)  # 1985: shown in (-180, 180]


def test_where_shows_the_1985_angle_in_minus_180_180_and_the_controllers_inside_the_stop() -> None:
    # SPEC §3a: the 1985 rules show a joint as the thesis's figures do (Fig. 2-8a1: JT2 172.08,
    # held as -187.92 inside the stop -225..45); the controller's rules, as the joint holds it
    sim = Simulator()
    list(sim.move_joints([0, -90, 215.04, 0, 0, 0]))
    assert sim.where().joints[2] == pytest.approx(-144.96)
    sim.set_rules(CONTROLLER)
    assert sim.where().joints[2] == pytest.approx(215.04)
    figure = Simulator()
    figure.stand_at([-108.02, 172.08, 19.34, -1.52, 35.64, -9.54])  # typed as printed: accepted
    assert figure.joints[1] == pytest.approx(-187.92)
    assert figure.where().joints == pytest.approx((-108.02, 172.08, 19.34, -1.52, 35.64, -9.54))


# -- configurations that stick -----------------------------------------------------------

def taught_lefty(rules: str) -> Simulator:
    """P2 taught LEFTY (DRIVE as the pendant would), then READY: the arm is RIGHTY again."""
    sim = Simulator()
    sim.set_rules(rules)
    list(sim.drive(2, 60.0))
    list(sim.drive(1, -40.0))
    sim.here("P2")
    assert sim.location("P2").config == Config(-1, 1, 1)
    assert sim.location("P2").joints == pytest.approx((-40.0, -30.0, 90.0, 0.0, 0.0, 0.0))
    list(sim.ready())
    return sim


def test_1985_rules_refuse_a_location_taught_in_another_configuration_naming_both() -> None:
    sim = taught_lefty(RULES_1985)
    with pytest.raises(MotionRefused) as refused:
        list(sim.appro("P2", 80.0))
    text = str(refused.value)
    assert "LEFTY ABOVE NOFLIP" in text and "RIGHTY ABOVE NOFLIP" in text and "P2" in text
    assert sim.joints == tuple(robot_geometry().ready)  # nothing moved
    sim.set_indicator("LEFTY")
    events = list(sim.appro("P2", 80.0))
    assert indicators(sim.joints).arm == -1
    assert "ARM CONFIGURATION CHANGED: RIGHTY TO LEFTY" in messages(events)


def test_controller_rules_follow_the_taught_configuration_and_say_so() -> None:
    sim = taught_lefty(CONTROLLER)
    events = list(sim.appro("P2", 80.0))
    assert indicators(sim.joints).arm == -1  # LEFTY as taught, never a silent swing to RIGHTY
    assert "ARM CONFIGURATION CHANGED: RIGHTY TO LEFTY" in messages(events)
    assert isinstance(events[-1], Motion)


def test_controller_rules_keep_the_arms_configuration_for_a_location_without_one() -> None:
    sim = Simulator()
    sim.set_rules(CONTROLLER)
    list(sim.drive(2, 60.0))  # LEFTY now
    pose = fk([10.0, -40.0, 120.0, 0.0, 20.0, 0.0])  # LEFTY; its RIGHTY solution is JT1 -145.9
    bare = Location(tuple(float(v) for v in pose.xyz), pose.oat)  # type: ignore[arg-type]
    events = list(sim.move(bare))
    assert indicators(sim.joints).arm == -1 and not [m for m in messages(events) if "CHANGED" in m]
    sim.set_indicator("RIGHTY")  # asked for: the next motion changes it, and says so
    events = list(sim.move(bare))
    assert indicators(sim.joints).arm == 1
    assert "ARM CONFIGURATION CHANGED: LEFTY TO RIGHTY" in messages(events)


def test_ready_says_when_it_turns_the_indicators_positive() -> None:
    sim = Simulator()
    sim.set_indicator("LEFTY")
    events = list(sim.ready())
    assert "READY: CONFIGURATION INDICATORS LEFTY TO RIGHTY" in messages(events)
    assert sim.config == Config(1, 1, 1)
    assert not messages(list(sim.ready()))  # nothing changed: nothing said


def test_set_copies_the_configuration_and_shift_keeps_it() -> None:
    sim = taught_lefty(RULES_1985)
    sim.set_location("P3", "P2")
    assert sim.location("P3") == sim.location("P2")
    shifted = sim.shift("P3", 0.0, 0.0, 10.0)
    assert shifted.config == Config(-1, 1, 1) and shifted.joints is None


# -- locations saved -------------------------------------------------------------------

def test_loc_lines_carry_configuration_and_joints_and_old_lines_still_read(tmp_path: Path) -> None:
    taught = Location((1.0, 2.0, 3.0), (90.0, 90.0, 0.0), Config(-1, 1, -1), (10.0, -20.0, 30.0, 0.0, 5.0, 6.0))
    text = format_locations({"P1": taught, "A": Location((465.0, -45.0, -245.0), (89.0, 91.0, 0.0))})
    assert "POINT P1, 1.00, 2.00, 3.00, 90.00, 90.00, 0.00, LEFTY ABOVE FLIP, 10.00, -20.00" in text
    assert "POINT A, 465.00, -45.00, -245.00, 89.00, 91.00, 0.00\n" in text
    back = parse_locations(text, tmp_path / "X.LOC")
    assert back["P1"] == taught and back["A"].config is None
    only_config = parse_locations("POINT B, 1, 2, 3, 4, 5, 6, RIGHTY BELOW NOFLIP\n", tmp_path / "Y.LOC")
    assert only_config["B"].config == Config(1, -1, 1) and only_config["B"].joints is None


@pytest.mark.parametrize("line, reason", [
    ("POINT B, 1, 2, 3, 4, 5, 6, LEFTY LEFTY NOFLIP", "twice"),
    ("POINT B, 1, 2, 3, 4, 5, 6, SIDEWAYS ABOVE NOFLIP", "not a configuration indicator"),
    ("POINT B, 1, 2, 3, 4, 5, 6, LEFTY ABOVE", "found 8 fields"),
])
def test_a_bad_configuration_on_a_loc_line_is_a_located_error(tmp_path: Path, line: str, reason: str) -> None:
    with pytest.raises(FileFormatError) as error:
        parse_locations(f"POINT A, 1, 2, 3, 4, 5, 6\n{line}\n", tmp_path / "BAD.LOC")
    assert error.value.line == 2 and reason in str(error.value)


def test_storel_then_a_new_session_executes_with_the_taught_locations(tmp_path: Path) -> None:
    first = Session(tmp_path, setup=None)
    list(first.command("LEFTY"))
    list(first.command("DRIVE 2,60,100"))
    list(first.command("HERE P1"))
    list(first.command("DRIVE 1,-40,100"))
    list(first.command("HERE P2"))
    assert first.simulator.unsaved_locations() == ["P1", "P2"]  # what the quit prompt counts
    [said] = messages(list(first.command("STOREL PICK")))
    assert said == "2 LOCATIONS STORED IN PICK.LOC"
    assert first.simulator.unsaved_locations() == []
    stored = read_locations(tmp_path / "PICK.LOC")
    assert stored["P2"].config == Config(-1, 1, 1) and stored["P2"].joints is not None
    (tmp_path / "PICK.DAT").write_text("    READY\n    LEFTY\n    MOVE P1\n    APPRO P2, 50\n    MOVE P2\n")
    second = Session(tmp_path, setup=None)
    second.load_locations("PICK")
    assert second.simulator.unsaved_locations() == []
    events = list(second.command("EXEC PICK"))
    assert not [e for e in events if type(e).__name__ == "Error"], events
    assert second.simulator.where().joints == pytest.approx(stored["P2"].joints)


@pytest.mark.parametrize("typed, words", [("STOREL", "NEEDS A FILE NAME"), ("STOREL ../X", "NOT A VALID NAME"),
                                           ("RULES SIDEWAYS", "NOT A SET OF RULES")])
def test_storel_and_rules_refuse_bad_arguments_with_a_message(tmp_path: Path, typed: str, words: str) -> None:
    session = Session(tmp_path, setup=None)
    before = sorted(tmp_path.parent.rglob("*.LOC"))
    [error] = [e for e in session.command(typed) if type(e).__name__ == "Error"]
    assert words in error.message.upper()
    assert sorted(tmp_path.parent.rglob("*.LOC")) == before  # no location file written anywhere


def test_status_names_the_rules(tmp_path: Path) -> None:
    session = Session(tmp_path, setup=None)
    [status] = [e for e in session.command("RULES CONTROLLER") if type(e).__name__ == "Status"]
    assert status.rules == CONTROLLER and status.rules_text.startswith("RULES CONTROLLER")


# -- refusals that answer at once ------------------------------------------------------

@pytest.mark.parametrize("command", ["DRAW 1000000000", "DRAW 279964360572463", "DRAW 1e300, 1e300, 1e300",
                                     "MOVES SHIFT(HOME BY 1e12, 0, 0)", "APPROS HOME, -1e15", "DEPARTS 1e15",
                                     "DRIVE 1, 1e300, 100"])
def test_absurd_motions_are_refused_before_any_path_is_built(tmp_path: Path, command: str) -> None:
    session = Session(tmp_path, setup=None)
    list(session.command("HERE HOME"))
    tracemalloc.start()
    events = list(session.command(command))
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    [error] = [e for e in events if type(e).__name__ == "Error"]
    assert "OUT OF REACH" in error.message.upper() or "BEYOND ITS STOP" in error.message.upper()
    assert len(error.message) < 200  # no 300-digit angle
    assert peak < 50_000_000  # no path of millions of steps (1e9 mm: 40 M steps, 1.9 GB) was built


def test_a_line_through_the_wrist_singularity_is_refused_by_name() -> None:
    # JT5 passes 0 on the way; JT6 swings past 90 there, so the line would end in the other wrist
    start = [0.0, -60.0, 150.0, 0.0, 15.0, 80.0]
    there = fk([0.0, -60.0, 150.0, 0.0, -15.0, 100.0])
    with pytest.raises(MotionRefused) as refused:
        straight_path(start, there.xyz, there.rotation, indicators(start), 25.4)
    assert "wrist singularity (JT5 = 0)" in str(refused.value)
    assert refused.value.joint == 5 and refused.value.step >= 1


# -- collision verdicts unchanged where they were right (SPEC §4) ------------------------

def run_program(tmp_path: Path, name: str) -> list:  # type: ignore[type-arg]
    from valterm.core.val.interpreter import Interpreter
    from valterm.core.files.programs import read_program

    sim = Simulator(read_setup(DATA / "TABLE.SET"))
    sim.locations.update(read_locations(DATA / "TABLE.LOC"))
    sim.collision_checks = True
    interpreter = Interpreter(sim, lambda n: read_program(DATA / f"{n}.DAT"))
    return list(interpreter.execute(name))


def test_setting_a_part_down_touching_the_table_is_no_collision(tmp_path: Path) -> None:
    events = run_program(tmp_path, "PLACE")
    assert any(type(e).__name__ == "Grasp" for e in events)
    assert not [e for e in events if isinstance(e, Collision)], [e.text for e in events if isinstance(e, Collision)]
    assert not [e for e in events if type(e).__name__ == "Error"]


def test_dragging_a_held_part_through_another_is_a_collision(tmp_path: Path) -> None:
    events = run_program(tmp_path, "DRAG")
    collisions = {(e.a, e.b) for e in events if isinstance(e, Collision)}
    assert ("2", "3") in collisions  # the held part 2 through the obstacle 3
