"""Session records (issue 38 item 6): ``valterm --record FILE`` keeps every key with its time
and the lines the screens showed, written as it goes (a kill -9 loses nothing written);
``valterm replay FILE`` plays it in the app (the demo's player) to the same files and
transcript."""

from __future__ import annotations

import asyncio
import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from textual import events

from app_helpers import until
from valterm.core.files.errors import FileWriteError
from valterm.core.files.record import RecordError, SessionRecord, read_record

HEADER = {"keys": "modern", "setup": "PROCESS", "rules": None, "robot": None}
PROGRAM = (" MOVE P1", " TYPE REACHED P1", " STOP")


# -- the file ------------------------------------------------------------------------------
def test_a_record_is_a_new_plain_file_never_a_link_a_fifo_or_an_old_record(tmp_path: Path) -> None:
    target = tmp_path / "real.rec"
    link = tmp_path / "link.rec"
    link.symlink_to(target)
    with pytest.raises(FileWriteError, match="symbolic link"):
        SessionRecord(link, HEADER)
    assert not target.exists()
    dangling = tmp_path / "dangling.rec"
    dangling.symlink_to(tmp_path / "nowhere")
    with pytest.raises(FileWriteError, match="symbolic link"):
        SessionRecord(dangling, HEADER)
    fifo = tmp_path / "fifo.rec"
    os.mkfifo(fifo)
    with pytest.raises(FileWriteError, match="not a regular file"):
        SessionRecord(fifo, HEADER)  # refused at once, never blocked on
    old = tmp_path / "old.rec"
    old.write_text("the last session\n")
    with pytest.raises(FileWriteError, match="never written over"):
        SessionRecord(old, HEADER)
    assert old.read_text() == "the last session\n"


def test_written_line_by_line_and_read_back(tmp_path: Path) -> None:
    path = tmp_path / "s.rec"
    now = [100.0]
    record = SessionRecord(path, HEADER, clock=lambda: now[0])
    now[0] = 101.25
    record.key("e", "e", False)
    assert path.read_text().count("\n") == 2  # on disk before anything closes it
    record.shown(["SETUP FILE PROCESS.SET WITH 14 PARTS"])
    now[0] = 102.5
    record.key("enter", "\r", True)
    assert oct(path.stat().st_mode & 0o777) == "0o600"  # a student's keys are private
    lines = [json.loads(line) for line in path.read_text().splitlines()]
    assert lines[0]["valterm"] == "record" and lines[0]["setup"] == "PROCESS"
    assert lines[1] == {"t": 1.25, "key": "e", "char": "e", "busy": False}
    back = read_record(path)
    assert [(k.at, k.key, k.char, k.busy) for k in back.keys] == [(1.25, "e", "e", False), (2.5, "enter", "\r", True)]
    assert back.lines == ["SETUP FILE PROCESS.SET WITH 14 PARTS"] and back.ended is None  # not closed: cut off
    with path.open("a") as handle:
        handle.write('{"t": 3.0, "key": "x", "ch')  # killed in the middle of a line
    assert len(read_record(path).keys) == 2
    record.close(0)


def test_a_program_printing_for_hours_fills_no_disk(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from valterm.core.files import record as module

    monkeypatch.setattr(module, "MAX_LINES_BYTES", 2000)
    monkeypatch.setattr(module, "MAX_BYTES", 4000)
    path = tmp_path / "loop.rec"
    record = SessionRecord(path, HEADER)
    for _ in range(100):
        record.shown(["HELLO FROM A LOOP"] * 10)
    assert 2000 < path.stat().st_size < 2500 and path.read_text().count('"cut"') == 1
    record.key("ctrl+c", "\x03", True)  # the keys go on
    assert read_record(path).keys[-1].key == "ctrl+c"
    for _ in range(1000):
        record.key("a", "a", False)
    assert path.stat().st_size < 4100


def test_a_full_disk_stops_the_record_not_the_session(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    record = SessionRecord(tmp_path / "full.rec", HEADER)

    def full(fd: int, data: bytes) -> int:
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "write", full)
    record.key("e", "e", False)  # no exception reaches the app
    record.shown(["A LINE"])
    monkeypatch.undo()
    record.close(0)
    assert record.failure == f"{tmp_path / 'full.rec'}: recording stopped: No space left on device"
    assert read_record(tmp_path / "full.rec").keys == []


def test_a_bad_record_is_refused_with_its_line(tmp_path: Path) -> None:
    path = tmp_path / "bad.rec"
    path.write_text('{"valterm": "record", "version": 1}\n{"t": 1, "key": "e"}\nnot json\n')
    with pytest.raises(RecordError, match=r"bad.rec:3: is not a JSON object"):
        read_record(path)
    path.write_text('{"hello": 1}\n')
    with pytest.raises(RecordError, match=r"bad.rec:1: is not a valterm record"):
        read_record(path)
    os.mkfifo(tmp_path / "fifo.rec")
    with pytest.raises(RecordError, match=r"is a FIFO \(a named pipe\), not a record file"):
        read_record(tmp_path / "fifo.rec")


# -- record in the app, replay in the app ------------------------------------------------------
async def _student(app, pilot) -> None:  # type: ignore[no-untyped-def]
    """A session from MAIN MENU: a program typed and saved in the editor, a point taught in
    VAL-II mode (DRIVE, HERE), the program run."""
    async def line(text: str) -> None:
        await pilot.press(*text, "enter")

    await pilot.pause()
    await pilot.press("e")
    await line("EDIT GOP")
    await pilot.press("c")
    await line(PROGRAM[0])
    app.post_message(events.Paste(PROGRAM[1]))  # a step pasted, not typed (as the driver posts it)
    await pilot.pause()
    await pilot.press("enter")
    await line(PROGRAM[2])
    await pilot.press("escape", "s", "e")
    await pilot.press("v", "v")
    for command in ("DRIVE 1,-30,50", "HERE P1", "READY", "EXEC GOP,1"):
        await line(command)
    await until(pilot, lambda: not app.moving and not app.keys_waiting, "the program's end")


def _files(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())
            if p.is_file() and not p.name.startswith(".")}


def test_a_recorded_session_replays_to_the_same_files_and_transcript(tmp_path: Path) -> None:
    from valterm.ui.app import ValtermApp
    from valterm.ui.replay import ReplayApp

    record_path, replayed_path = tmp_path / "student.rec", tmp_path / "replayed.rec"

    async def record() -> None:
        app = ValtermApp(tmp_path / "student", "PROCESS", motion_rate=math.inf)
        app.recorder = SessionRecord(record_path, HEADER)
        async with app.run_test(size=(120, 40)) as pilot:
            await _student(app, pilot)
            await pilot.press("ctrl+q", "y")  # P1 not saved: EXIT WITHOUT SAVING (Y/N)? Y
            await until(pilot, lambda: app.return_code is not None, "the student's exit")
        app.recorder.close(0)

    async def replay() -> None:
        app = ReplayApp(read_record(record_path), "student.rec", speed=1000.0, once=False,
                        workspace=tmp_path / "replay", motion_rate=math.inf)
        app.recorder = SessionRecord(replayed_path, HEADER)  # what the replay showed
        async with app.run_test(size=(120, 40)) as pilot:
            await until(pilot, lambda: app.finished, "the end of the record", limit=60.0)
            await pilot.pause()
            # the student's exit ends the record, not the replay: the instructor stays
            assert "END OF THE RECORD student.rec: the student left the simulator here" in app.caption
            assert app.is_running and app.return_code is None
        app.recorder.close(0)

    asyncio.run(record())
    student = read_record(record_path)
    assert ". HERE P1" in student.lines and "REACHED P1" in student.lines
    assert "PROGRAM GOP COMPLETED: 1 LOOP" in student.lines
    assert student.keys[0].key == "e" and [k.key for k in student.keys[-2:]] == ["ctrl+q", "y"]
    asyncio.run(replay())
    replayed = read_record(replayed_path)
    assert [(k.key, k.char, k.paste) for k in replayed.keys] == [(k.key, k.char, k.paste) for k in student.keys]
    assert [k.paste for k in student.keys if k.paste] == [PROGRAM[1]]
    assert replayed.lines == student.lines
    written = _files(tmp_path / "student")
    assert b"MOVE P1" in written["GOP.DAT"] and "CHECK.DAT" in written
    assert _files(tmp_path / "replay") == written


# -- the command line ----------------------------------------------------------------------------
def _valterm(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "valterm", *args], capture_output=True, text=True,
                          cwd=cwd, timeout=60, stdin=subprocess.DEVNULL)


def test_the_command_line_refuses_a_linked_record_and_an_unreadable_replay(tmp_path: Path) -> None:
    (tmp_path / "elsewhere").write_text("precious\n")
    (tmp_path / "s.rec").symlink_to(tmp_path / "elsewhere")
    result = _valterm("--record", str(tmp_path / "s.rec"), "--workspace", str(tmp_path / "ws"), cwd=tmp_path)
    assert result.returncode == 1, result.stderr
    assert "s.rec: is a symbolic link" in result.stderr and "Traceback" not in result.stderr
    assert (tmp_path / "elsewhere").read_text() == "precious\n"
    result = _valterm("replay", str(tmp_path / "none.rec"), cwd=tmp_path)
    assert result.returncode == 1 and "none.rec: no such record file" in result.stderr
    result = _valterm("replay", str(tmp_path / "s.rec"), "--speed", "0", cwd=tmp_path)
    assert result.returncode == 2 and "--speed" in result.stderr


@pytest.mark.skipif(not hasattr(os, "login_tty"), reason="needs a POSIX terminal")
def test_a_record_survives_kill_9(tmp_path: Path) -> None:
    path = tmp_path / "killed.rec"
    master, slave = os.openpty()
    env = dict(os.environ, TERM="xterm-256color")
    process = subprocess.Popen([sys.executable, "-m", "valterm", "--record", str(path), "--workspace",
                                str(tmp_path / "ws"), "--setup", "PROCESS", "--max-steps", "500"],
                               env=env, preexec_fn=lambda: os.login_tty(slave), close_fds=True)
    os.close(slave)

    def wait_for(text: str) -> None:
        end = time.monotonic() + 30
        while not (path.exists() and text in path.read_text()):
            assert time.monotonic() < end, f"{text!r} never recorded: {path.read_text() if path.exists() else ''}"
            try:
                os.read(master, 65536)  # the terminal is read, as a person's is
            except OSError:
                pass
            time.sleep(0.05)

    try:
        wait_for("SETUP FILE PROCESS.SET")
        os.write(master, b"V")
        wait_for('"key": "V"')
        time.sleep(0.3)
        os.write(master, b"V")
        time.sleep(0.3)
        os.write(master, b"HERE P1\r")
        wait_for(". HERE P1")
        process.send_signal(signal.SIGKILL)
        assert process.wait(timeout=10) == -signal.SIGKILL
    finally:
        if process.poll() is None:
            process.kill()
        os.close(master)
    record = read_record(path)
    assert "".join(k.char or "" for k in record.keys).endswith("HERE P1\r")
    assert ". HERE P1" in record.lines and record.ended is None
    assert record.header["setup"] == "PROCESS" and record.header["keys"] == "modern"
    assert record.header["limits"]["steps"] == 500


def test_a_replay_starts_as_the_session_did(tmp_path: Path) -> None:
    from valterm.core.files.record import Record
    from valterm.core.val.limits import RunLimits
    from valterm.ui.replay import ReplayApp

    header = {"keys": "1985", "setup": "CONV", "rules": "controller", "limits": {"steps": 7, "seconds": 2.5, "lines": 9}}
    app = ReplayApp(Record(header), "s.rec", workspace=tmp_path)
    assert (app.keys_1985, app.initial_setup, app.rules) == (True, "CONV", "controller")
    assert app.limits == RunLimits(7, 2.5, 9) and app.workspace_root == tmp_path
    odd = {"keys": "qwerty", "setup": 5, "rules": "1984", "limits": {"steps": "many"}}
    app = ReplayApp(Record(odd), "s.rec")
    assert (app.keys_1985, app.initial_setup, app.rules, app.limits) == (False, None, None, None)
