"""Issue 40: ``valterm run`` and ``valterm monitor`` write their output in blocks whatever
``PYTHONUNBUFFERED`` says (it made one write() a line: 0.48 M statements/s), line by line to a
person watching (a terminal), and the monitor's answer to each command before the next is read."""

from __future__ import annotations

import math
import os
import select
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from valterm.cli import main
from valterm.core.events import Event, Step, TypeOut
from valterm.core.text.transcript import BLOCK, Blocks, blocks_for, event_lines, write_events

LOOP = "    X=0\n10  X=X+1\n    TYPE X\n    GOTO 10\n"


class Counting:
    """A stream that counts its writes and flushes (as the system calls they would be)."""

    def __init__(self, terminal: bool = False) -> None:
        self.writes: list[str] = []
        self.flushes = 0
        self.terminal = terminal

    def write(self, text: str) -> int:
        self.writes.append(text)
        return len(text)

    def flush(self) -> None:
        self.flushes += 1

    def isatty(self) -> bool:
        return self.terminal


def loop_events(n: int) -> list[Event]:
    steps = [Step("LOOP", 2, "10 X=X+1"), Step("LOOP", 3, "TYPE X")]
    return [event for i in range(n) for event in (steps[i % 2], TypeOut(str(i)))]


def transcript(events: list[Event], as_json: bool) -> str:
    if as_json:
        return "".join(event.json_line() for event in events)
    return "".join(line + "\n" for event in events for line in event_lines(event))


@pytest.mark.parametrize("as_json", [True, False])
def test_lines_are_written_in_blocks_and_are_the_same_lines(as_json: bool) -> None:
    events = loop_events(5000)
    stream = Counting()
    write_events(iter(events), blocks_for(stream), as_json=as_json)  # type: ignore[arg-type]
    assert "".join(stream.writes) == transcript(events, as_json)
    assert len(stream.writes) == math.ceil(len(events) / BLOCK)  # 10 000 lines in 10 writes


def test_a_person_watching_sees_each_event_at_once() -> None:
    events = loop_events(50)
    stream = Counting(terminal=True)
    write_events(iter(events), blocks_for(stream))  # type: ignore[arg-type]
    assert stream.writes == [line + "\n" for event in events for line in event_lines(event)]
    assert stream.flushes == len(events)


def test_what_was_gathered_is_written_when_the_run_breaks_off() -> None:
    def broken() -> Iterator[Event]:
        yield from loop_events(10)
        raise KeyboardInterrupt  # a second CTRL-C

    stream = Counting()
    with pytest.raises(KeyboardInterrupt):
        write_events(broken(), Blocks(stream))
    assert "".join(stream.writes) == transcript(loop_events(10), as_json=False)


@pytest.fixture
def workspace(tmp_path: Path) -> Path:
    (tmp_path / "LOOP.DAT").write_text(LOOP)
    return tmp_path


def test_run_writes_its_transcript_in_blocks(workspace: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    stream = Counting()
    monkeypatch.setattr("sys.stdout", stream)
    assert main(["run", "LOOP", "--workspace", str(workspace), "--max-steps", "6000", "--json"]) == 1  # the limit
    lines = "".join(stream.writes).splitlines()
    assert len(lines) > 7000
    assert len(stream.writes) <= math.ceil(len(lines) / BLOCK) + 1  # the end's line after the last block


def _valterm(*args: str, unbuffered: bool, workspace: Path) -> bytes:
    env = {k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}
    if unbuffered:
        env["PYTHONUNBUFFERED"] = "1"
    done = subprocess.run([sys.executable, "-m", "valterm", *args, "--workspace", str(workspace)],
                          capture_output=True, env=env, timeout=60, check=False)
    assert done.returncode == 1, done.stderr  # stopped by the step limit
    return done.stdout


@pytest.mark.parametrize("mode", [["--json"], []])
def test_the_output_is_the_same_bytes_with_or_without_pythonunbuffered(workspace: Path, mode: list[str]) -> None:
    args = ("run", "LOOP", "--max-steps", "3000", *mode)
    buffered = _valterm(*args, unbuffered=False, workspace=workspace)
    assert buffered.count(b"\n") > 2 * BLOCK
    assert _valterm(*args, unbuffered=True, workspace=workspace) == buffered


def _read_answer(stream: int, until: bytes, seconds: float = 30.0) -> bytes:
    """Read a pipe until `until` has come, within a deadline (a regression fails, not hangs)."""
    data, deadline = b"", time.monotonic() + seconds
    while until not in data:
        left = deadline - time.monotonic()
        assert left > 0 and select.select([stream], [], [], left)[0], f"no answer: {data!r}"
        chunk = os.read(stream, 65536)
        assert chunk, f"the monitor ended: {data!r}"
        data += chunk
    return data


@pytest.mark.parametrize("unbuffered", [False, True])
def test_the_monitor_answers_each_command_before_reading_the_next(workspace: Path, unbuffered: bool) -> None:
    env = {k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}
    if unbuffered:
        env["PYTHONUNBUFFERED"] = "1"
    monitor = subprocess.Popen([sys.executable, "-m", "valterm", "monitor", "--workspace", str(workspace),
                                "--max-steps", "2000"], stdin=subprocess.PIPE, stdout=subprocess.PIPE, env=env)
    assert monitor.stdin is not None and monitor.stdout is not None
    try:
        monitor.stdin.write(b"EXECUTE LOOP\n")
        monitor.stdin.flush()
        answer = _read_answer(monitor.stdout.fileno(), b"RUN LIMIT REACHED: 2000 STEPS")
        assert answer.count(b"LOOP        2  10 X=X+1") == 667  # steps 1, then 2, 3, 4 a pass
        monitor.stdin.write(b"TYPE 42\n")  # sent only once the first answer was read
        monitor.stdin.flush()
        assert b"42" in _read_answer(monitor.stdout.fileno(), b". TYPE 42\n42\n")
        monitor.stdin.close()
        assert monitor.wait(timeout=30) == 1  # the limit is an error
    finally:
        monitor.kill()
        monitor.wait()
