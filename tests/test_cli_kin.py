"""The `valterm kin` command-line contract (issue 2 item 5)."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from valterm.cli import main


def run(argv: list[str], stdin: str = "") -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "valterm", *argv], input=stdin,
                          capture_output=True, text=True, timeout=60)


def test_fk_prints_the_fig_2_8_layout(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["kin", "fk", "-108.02", "172.08", "19.34", "-1.52", "35.64", "-9.54"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].split() == ["OPENED", "XW", "YW", "ZW", "O", "A", "T"]
    assert lines[1].split()[0] == "RIGHTY"
    assert [float(v) for v in lines[1].split()[1:4]] == pytest.approx([338.53, 534.32, -565.51], abs=0.2)
    assert lines[2].split() == ["ABOVE", "JT1", "JT2", "JT3", "JT4", "JT5", "JT6"]
    assert lines[3].split()[0] == "NOFLIP"


def test_fk_json_with_point_option(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["kin", "fk", "0", "-90", "90", "0", "0", "0", "--point", "3", "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["xyz"] == pytest.approx([0.0, 158.75, 990.6 + 50.8])
    assert result["oat"] == pytest.approx([90.0, -90.0, 0.0])
    assert set(result["config"]) == {"arm", "elbow", "wrist"}
    assert result["joints"] == [0.0, -90.0, 90.0, 0.0, 0.0, 0.0]


def test_ik_negative_numbers_need_no_double_dash(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["kin", "ik", "-537.29", "61.79", "-610.00", "65.00", "89.00", "0.00",
                 "--config", "LEFTY,ABOVE,NOFLIP", "--json"])
    assert code == 0
    joints = json.loads(capsys.readouterr().out)["joints"]
    assert joints == pytest.approx([156.36, 8.18, 159.13, -179.90, -13.68, 1.27], abs=0.05)


def test_ik_failure_exits_1_with_reason_and_joint(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["kin", "ik", "3000", "0", "0", "0", "0", "0", "--json"]) == 1
    captured = capsys.readouterr()
    assert json.loads(captured.out) == {"error": "out of reach", "joint": 0}
    assert captured.err == "valterm: kin ik: out of reach\n"


def test_batch_from_standard_input_one_result_per_line() -> None:
    lines = "\n".join([
        "338.53 534.32 -565.51 163.19 42.95 170.05",
        "not a pose",
        "-511.68, 175.40, -610.00, 52.64, 89.00, 0.00 LEFTY,BELOW,NOFLIP",
        "-537.29 61.79 -610.00 65.00 89.00 0.00 LEFTY,ABOVE,NOFLIP",
    ]) + "\n"
    result = run(["kin", "ik", "--json"], lines)
    assert result.returncode == 1  # line 2 failed
    out = [json.loads(line) for line in result.stdout.splitlines()]
    assert len(out) == 4
    # Fig. 2-8a1's JT2 172.08 printed as the figure prints it (the 1985 rules, SPEC §3a); the
    # controller's rules print its equivalent inside the stop -225..45
    assert out[0]["joints"] == pytest.approx([-108.02, 172.08, 19.34, -1.52, 35.64, -9.54], abs=0.02)
    controller = json.loads(run(["--rules", "controller", "kin", "ik", "--json"], lines).stdout.splitlines()[0])
    assert controller["joints"] == pytest.approx([-108.02, 172.08 - 360.0, 19.34, -1.52, 35.64, -9.54], abs=0.05)
    assert out[1]["line"] == 2 and "expected 6 numbers" in out[1]["error"]
    # Fig. 2-8c: the geometric solution, flagged (JT2 is beyond its stop)
    assert out[2]["beyond_stop"] == 2
    assert out[2]["joints"] == pytest.approx([144.00, 76.14, 20.87, -179.98, -84.00, 1.36], abs=0.05)
    assert out[3]["config"] == {"arm": "LEFTY", "elbow": "ABOVE", "wrist": "NOFLIP"}
    assert result.stderr.splitlines()[0] == "valterm: kin ik: line 2: expected 6 numbers (X Y Z O A T), got 3"


def test_fk_batch_many_poses_in_one_call() -> None:
    stdin = "\n".join(f"{i % 150} -90 90 0 {i % 90} 0" for i in range(2000)) + "\n"
    result = run(["kin", "fk", "--json"], stdin)
    assert result.returncode == 0
    rows = result.stdout.splitlines()
    assert len(rows) == 2000
    assert json.loads(rows[0])["xyz"] == pytest.approx([0.0, 158.75, 990.6])


def test_bad_config_word_is_a_clear_error(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["kin", "ik", "1", "2", "3", "4", "5", "6", "--config", "SIDEWAYS"]) == 2
    assert "SIDEWAYS" in capsys.readouterr().err
