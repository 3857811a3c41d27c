"""Issue 26: the robot is chosen once (--robot) and everything kinematic goes through it.

The thesis's PROCESS program runs on the PUMA 560 and stops, in the 560's own words, where that
robot cannot follow it; STATUS, --json's status and end events, the app's status bar and grade's
task files name the robot; the simulator's motions on the 560 land where the 560's own
kinematics say (the drawn links too); the thesis's robot stays the default, untouched."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from valterm.cli import main
from valterm.core.arms import DHArm, ThesisArm, arm_of, thesis_arm
from valterm.core.robot_choice import check_robot
from valterm.core.dh import dh_robot
from valterm.core.errors import RefusedValue
from valterm.core.grading import TaskError, grade, read_task
from valterm.core.kinematics import OUT_OF_REACH, Config, Location, fk, rotation_to_oat
from valterm.core.motion import MotionRefused, straight_path
from valterm.core.simulator import Simulator
from valterm.testing import Simulation

PROCESS_560_ERROR = ("*** PROCESS STEP 6: THE APPROACH TO LOCATION A IS BEYOND THE PUMA 560'S STOPS: "
                     "JOINT 4 BEYOND ITS STOP (170.77 DEG, STOP -110..170)")


def _run(capsys: pytest.CaptureFixture[str], workspace: Path, *args: str) -> tuple[int, list[str]]:
    status = main(["--workspace", str(workspace), *args])
    return status, capsys.readouterr().out.splitlines()


def test_process_runs_on_the_560_and_stops_in_its_own_words(capsys: pytest.CaptureFixture[str],
                                                            tmp_path: Path) -> None:
    status, lines = _run(capsys, tmp_path, "run", "PROCESS", "--robot", "PUMA560")
    assert status == 1
    assert lines[:5] == ["PROCESS     3  READY", "PROCESS     4  LEFTY", "PROCESS     5  ABOVE",
                         "PROCESS     6  APPRO A, -50", PROCESS_560_ERROR]
    # nothing moved at the refused step: the 560 stands at its own READY (the toolbox's qr), its
    # shoulder where the thesis's robot has its own (X and Y: the 560's a3 and shoulder offset d3)
    assert lines[-4:] == ["RIGHTY      20.30  -150.05   863.60    90.00   -90.00     0.00",
                            "ABOVE        JT 1     JT 2     JT 3     JT 4     JT 5     JT 6",
                            "NOFLIP       0.00    90.00   -90.00     0.00     0.00     0.00",
                            "CYCLE TIME 0.00 S (ESTIMATE FOR THE REAL PUMA)"]
    # --robot before the subcommand is the same run; --json's end event names the robot
    status, lines = _run(capsys, tmp_path, "--robot", "PUMA560", "run", "PROCESS", "--json")
    events = [json.loads(line) for line in lines]
    assert status == 1 and events[-2]["event"] == "error" and events[-2]["step"] == 6
    assert events[-2]["message"].upper() == PROCESS_560_ERROR.removeprefix("*** PROCESS STEP 6: ")
    assert (events[-1]["event"], events[-1]["robot"], events[-1]["robot_key"]) == ("end", "PUMA 560", "PUMA560")
    # the thesis's robot (the default) still runs PROCESS to its end, and says it is the PUMA 600
    status, lines = _run(capsys, tmp_path, "run", "PROCESS", "--json")
    events = [json.loads(line) for line in lines]
    assert status == 0 and not [e for e in events if e["event"] == "error"]
    assert (events[-1]["robot"], events[-1]["robot_key"]) == ("PUMA 600", "PUMA")


def test_status_names_the_robot_when_it_is_not_the_thesiss(monkeypatch: pytest.MonkeyPatch,
                                                            capsys: pytest.CaptureFixture[str],
                                                            tmp_path: Path) -> None:
    def status_lines(*args: str) -> list[str]:
        monkeypatch.setattr("sys.stdin", __import__("io").StringIO("STATUS\n"))
        assert main(["--workspace", str(tmp_path), "monitor", "--setup", "PROCESS", *args]) == 0
        out = capsys.readouterr().out.splitlines()
        return out[out.index(". STATUS") + 1:]

    thesis = status_lines()
    assert len(thesis) == 3 and thesis[1].startswith("RULES 1985") and not any("ROBOT" in x for x in thesis)
    puma560 = status_lines("--robot", "PUMA560")
    assert puma560[2] == "ROBOT PUMA 560 (--ROBOT PUMA560: ITS OWN DH MODEL, NOT THE THESIS'S)"
    assert [puma560[0], puma560[1], puma560[3]] == thesis
    # the status event of --json carries the robot either way
    sim = Simulator(robot="PUMA560")
    from valterm.core.val.interpreter import Interpreter

    event = Interpreter(sim, lambda name: None).status().to_json()  # type: ignore[arg-type,return-value]
    assert (event["robot"], event["robot_key"]) == ("PUMA 560", "PUMA560")
    assert Interpreter(Simulator(), lambda name: None).status().to_json()["robot"] == "PUMA 600"  # type: ignore[arg-type,return-value]


def test_an_unknown_robot_is_a_usage_error_naming_the_robots(capsys: pytest.CaptureFixture[str],
                                                            tmp_path: Path) -> None:
    for args in (["--robot", "PUMA9", "run", "PROCESS"], ["run", "PROCESS", "--robot", "PUMA9"],
                 ["monitor", "--robot", "PUMA9"]):
        assert main(["--workspace", str(tmp_path), *args]) == 2
        assert "no robot 'PUMA9'; the robots are PUMA (the thesis's, the default), PUMA560" in capsys.readouterr().err
    assert check_robot(" puma560 ") == "PUMA560"
    with pytest.raises(RefusedValue):
        check_robot("KUKA")


def test_motions_on_the_560_go_through_its_own_kinematics() -> None:
    sim = Simulator(robot="PUMA560")
    assert isinstance(sim.arm, DHArm) and sim.joints == (0.0, 90.0, -90.0, 0.0, 0.0, 0.0)
    chain = dh_robot("PUMA560")
    goal = [20.0, 60.0, -120.0, 30.0, -40.0, 50.0]
    tool = chain.fk(goal)
    # a location in the cell: the 560's tool frame with its shoulder at the cell's robot origin
    xyz = tool[:3, 3] - [0.0, 0.0, chain.d[0]]
    location = Location(tuple(float(v) for v in xyz), rotation_to_oat(tool[:3, :3]))  # type: ignore[arg-type]
    sim.config = chain.indicators(goal)
    poses = list(sim.move(location))
    assert poses and np.allclose(sim.joints, goal, atol=1e-6)
    where = sim.where()
    assert np.allclose(where.xyz, xyz, atol=1e-5) and where.config == sim.config.as_dict()
    # the drawn links stand on the 560's own chain, moved by the same mount
    placed = {p.name: p for p in sim.robot_polyhedra()}
    flange = tool[:3, 3] + 43.0 * tool[:3, 2] - [0.0, 0.0, chain.d[0]]
    assert np.allclose(placed["FLANGE"].vertices.mean(axis=0), flange, atol=1e-6)
    # a straight line of the 560, each step solved by its inverse
    start = list(sim.joints)
    here = sim.arm.fk(start)
    path = straight_path(start, here.xyz + [0.0, 0.0, -60.0], here.rotation, sim.config, 25.4, sim.arm)
    assert len(path) == 3 and np.allclose(sim.arm.fk(list(path[-1])).xyz, here.xyz + [0, 0, -60], atol=1e-6)
    # beyond its reach: the location is named with the robot
    far = Location((3000.0, 0.0, 0.0), (0.0, 90.0, 0.0))
    sim.locations["FAR"] = far
    with pytest.raises(MotionRefused, match="location FAR is out of reach of the PUMA 560"):
        list(sim.move("FAR"))


def test_the_560s_batch_inverse_and_its_elbow_straight() -> None:
    arm = arm_of("PUMA560")
    joints = np.array([[10.0, 40.0, -120.0, 30.0, -45.0, 60.0], [0.0, 100.0, -150.0, -60.0, -30.0, 10.0]])
    poses = [arm.fk(list(q)) for q in joints]
    xyz = np.array([p.xyz for p in poses] + [[5000.0, 0.0, 0.0]])
    rot = np.array([p.rotation for p in poses] + [np.eye(3)])
    solved, status = arm.ik_batch(xyz, rot, arm.indicators(list(joints[0])))
    assert np.allclose(solved[0], joints[0], atol=1e-6) and list(status) == [0, 0, OUT_OF_REACH]
    # at JT3 = elbow_straight the arm is straight: the wrist centre as far from the shoulder, in the
    # arm's plane, as the upper arm and the forearm together reach
    chain = dh_robot("PUMA560")
    for jt2 in (-30.0, 30.0, 120.0):
        frames = arm.link_frames([15.0, jt2, arm.elbow_straight, 0.0, 0.0, 0.0])
        axis = frames[1, :3, 2]  # the shoulder's axis: the d3 offset lies along it
        v = frames[4, :3, 3] - frames[1, :3, 3]
        in_plane = np.linalg.norm(v - np.dot(v, axis) * axis)
        assert in_plane == pytest.approx(chain.a[1] + np.hypot(chain.a[2], chain.d[3]), abs=1e-9)
    assert arm_of().elbow_straight == 90.0


def test_the_thesiss_robot_is_the_default_and_its_functions_unchanged() -> None:
    sim = Simulator()
    assert sim.arm is thesis_arm() and isinstance(sim.arm, ThesisArm) and sim.base is not None
    assert np.array_equal(sim.base, np.eye(4))
    q = [10.0, -40.0, 120.0, 30.0, 45.0, 60.0]
    for point in (1, 2, 3):
        assert np.array_equal(sim.arm.fk(q, point).xyz, fk(q, point).xyz)
    pose = fk(q)
    assert sim.arm.ik(pose.xyz, pose.rotation, Config(1, 1, 1), q) == pytest.approx(
        __import__("valterm.core.kinematics", fromlist=["ik"]).ik(pose.xyz, pose.rotation, Config(1, 1, 1), q))


def test_grade_takes_the_robot_from_the_task_file(tmp_path: Path) -> None:
    data = Path(__file__).parent / "data" / "grade"
    text = (data / "PICK.toml").read_text()
    (tmp_path / "PICK.toml").write_text(text.replace('name = "PICK"', 'name = "PICK"\nrobot = "PUMA560"'))
    task = read_task(tmp_path / "PICK.toml")
    assert task.robot == "PUMA560"
    verdict = grade(task, data / "students" / "GOOD.DAT")
    assert not verdict.passed and verdict.failures[0].kind == "error"
    assert verdict.failures[0].message == ("GOOD STEP 5: THE APPROACH TO LOCATION A IS BEYOND THE PUMA 560'S "
                                           "STOPS: JOINT 4 BEYOND ITS STOP (177.37 DEG, STOP -110..170)")
    assert grade(read_task(data / "PICK.toml"), data / "students" / "GOOD.DAT").passed  # the thesis's robot
    (tmp_path / "BAD.toml").write_text(text.replace('name = "PICK"', 'name = "PICK"\nrobot = "R2D2"'))
    with pytest.raises(TaskError, match="robot: no robot 'R2D2'"):
        read_task(tmp_path / "BAD.toml")


async def test_the_apps_status_bar_names_the_560(tmp_path: Path) -> None:
    async with Simulation(tmp_path, setup="PROCESS", size=(200, 24), robot="PUMA560") as sim:
        assert "ROBOT PUMA 560" in sim.status()
        assert sim.where().joints == (0.0, 90.0, -90.0, 0.0, 0.0, 0.0)
    async with Simulation(tmp_path, setup="PROCESS", size=(200, 24)) as sim:
        assert "ROBOT" not in sim.status() and "RULES 1985" in sim.status()


def test_cycle_times_come_from_the_robots_own_file() -> None:
    from dataclasses import replace

    from valterm.core.cycletime import robot_timing
    from valterm.core.events import Motion

    sim = Simulator(robot="PUMA560")
    assert sim.timing == robot_timing("PUMA560") and robot_timing("PUMA560").hand_time == 0.2
    assert Simulator().timing == robot_timing()

    def seconds(sim: Simulator) -> float:
        return sum(e.seconds for e in sim.drive(1, 90.0) if isinstance(e, Motion))

    before = seconds(Simulator(robot="PUMA560"))
    slow = Simulator(robot="PUMA560")
    slow.timing = replace(slow.timing, joint_speed=tuple(v / 2 for v in slow.timing.joint_speed),
                          joint_accel=tuple(v / 4 for v in slow.timing.joint_accel))
    assert seconds(slow) == pytest.approx(2 * before) and before > 1.0


def test_serve_starts_every_tabs_app_on_the_chosen_robot() -> None:
    from valterm.cli import build_parser
    from valterm.commands.serve import app_command

    assert app_command(build_parser().parse_args(["--robot", "PUMA560", "serve"])).endswith("--robot PUMA560")
    assert "--robot" not in app_command(build_parser().parse_args(["serve"]))


def test_the_app_is_started_on_the_robot_the_command_line_names(monkeypatch: pytest.MonkeyPatch) -> None:
    started: dict[str, object] = {}

    def run(*args: object, **kwargs: object) -> int:
        started.update(kwargs)
        return 0

    monkeypatch.setattr("valterm.ui.app.run", run)
    assert main(["--robot", "puma560"]) == 0 and started["robot"] == "PUMA560"
    assert main([]) == 0 and started["robot"] is None


def test_a_singular_wrist_on_the_560_keeps_jt4() -> None:
    arm = arm_of("PUMA560")
    for jt5 in (0.0, 180.0):
        q = [10.0, 60.0, -100.0, 0.0, jt5, 70.0]
        pose = arm.fk(q)
        got = arm.ik(pose.xyz, pose.rotation, arm.indicators(q), [10.0, 60.0, -100.0, 35.0, jt5, 0.0],
                     enforce_stops=False)
        assert got[3] == pytest.approx(35.0)
        again = arm.fk(got)
        assert np.allclose(again.xyz, pose.xyz, atol=1e-9) and np.allclose(again.rotation, pose.rotation, atol=1e-9)
    # at a singular wrist (JT5 = 0, JT4 30) a joint move to a pose turned about the tool's axis keeps JT4
    sim = Simulator(robot="PUMA560")
    sim.stand_at([0.0, 90.0, -90.0, 30.0, 0.0, -30.0])
    here = sim.arm.fk(sim.joints)
    turned = sim.arm.fk([0.0, 90.0, -90.0, 0.0, 0.0, 40.0])
    list(sim.move(Location(tuple(float(v) for v in here.xyz - [0, 0, 671.83]),  # type: ignore[arg-type]
                           rotation_to_oat(turned.rotation))))
    assert sim.joints[3] == pytest.approx(30.0) and sim.joints[5] == pytest.approx(10.0)
