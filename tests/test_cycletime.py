"""Cycle time: the real PUMA's time for each motion and the whole program (issue 13 item 3)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from valterm.cli import main
from valterm.core.cycletime import joint_motion_seconds, robot_timing, straight_motion_seconds, trapezoid_seconds


def test_trapezoid_cruises_when_long_and_is_a_triangle_when_short() -> None:
    # 100 deg at 50 deg/s, 100 deg/s^2: 0.5 s up, 1.5 s cruising, 0.5 s down
    assert trapezoid_seconds(100.0, 50.0, 100.0) == pytest.approx(2.5)
    # 4 deg never reaches 50 deg/s: 2 sqrt(4 / 100)
    assert trapezoid_seconds(4.0, 50.0, 100.0) == pytest.approx(0.4)
    assert trapezoid_seconds(0.0, 50.0, 100.0) == 0.0


def test_the_slowest_joint_governs_and_speed_time_scales() -> None:
    timing = robot_timing()
    start = np.zeros(6)
    goal = np.array([90.0, 0.0, 0.0, 90.0, 0.0, 0.0])  # JT1 is slower than JT4
    jt1 = trapezoid_seconds(90.0, timing.joint_speed[0], timing.joint_accel[0])
    assert joint_motion_seconds(start, goal, 100.0) == pytest.approx(jt1)
    assert joint_motion_seconds(start, goal, 50.0) == pytest.approx(2 * jt1)


def test_a_straight_line_runs_at_the_tool_speed() -> None:
    timing = robot_timing()
    expected = trapezoid_seconds(400.0, timing.tool_speed, timing.tool_accel)
    assert straight_motion_seconds(400.0, 0.0, 100.0) == pytest.approx(expected)
    assert straight_motion_seconds(400.0, 0.0, 25.0) == pytest.approx(4 * expected)


def _run(tmp_path: Path, name: str, body: str, capsys: pytest.CaptureFixture[str]) -> list[dict]:
    ws = tmp_path / "ws"
    assert main(["--workspace", str(ws), "cell", "show", "PROCESS.SET"]) == 0  # seeds the workspace
    (ws / f"{name}.DAT").write_text("".join(f"    {line}\n" for line in body.splitlines()))
    capsys.readouterr()
    assert main(["--workspace", str(ws), "run", name, "--cell", "PROCESS", "--loc", "PROCESS", "--json"]) == 0
    return [json.loads(line) for line in capsys.readouterr().out.splitlines()]


MOTIONS = "LEFTY\nABOVE\nMOVE A\nDEPARTS 100\nMOVES E\nMOVES F\nDEPARTS 200\nAPPROS C, -50\nMOVES C\nREADY\n"


def test_cycle_time_doubles_from_speed_100_to_50(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    fast = _run(tmp_path / "a", "FAST", "SPEED 100\n" + MOTIONS, capsys)
    slow = _run(tmp_path / "b", "SLOW", "SPEED 50\n" + MOTIONS, capsys)
    assert fast[-1]["event"] == "end" and fast[-1]["cycle_time_s"] > 1.0
    assert slow[-1]["cycle_time_s"] / fast[-1]["cycle_time_s"] == pytest.approx(2.0, rel=0.25)
    motions = [e for e in fast if e["event"] == "motion"]
    assert all(e["seconds"] > 0 for e in motions)
    assert sum(e["seconds"] for e in motions) == pytest.approx(fast[-1]["cycle_time_s"], abs=0.01)


def test_delay_adds_exactly_its_time(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    plain = _run(tmp_path / "a", "PLAIN", MOTIONS, capsys)
    waits = _run(tmp_path / "b", "WAITS", MOTIONS + "DELAY 2.5\n", capsys)
    assert waits[-1]["cycle_time_s"] - plain[-1]["cycle_time_s"] == pytest.approx(2.5, abs=0.002)


def test_process_cycle_time_counts_the_hand(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--workspace", str(tmp_path / "ws"), "run", "PROCESS", "--json"]) == 0
    events = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    motions = sum(e["seconds"] for e in events if e["event"] == "motion")
    hands = sum(1 for e in events if e["event"] == "hand")
    delays = sum(e["seconds"] for e in events if e["event"] == "delay")
    expected = motions + hands * robot_timing().hand_time + delays
    assert events[-1]["cycle_time_s"] == pytest.approx(expected, abs=0.002)
