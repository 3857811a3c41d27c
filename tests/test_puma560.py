"""The PUMA 560 of the robotics courses (issue 26): `kin fk` / `kin ik --robot PUMA560` agree
with Corke's Robotics Toolbox `Puma560().fkine` / `ikine_a` (1000 seeded poses, all eight
configurations, 1e-6 m and 1e-6 rad), and the thesis's robot stays the default."""

from __future__ import annotations

import io
import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from valterm.cli import main as cli
from valterm.core.dh import RobotFileError, dh_robot, load_dh_robot
from valterm.core.robot_choice import robot_names
from valterm.core.kinematics import oat_to_rotation, rotation_to_oat

CONFIGS = [(arm, elbow, wrist) for arm in ("RIGHTY", "LEFTY") for elbow in ("ABOVE", "BELOW")
           for wrist in ("NOFLIP", "FLIP")]
TOOLBOX_WORD = {"RIGHTY": "r", "LEFTY": "l", "ABOVE": "u", "BELOW": "d", "NOFLIP": "n", "FLIP": "f"}
POSES = 1000


def kin(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], args: list[str],
        lines: list[str]) -> list[dict]:  # type: ignore[type-arg]
    """`valterm kin ...` on one pose a line of standard input: one JSON record a line."""
    capsys.readouterr()
    monkeypatch.setattr(sys, "stdin", io.StringIO("\n".join(lines) + "\n"))
    assert cli(["kin", *args, "--robot", "PUMA560", "--json"]) == 0, capsys.readouterr().err
    return [json.loads(line) for line in capsys.readouterr().out.splitlines()]


def angle_error(a: np.ndarray, b: np.ndarray) -> float:
    """Largest difference of two joint vectors in radians, a turn counting as none."""
    return float(np.abs(np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b))))).max())


def test_kin_agrees_with_the_robotics_toolbox(monkeypatch: pytest.MonkeyPatch,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    models = pytest.importorskip("roboticstoolbox.models.DH")
    puma = models.Puma560()
    rng = np.random.default_rng(560)
    limits = np.degrees(np.array([link.qlim for link in puma.links]))
    joints = rng.uniform(limits[:, 0], limits[:, 1], size=(POSES, 6))
    tools = [puma.fkine(np.radians(q)).A for q in joints]

    # forward: position (m) and rotation of the toolbox's end-effector frame
    got = kin(monkeypatch, capsys, ["fk"], [" ".join(repr(float(v)) for v in q) for q in joints])
    assert len(got) == POSES and {r["robot"] for r in got} == {"PUMA 560"}
    for record, tool in zip(got, tools):
        assert np.abs(np.array(record["xyz"]) / 1000.0 - tool[:3, 3]).max() < 1e-6
        assert np.abs(oat_to_rotation(*record["oat"]) - tool[:3, :3]).max() < 1e-6

    # inverse: every pose in all eight configurations, as ikine_a solves it
    lines, expected = [], []
    for tool in tools:
        xyz = tool[:3, 3] * 1000.0
        oat = rotation_to_oat(tool[:3, :3])
        for config in CONFIGS:
            solution = puma.ikine_a(tool, "".join(TOOLBOX_WORD[w] for w in config))
            assert solution.success, solution.reason
            lines.append(" ".join(repr(float(v)) for v in (*xyz, *oat)) + " " + ",".join(config))
            expected.append(solution.q)
    got = kin(monkeypatch, capsys, ["ik"], lines)
    assert len(got) == len(expected) == 8 * POSES
    worst = max(angle_error(np.radians(r["joints"]), q) for r, q in zip(got, expected))
    assert worst < 1e-6
    # the configuration a pose is shown in is the one that solves back to its joints
    shown = kin(monkeypatch, capsys, ["fk"], [" ".join(repr(float(v)) for v in q) for q in joints[:200]])
    for record, q in zip(shown, joints[:200]):
        config = tuple(record["config"][k] for k in ("arm", "elbow", "wrist"))
        back = puma.ikine_a(puma.fkine(np.radians(q)), "".join(TOOLBOX_WORD[w] for w in config)).q
        assert angle_error(back, np.radians(q)) < 1e-6


def test_the_file_is_the_toolboxs_table_and_the_thesis_robot_stays_the_default(
        capsys: pytest.CaptureFixture[str]) -> None:
    robot = dh_robot("PUMA560")
    assert robot.name == "PUMA 560" and "PUMA560" in robot_names()
    # all joints 0: the "L" of the toolbox's qz, frame 6 at (a2 + a3, -d3, d1 + d4)
    assert np.allclose(robot.fk([0] * 6)[:3, 3], [431.8 + 20.3, -150.05, 671.83 + 431.8])
    assert robot.stops[1] == (-45.0, 225.0) and robot.ready == (0.0, 90.0, -90.0, 0.0, 0.0, 0.0)
    assert cli(["kin", "fk", "--json", "0", "-90", "90", "0", "0", "0"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record["robot"] == "PUMA 600" and record["xyz"] == pytest.approx([0.0, 158.75, 990.6])


def test_ik_then_fk_returns_the_pose_and_the_stops_flag(capsys: pytest.CaptureFixture[str]) -> None:
    robot = dh_robot("PUMA560")
    tool = robot.fk([10, 40, -120, 30, -45, 60])
    oat = rotation_to_oat(tool[:3, :3])
    pose = [repr(float(v)) for v in (*tool[:3, 3], *oat)]
    assert cli(["kin", "ik", "--robot", "PUMA560", "--json", "--config", "RIGHTY,ABOVE,NOFLIP", *pose]) == 0
    joints = json.loads(capsys.readouterr().out)["joints"]
    assert np.allclose(robot.fk(joints), tool, atol=1e-6)
    # a FLIP pose (JT5 60) asked NOFLIP turns JT4 by 180: beyond the 560's stops of -110..170
    tool = robot.fk([0, 45, -90, 0, 60, 0])
    pose = [repr(float(v)) for v in (*tool[:3, 3], *rotation_to_oat(tool[:3, :3]))]
    assert cli(["kin", "ik", "--robot", "PUMA560", "--json", "--config", "RIGHTY,ABOVE,NOFLIP", *pose]) == 0
    captured = capsys.readouterr()
    assert json.loads(captured.out)["beyond_stop"] == 4 and "joint 4 beyond its stop (180.00 deg)" in captured.err


def test_unreachable_and_refused_input(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    assert cli(["kin", "ik", "--robot", "PUMA560", "5000", "0", "0", "0", "90", "0"]) == 1
    assert "out of reach" in capsys.readouterr().err
    assert cli(["kin", "ik", "--robot", "PUMA560", "10", "20", "700", "0", "90", "0"]) == 1
    assert "inside the shoulder offset" in capsys.readouterr().err
    assert cli(["kin", "fk", "--robot", "PUMA9", "0", "0", "0", "0", "0", "0"]) == 2
    assert "no robot 'PUMA9'" in capsys.readouterr().err
    assert cli(["kin", "fk", "--robot", "PUMA560", "--point", "3", "0", "0", "0", "0", "0", "0"]) == 2
    assert "frame 6 only" in capsys.readouterr().err
    bad = tmp_path / "ARM.toml"
    bad.write_text("[dh]\na = [0, 1, 0, 0, 0, 0]\nalpha = [0, 0, 0, 0, 0, 0]\nd = [0, 0, 0, 0, 0, 0]\n"
                   "[stops]\njoints = [[-1, 1]]\n[ready]\njoints = [0, 0, 0, 0, 0, 0]\n")
    with pytest.raises(RobotFileError, match="six entries"):
        load_dh_robot(bad)
    assert not math.isnan(dh_robot("PUMA560").d[0])


def test_the_drawn_560_follows_its_own_chain() -> None:
    from valterm.core.robot import load_robot_model

    model = load_robot_model("PUMA560")
    assert model.chain is not None and model.geometry.ready == (0.0, 90.0, -90.0, 0.0, 0.0, 0.0)
    assert model.names == ("PEDESTAL", "TRUNK", "TRUNK", "UPPER ARM", "FOREARM", "FOREARM", "WRIST", "WRIST",
                           "FLANGE")
    rng = np.random.default_rng(26)
    for q in rng.uniform(-90, 90, size=(20, 6)):
        placed = {p.name: p for p in model.place(q)}
        tool = model.chain.fk(q)
        # the flange: a disc 30..56 mm beyond frame 6 along its z, centred on the axis
        assert np.allclose(placed["FLANGE"].vertices.mean(axis=0), tool[:3, 3] + 43.0 * tool[:3, 2], atol=1e-6)
        # the upper arm spans the shoulder to the elbow: its middle is halfway along a2
        elbow = model.chain.link_frames(q)[0, 2]
        middle = placed["UPPER ARM"].vertices.mean(axis=0)
        along = (middle - elbow[:3, 3]) @ elbow[:3, 0]
        assert -300.0 < along < -130.0
        assert np.allclose(placed["PEDESTAL"].vertices, model.place(np.zeros(6))[0].vertices)
    # the thesis's robot is still the default model
    assert load_robot_model().chain is None and load_robot_model().names[0] == "BASE"


def test_render_draws_the_560_and_runs_programs_on_it(tmp_path: Path,
                                                         capsys: pytest.CaptureFixture[str]) -> None:
    ws = ["--workspace", str(tmp_path)]
    assert cli([*ws, "render", "--size", "60x20", "--json"]) == 0
    thesis = json.loads(capsys.readouterr().out)["lines"]
    assert cli([*ws, "render", "--robot", "PUMA560", "--size", "60x20", "--json"]) == 0
    puma560 = json.loads(capsys.readouterr().out)["lines"]
    assert len(puma560) == 20 and all(len(line) == 60 for line in puma560) and puma560 != thesis
    # JT3 100 is inside the thesis's robot's stops (-45..225), beyond the 560's (-225..45)
    assert cli([*ws, "render", "--size", "60x20", "--joints", "0", "0", "100", "0", "0", "0"]) == 0
    capsys.readouterr()
    assert cli([*ws, "render", "--robot", "PUMA560", "--joints", "0", "0", "100", "0", "0", "0"]) == 2
    assert "joint 3" in capsys.readouterr().err.lower()
    # a traced program moves the 560 itself: PROCESS stops where the 560 cannot follow it
    assert cli([*ws, "render", "--robot", "PUMA560", "--trace", "PROCESS", "--loc", "PROCESS"]) == 1
    assert "beyond the puma 560's stops" in capsys.readouterr().err.lower()
