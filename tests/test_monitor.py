"""``valterm monitor``: the VAL-II prompt fed from a pipe, with the debugger commands."""

from __future__ import annotations

import io
import json
import re
from pathlib import Path

import pytest

from valterm.cli import main
from valterm.core.kinematics import Location, fk, rotation_to_oat
from valterm.core.val.interpreter import program_from_lines
from valterm.core.workspace import Workspace


def monitor(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], workspace: Path,
            lines: list[str], *options: str) -> tuple[int, list[str]]:
    """Run ``valterm monitor`` on `lines` piped in; its exit status and its output lines."""
    monkeypatch.setattr("sys.stdin", io.StringIO("".join(f"{line}\n" for line in lines)))
    status = main(["monitor", "--workspace", str(workspace), *options])
    return status, capsys.readouterr().out.splitlines()


def after(lines: list[str], command: str) -> list[str]:
    """The output of one echoed command: the lines after `. command` up to the next command."""
    start = lines.index(f". {command}") + 1
    end = next((i for i in range(start, len(lines)) if lines[i].startswith(". ")), len(lines))
    return lines[start:end]


def steps(lines: list[str], program: str) -> list[int]:
    return [int(m.group(1)) for m in (re.match(rf"{program}\s+(\d+)  ", line) for line in lines) if m]


@pytest.fixture
def workspace(tmp_path: Path) -> Path:
    Workspace.open(tmp_path / "ws")  # seeded with the thesis's cells and programs
    return tmp_path / "ws"


def test_a_breakpoint_stops_before_its_step_xstep_runs_exactly_it_proceed_completes(
        monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], workspace: Path) -> None:
    status, out = monitor(monkeypatch, capsys, workspace,
                          ["BPT PROCESS,8", "EXECUTE PROCESS", "XSTEP", "PROCEED"], "--setup", "PROCESS")
    assert status == 0
    assert after(out, "BPT PROCESS,8") == ["BREAKPOINT SET AT PROCESS STEP 8"]
    run = after(out, "EXECUTE PROCESS")
    assert steps(run, "PROCESS") == [3, 4, 5, 6, 7]  # steps 1-2 are comments
    assert run[-1] == "BREAKPOINT BEFORE PROCESS STEP 8: MOVE A"
    stepped = after(out, "XSTEP")
    assert steps(stepped, "PROCESS") == [8]
    assert stepped[-1] == "XSTEP: PAUSED BEFORE PROCESS STEP 9: CLOSEI 50"
    rest = after(out, "PROCEED")
    assert steps(rest, "PROCESS") == list(range(9, 36))
    assert rest[-1] == "PROGRAM PROCESS COMPLETED: 1 LOOP"


def test_the_monitor_prints_the_same_transcript_as_run(
        monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], workspace: Path) -> None:
    status, out = monitor(monkeypatch, capsys, workspace, ["EXECUTE PROCESS", "STATUS"], "--setup", "PROCESS")
    assert status == 0
    assert main(["--workspace", str(workspace), "run", "PROCESS", "--json"]) == 0
    events = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert main(["--workspace", str(workspace), "run", "PROCESS"]) == 0
    ran = capsys.readouterr().out.splitlines()
    transcript = after(out, "EXECUTE PROCESS")
    assert transcript == ran[:len(transcript)]
    # STATUS keeps its line and adds the cycle time: the whole run's (it has ended), as `run` ends with
    speed, rules, cycle = after(out, "STATUS")
    assert speed == "SPEED 100  PROGRAM PROCESS  LOOPS COMPLETED 1  REMAINING 0"
    assert rules.startswith("RULES 1985 (THE THESIS")  # the rules the verdicts followed (SPEC §3a)
    assert cycle == f"CYCLE TIME {events[-1]['cycle_time_s']:.2f} S (ESTIMATE FOR THE REAL PUMA)"
    assert events[-1]["cycle_time_s"] > 2.0  # two DELAY 1 and the motions


def _write(workspace: Path, name: str, lines: list[str]) -> None:
    Workspace.open(workspace).write_program(program_from_lines(name, lines))


def test_sstep_runs_a_call_as_one_step_xstep_goes_into_it(
        monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], workspace: Path) -> None:
    _write(workspace, "MAIN", ["    K=1", "    CALL SUB", "    K=K+1", "    TYPE K="])
    _write(workspace, "SUB", ["    K=K+10", "    TYPE K=", "    RETURN"])
    status, out = monitor(monkeypatch, capsys, workspace, ["SSTEP MAIN", "SSTEP", "PROCEED"])
    assert status == 0
    first = after(out, "SSTEP MAIN")
    assert steps(first, "MAIN") == [1] and first[-1] == "SSTEP: PAUSED BEFORE MAIN STEP 2: CALL SUB"
    over = after(out, "SSTEP")
    assert steps(over, "MAIN") == [2] and steps(over, "SUB") == [1, 2, 3]
    assert "K = 11" in over and over[-1] == "SSTEP: PAUSED BEFORE MAIN STEP 3: K=K+1"
    assert after(out, "PROCEED")[-2:] == ["K = 12", "PROGRAM MAIN COMPLETED: 1 LOOP"]

    status, out = monitor(monkeypatch, capsys, workspace, ["XSTEP MAIN,2", "XSTEP", "XSTEP", "PROCEED"])
    assert status == 0
    assert after(out, "XSTEP MAIN,2")[-1] == "XSTEP: PAUSED BEFORE SUB STEP 1: K=K+10"  # started at step 2
    into = out[out.index(". XSTEP") + 1:]
    assert into[:2] == ["SUB         1  K=K+10", "XSTEP: PAUSED BEFORE SUB STEP 2: TYPE K="]


def test_watch_reports_each_change_with_old_and_new_value_and_trace_the_assignments(
        monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], workspace: Path) -> None:
    _write(workspace, "COUNT", ["    N=1", "    M=5", "    N=N+2", "    TYPE N=", "    PAUSE", "    N=N*2"])
    status, out = monitor(monkeypatch, capsys, workspace, [
        "WATCH N", "WATCH", "TRACE ON", "EXECUTE COUNT", "N=10", "TRACE OFF", "PROCEED", "WATCH -N", "WATCH"])
    assert status == 0
    assert after(out, "WATCH N") == ["WATCHING N = UNDEFINED"]
    run = after(out, "EXECUTE COUNT")
    assert [line for line in run if line.startswith("WATCH")] == [
        "WATCH N: UNDEFINED -> 1 (COUNT STEP 1)", "WATCH N: 1 -> 3 (COUNT STEP 3)"]
    assert [line for line in run if line.startswith("TRACE")] == [
        "TRACE COUNT       1  N=1   [N=1]", "TRACE COUNT       2  M=5   [M=5]",
        "TRACE COUNT       3  N=N+2   [N=3]", "TRACE COUNT       4  TYPE N="]
    # a value typed while paused is told as typed; the program's change after it, from 10
    assert after(out, "PROCEED")[:3] == ["WATCH N: 3 -> 10 (TYPED)", "COUNT       6  N=N*2",
                                         "WATCH N: 10 -> 20 (COUNT STEP 6)"]
    assert not any(line.startswith("TRACE") for line in after(out, "PROCEED"))
    assert after(out, "WATCH -N") == ["N NO LONGER WATCHED"]
    assert out[-1] == "NO VARIABLES ARE WATCHED"


def test_autoconfig_on_lets_a_move_through_that_the_user_configuration_refuses(
        monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], workspace: Path) -> None:
    # Fig. 2-8a2: RIGHTY BELOW puts JT2 at 102.63, beyond its stop (SPEC section 2)
    pose = fk([-100.02, 102.63, 168.66, -0.33, -84.24, -18.99])
    target = Location(tuple(float(v) for v in pose.xyz), rotation_to_oat(pose.rotation))
    Workspace.open(workspace).write_locations("FAR", {"T": target})
    status, out = monitor(monkeypatch, capsys, workspace,
                          ["BELOW", "MOVE T", "AUTOCONFIG ON", "MOVE T", "WHERE", "AUTOCONFIG OFF"], "--loc", "FAR")
    assert status == 1  # the first MOVE failed
    assert after(out, "MOVE T")[0].startswith("*** ") and "JOINT 2" in after(out, "MOVE T")[0].upper()
    assert after(out, "AUTOCONFIG ON") == ["AUTOCONFIG ON"]
    moved = out[out.index(". AUTOCONFIG ON") + 2:out.index(". WHERE")]
    assert moved[0] == ". MOVE T" and moved[1].startswith("AUTOCONFIG: USING ")
    assert not any(line.startswith("***") for line in moved)
    where = after(out, "WHERE")
    assert [float(v) for v in where[1].split()[1:4]] == pytest.approx([float(v) for v in pose.xyz], abs=0.01)
    assert after(out, "AUTOCONFIG OFF") == ["AUTOCONFIG OFF"]


@pytest.mark.parametrize(("lines", "status"), [
    ([], 0),
    (["SPEED 50", "", "STATUS"], 0),
    (["FROB"], 1),                                  # not a command
    (["PROCEED"], 1),                               # nothing is paused
    (["BPT PROCESS,1"], 1),                         # a comment step
    (["BPT -PROCESS,9"], 1),                        # no such breakpoint
    (["BPT PROCESS,9", "EXECUTE PROCESS"], 1),      # paused at the end of the input: aborted
])
def test_the_end_of_the_input_ends_the_monitor_with_0_or_1_if_a_command_failed(
        monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], workspace: Path,
        lines: list[str], status: int) -> None:
    got, out = monitor(monkeypatch, capsys, workspace, lines, "--setup", "PROCESS")
    assert got == status
    assert not any("Traceback" in line for line in out)
    if lines[-1:] == ["EXECUTE PROCESS"]:
        assert out[-1] == "*** PROCESS STEP 9: ABORTED"


def test_a_bad_setup_is_exit_2_with_its_reason(
        monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], workspace: Path) -> None:
    monkeypatch.setattr("sys.stdin", io.StringIO("WHERE\n"))
    assert main(["monitor", "--workspace", str(workspace), "--setup", "NOSUCH"]) == 2
    assert "NOSUCH" in capsys.readouterr().err.upper()
