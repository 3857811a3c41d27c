"""Limits on every run (docs/LIMITS.md): steps, robot seconds, output lines; a runaway
``10 GOTO 10`` with a TYPE ends by itself in ``run`` and ``monitor`` with a message naming
the limit, and exit 1."""

from __future__ import annotations

import io
import json
from pathlib import Path

import pytest
from app_helpers import until

from valterm.cli import build_parser, main
from valterm.commands.limits import limits_from
from valterm.core.events import LimitReached, Step, TypeOut
from valterm.core.simulator import Simulator
from valterm.core.val.interpreter import Interpreter, program_from_lines
from valterm.core.val.limits import DEFAULT_LINES, DEFAULT_STEPS, RunLimits

RUNAWAY = ["10  TYPE HELLO", "    GOTO 10"]


def interpreter(lines: list[str], limits: RunLimits | None = None) -> Interpreter:
    program = program_from_lines("LOOP", lines)
    return Interpreter(Simulator(), lambda name: program, {}, limits=limits)


def test_the_default_line_limit_ends_a_runaway_with_an_event_naming_it() -> None:
    events = list(interpreter(RUNAWAY).execute("LOOP"))
    stop = events[-1]
    assert isinstance(stop, LimitReached)
    assert (stop.limit, stop.flag) == ("lines", "--max-lines")
    assert stop.message == f"RUN LIMIT REACHED: {DEFAULT_LINES} LINES OF OUTPUT"
    # each scrolled step is a line and each TYPE one more: the limit is kept to the line
    lines = sum(1 for e in events if isinstance(e, (Step, TypeOut)))
    assert DEFAULT_LINES - 3 <= lines <= DEFAULT_LINES + 1  # + the last TYPE's line


def test_the_step_limit_counts_every_step_across_passes() -> None:
    events = list(interpreter(["    X=1", "    X=2", "    X=3"], RunLimits(steps=10, lines=0)).execute("LOOP", 5))
    assert sum(1 for e in events if isinstance(e, Step)) == 10  # 3 + 3 + 3 + 1, then it stops
    stop = events[-1]
    assert isinstance(stop, LimitReached) and stop.limit == "steps"
    assert (stop.program, stop.step) == ("LOOP", 2)  # the step it did not run


def test_the_robot_time_limit_stops_after_the_motion_that_passes_it() -> None:
    lines = ["10  DELAY 5", "    GOTO 10"]
    events = list(interpreter(lines, RunLimits(seconds=12)).execute("LOOP"))
    stop = events[-1]
    assert isinstance(stop, LimitReached) and stop.limit == "seconds"
    assert stop.message == "RUN LIMIT REACHED: 12 SECONDS OF ROBOT TIME"
    assert sum(1 for e in events if isinstance(e, Step) and e.step == 1) == 3  # 5 + 5 + 5 > 12


def test_no_limit_is_zero_and_a_normal_end_is_not_a_limit() -> None:
    many = interpreter(["    X=X+1"], RunLimits(steps=0, lines=0))
    many.variables["X"] = 0.0
    events = list(many.execute("LOOP", 150_000 // 1))  # 150 000 steps: past 100 000 lines
    assert not any(isinstance(e, LimitReached) for e in events)
    assert many.variables["X"] == 150_000


@pytest.fixture
def runaway(tmp_path: Path) -> Path:
    path = tmp_path / "LOOP.DAT"
    path.write_text("".join(f"{line}\n" for line in RUNAWAY))
    return path


def test_run_ends_a_runaway_at_the_default_limit_with_the_message_and_exit_1(
        runaway: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    status = main(["run", str(runaway), "--workspace", str(tmp_path / "ws")])
    out = capsys.readouterr().out.splitlines()
    assert status == 1
    assert f"*** LOOP STEP 2: RUN LIMIT REACHED: {DEFAULT_LINES} LINES OF OUTPUT (raise it with --max-lines)" in out
    assert len(out) < DEFAULT_LINES + 20  # the transcript, then the final WHERE


def test_run_flags_change_the_limits_and_json_names_the_limit(
        runaway: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    status = main(["run", str(runaway), "--json", "--max-steps", "7", "--workspace", str(tmp_path / "ws")])
    events = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert status == 1
    assert sum(1 for e in events if e["event"] == "step") == 7
    limit = next(e for e in events if e["event"] == "limit")
    assert (limit["limit"], limit["flag"], limit["message"]) == ("steps", "--max-steps", "RUN LIMIT REACHED: 7 STEPS")


def test_monitor_ends_a_runaway_at_the_default_limit_and_exits_1(
        runaway: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    workspace = tmp_path / "ws"
    workspace.mkdir()
    (workspace / "LOOP.DAT").write_text(runaway.read_text())
    monkeypatch.setattr("sys.stdin", io.StringIO("EXECUTE LOOP\nTYPE STILL HERE\n"))
    status = main(["monitor", "--workspace", str(workspace)])
    out = capsys.readouterr().out.splitlines()
    assert status == 1
    stop = out.index(f"*** LOOP STEP 2: RUN LIMIT REACHED: {DEFAULT_LINES} LINES OF OUTPUT (raise it with --max-lines)")
    assert out[stop + 1:] == [". TYPE STILL HERE", "STILL HERE"]  # the prompt goes on


def test_monitor_takes_the_flags_too(runaway: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                     capsys: pytest.CaptureFixture[str]) -> None:
    workspace = tmp_path / "ws"
    workspace.mkdir()
    (workspace / "LOOP.DAT").write_text(runaway.read_text())
    monkeypatch.setattr("sys.stdin", io.StringIO("EXECUTE LOOP\n"))
    assert main(["monitor", "--max-lines", "5", "--workspace", str(workspace)]) == 1
    out = capsys.readouterr().out.splitlines()
    assert out[-1] == "*** LOOP STEP 2: RUN LIMIT REACHED: 5 LINES OF OUTPUT (raise it with --max-lines)"


@pytest.mark.parametrize("argv", [["--max-steps", "5", "run", "X"], ["run", "X", "--max-steps", "5"]])
def test_the_flags_go_before_or_after_the_subcommand_and_the_app_reads_them(argv: list[str]) -> None:
    limits = limits_from(build_parser().parse_args(argv))
    assert limits == RunLimits(steps=5)
    assert limits_from(build_parser().parse_args([])) == RunLimits(DEFAULT_STEPS)  # the app's defaults


@pytest.mark.parametrize("flag, value", [("--max-steps", "-1"), ("--max-lines", "ten"), ("--max-seconds", "nan")])
def test_a_bad_limit_is_a_usage_error(flag: str, value: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", "X", flag, value]) == 2
    assert flag in capsys.readouterr().err


def test_the_app_stops_a_runaway_at_its_limit_and_the_prompt_answers(tmp_path: Path) -> None:
    import asyncio
    import math

    from valterm.core.workspace import Workspace
    from valterm.ui.app import ValtermApp
    from valterm.ui.screens.valmode import ValModeScreen

    workspace = Workspace.open(tmp_path / "ws")
    (workspace.root / "LOOP.DAT").write_text("".join(f"{line}\n" for line in RUNAWAY))

    async def body() -> None:
        # the limits as `valterm --max-steps 30` gives them to the app: every session it opens has them
        app = ValtermApp(workspace.root, "PROCESS", motion_rate=math.inf, limits=RunLimits(steps=30))
        async with app.run_test(size=(120, 40)) as pilot:
            screen = ValModeScreen()
            await app.push_screen(screen)
            await pilot.pause()
            await pilot.press("n", "v", *"EXEC LOOP", "enter")
            await until(pilot, lambda: screen.mode == "command", "the run limit's stop")
            assert screen.mode == "command"
            assert sum(1 for line in screen.transcript if line.startswith("LOOP ")) == 30
            assert "*** LOOP STEP 1: RUN LIMIT REACHED: 30 STEPS (raise it with --max-steps)" in screen.transcript
            assert not screen.interpreter.running

    asyncio.run(body())


@pytest.mark.parametrize("lines", [["    DELAY 100000"], ["    READY", "    DELAY 100000"]])
def test_a_last_step_past_the_robot_time_limit_does_not_escape_it(lines: list[str]) -> None:
    events = list(interpreter(lines, RunLimits(seconds=60)).execute("LOOP"))
    stop = events[-1]
    assert isinstance(stop, LimitReached) and stop.limit == "seconds"
    assert (stop.program, stop.step) == ("LOOP", len(lines))  # the step that passed it
    assert not any("COMPLETED" in getattr(e, "text", "") for e in events)
