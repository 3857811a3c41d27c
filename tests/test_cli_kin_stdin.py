"""`valterm kin` with poses on standard input, non-finite numbers, and poses beyond a stop
(issue 10 item 4, issue 13 item 5, issue 16 item 1)."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from valterm.cli import main

FIG_2_8A2 = ["249.46", "494.67", "-550.56", "167.32", "82.94", "158.35"]


def kin(argv: list[str], stdin: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "valterm", "kin", *argv], input=stdin,
                          capture_output=True, text=True, timeout=60)


def test_fk_stdin_skips_blank_and_comment_lines_and_locates_bad_ones() -> None:
    stdin = "\n".join([
        "# JT1..JT6 of Fig. 2-9",     # 1
        "",                             # 2
        "0 0 90 0 0 0   # READY-ish",   # 3
        "   ",                          # 4
        "0 0 90 0 x 0",                 # 5
        "1 2 3",                        # 6
        "0 -90 90 0 0 0",               # 7
    ]) + "\n"
    result = kin(["fk"], stdin)
    assert result.returncode == 1
    assert result.stderr.splitlines() == [
        "valterm: kin fk: line 5: 'x' is not a number",
        "valterm: kin fk: line 6: expected 6 numbers (JT1..JT6), got 3",
    ]
    # two readouts of four lines each, nothing else on stdout
    lines = result.stdout.splitlines()
    assert len(lines) == 8
    assert [float(v) for v in lines[1].split()[1:4]] == pytest.approx([990.60, 158.75, 0.00], abs=0.01)
    assert [float(v) for v in lines[5].split()[1:4]] == pytest.approx([0.00, 158.75, 990.60], abs=0.01)


def test_stdin_all_good_exits_0_with_nothing_on_stderr() -> None:
    result = kin(["fk", "--json"], "# header\n0 -90 90 0 0 0\n\n10 -90 90 0 0 0\n")
    assert result.returncode == 0
    assert result.stderr == ""
    assert len(result.stdout.splitlines()) == 2


def test_only_comments_is_no_failure() -> None:
    result = kin(["ik"], "# nothing to do\n\n")
    assert (result.returncode, result.stdout, result.stderr) == (0, "", "")


@pytest.mark.parametrize("pose", [
    ["0", "inf", "0", "0", "0", "0"],
    ["0", "0", "0", "0", "0", "nan"],
    ["0", "-inf", "1e308", "0", "0", "0"],
])
def test_fk_non_finite_is_a_usage_error_not_a_traceback(pose: list[str], capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["kin", "fk", *pose]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.startswith("valterm: kin fk: ") and "not a usable number" in captured.err
    assert len(captured.err.splitlines()) == 1


def test_ik_non_finite_on_stdin_gives_no_numpy_warning() -> None:
    result = kin(["ik", "--json"], "nan inf 1e308 0 0 0\n1e9 1e9 1e9 1e9 1e9 1e9\n")
    assert result.returncode == 1
    assert "Warning" not in result.stderr and "Traceback" not in result.stderr
    errors = [json.loads(line) for line in result.stdout.splitlines()]
    assert [e["line"] for e in errors] == [1, 2]
    assert "not a usable number" in errors[0]["error"]
    assert errors[1]["error"] == "out of reach"


def test_usage_errors_on_the_command_line_exit_2(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["kin", "fk", "1", "2", "3"]) == 2
    assert capsys.readouterr().err == "valterm: kin fk: expected 6 numbers (JT1..JT6), got 3\n"
    assert main(["kin", "ik", "1", "2", "3", "4", "5", "six"]) == 2
    assert main(["kin", "ik", *FIG_2_8A2, "SIDEWAYS"]) == 2
    assert main(["kin"]) == 2
    assert main(["kin", "fk", "--point", "9", "0", "0", "0", "0", "0", "0"]) == 2


def test_ik_beyond_stop_prints_the_fig_2_8a2_row_flagged(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["kin", "ik", *FIG_2_8A2, "--config", "RIGHTY,BELOW,NOFLIP", "--json"]) == 0
    captured = capsys.readouterr()
    result = json.loads(captured.out)
    assert result["beyond_stop"] == 2
    # the thesis's row (JT1 as corrected in SPEC §2)
    assert result["joints"] == pytest.approx([-100.02, 102.63, 168.66, -0.33, -84.24, -18.99], abs=0.05)
    assert "warning: joint 2 beyond its stop (102.63 deg)" in captured.err


def test_ik_beyond_stop_in_text_warns_on_stderr(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["kin", "ik", "-511.68", "175.40", "-610.00", "52.64", "89.00", "0.00",
                 "--config", "LEFTY,BELOW,NOFLIP"]) == 0
    captured = capsys.readouterr()
    assert [float(v) for v in captured.out.split()] == pytest.approx(
        [144.00, 76.14, 20.87, -179.98, -84.00, 1.36], abs=0.05)
    assert captured.err.startswith("valterm: kin ik: warning: joint 2 beyond its stop")


def test_ik_within_stops_has_no_flag(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["kin", "ik", "338.53", "534.32", "-565.51", "163.19", "42.95", "170.05", "--json"]) == 0
    captured = capsys.readouterr()
    assert "beyond_stop" not in json.loads(captured.out)
    assert captured.err == ""
