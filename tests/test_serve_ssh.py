"""docs/valterm-login.sh, the ForceCommand of the SSH recipe (docs/SERVING.md): it refuses to
start without a terminal (``ssh -T``), starts the simulator on $HOME/valterm with a terminal,
and the simulator ends when the client leaves (the terminal hangs up)."""

from __future__ import annotations

import os
import re
import select
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
WRAPPER = ROOT / "docs" / "valterm-login.sh"
LIMIT = 60.0  # seconds any step may take before the test fails (a guard, not a timing)

pytestmark = pytest.mark.skipif(not hasattr(os, "login_tty"), reason="needs a POSIX terminal")


def fake_valterm(tmp_path: Path, body: str) -> Path:
    script = tmp_path / "valterm"
    script.write_text("#!/bin/sh\n" + body + "\n")
    script.chmod(0o755)
    return script


def on_terminal(argv: list[str], env: dict[str, str], hangup_ignored: bool = False) -> tuple[subprocess.Popen[bytes], int]:
    """``argv`` as an SSH session runs it: a new session whose controlling terminal is a pty
    (``hangup_ignored``: started by a parent that ignores SIGHUP, which exec passes on)."""
    master, slave = os.openpty()

    def session() -> None:
        if hangup_ignored:
            signal.signal(signal.SIGHUP, signal.SIG_IGN)
        os.login_tty(slave)

    process = subprocess.Popen(argv, env=env, preexec_fn=session, close_fds=True)
    os.close(slave)
    return process, master


def read_until(master: int, needle: bytes) -> bytes:
    seen = b""
    end = time.monotonic() + LIMIT
    while needle not in seen:
        if time.monotonic() > end:
            pytest.fail(f"{needle!r} never appeared: {seen[-400:]!r}")
        ready, _, _ = select.select([master], [], [], 0.5)
        if ready:
            try:
                seen += os.read(master, 65536)
            except OSError:
                break
    return seen


def test_refuses_without_a_terminal(tmp_path: Path) -> None:
    marker = tmp_path / "started"
    env = dict(os.environ, HOME=str(tmp_path), VALTERM=str(fake_valterm(tmp_path, f"touch {marker}")))
    result = subprocess.run([str(WRAPPER)], stdin=subprocess.DEVNULL, capture_output=True, text=True,
                            env=env, timeout=LIMIT)
    assert result.returncode == 1
    assert "needs a terminal" in result.stderr and "ssh -t" in result.stderr
    assert not marker.exists()


def test_refuses_a_simulator_that_does_not_start(tmp_path: Path) -> None:
    """Executable is not enough (an unreadable venv interpreter): the wrapper starts it once
    (--version) and says so, rather than a screen that dies at once."""
    marker = tmp_path / "started"
    valterm = fake_valterm(tmp_path, f'[ "$1" = --version ] && exit 127; touch {marker}')
    env = dict(os.environ, HOME=str(tmp_path), VALTERM=str(valterm))
    process, master = on_terminal([str(WRAPPER)], env)
    try:
        said = read_until(master, b"ask the administrator")
        assert process.wait(timeout=LIMIT) == 1
    finally:
        os.close(master)
    assert b"does not start" in said and b"--version" in said
    assert not marker.exists()


def test_starts_the_simulator_on_the_users_workspace(tmp_path: Path) -> None:
    seen = tmp_path / "seen"
    valterm = fake_valterm(tmp_path, f'echo "$@" > {seen}; umask >> {seen}; echo "$TEXTUAL_FPS" >> {seen}')
    env = dict(os.environ, HOME=str(tmp_path), VALTERM=str(valterm))
    process, master = on_terminal([str(WRAPPER)], env)
    try:
        assert process.wait(timeout=LIMIT) == 0
    finally:
        os.close(master)
    args, umask, fps = seen.read_text().splitlines()
    workspace, record = args.split()[:2], args.split()[2:]
    assert workspace == ["--workspace", f"{tmp_path}/valterm"] and (umask, fps) == ("0077", "20")
    # every login is recorded (issue 38 item 6), outside the workspace, under a name of its own
    assert record[0] == "--record" and re.fullmatch(
        rf"{tmp_path}/valterm-records/\d{{4}}-\d\d-\d\d-\d{{6}}-\d+\.rec", record[1]), record
    assert (tmp_path / "valterm-records").is_dir() and not Path(record[1]).exists()  # the app makes it


def test_recording_can_be_turned_off(tmp_path: Path) -> None:
    seen = tmp_path / "seen"
    valterm = fake_valterm(tmp_path, f'echo "$@" > {seen}')
    env = dict(os.environ, HOME=str(tmp_path), VALTERM=str(valterm), VALTERM_RECORDS="")
    process, master = on_terminal([str(WRAPPER)], env)
    try:
        assert process.wait(timeout=LIMIT) == 0
    finally:
        os.close(master)
    assert seen.read_text().split() == ["--workspace", f"{tmp_path}/valterm"]


# an abandoned simulator must end even under a parent that ignores SIGHUP (nohup, supervisors,
# some CI runners): it did not (Textual's input thread then reads end-of-file for ever)
@pytest.mark.parametrize("hangup_ignored", [False, True], ids=["plain", "hangup-ignored-by-parent"])
def test_the_simulator_ends_when_the_client_leaves(tmp_path: Path, hangup_ignored: bool) -> None:
    valterm = fake_valterm(tmp_path, f'exec env PYTHONPATH={ROOT} {sys.executable} -m valterm "$@"')
    env = dict(os.environ, HOME=str(tmp_path), VALTERM=str(valterm), TERM="xterm-256color")
    process, master = on_terminal([str(WRAPPER)], env, hangup_ignored)
    try:
        read_until(master, b"COPYRIGHT")  # the start screen is up
        time.sleep(0.5)
        assert process.poll() is None  # the simulator runs while the client is there
        os.close(master)  # the client leaves: the terminal hangs up
        master = -1
        assert process.wait(timeout=LIMIT) != 0  # ended by the hangup, not still running
    finally:
        if master >= 0:
            os.close(master)
        if process.poll() is None:
            process.kill()
            process.wait()
