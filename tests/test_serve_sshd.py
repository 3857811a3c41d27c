"""The SSH recipe of docs/SERVING.md against a real OpenSSH server (issue 24): the sshd_config
Match block as written, the ForceCommand wrapper, a key login, the "command ignored" note
before the simulator starts, and the recipe's useradd leaving the account unlocked.

Skipped where sshd, ssh or ssh-keygen is absent (``apt-get install openssh-server
openssh-client``). The server runs as the current user on a free port of 127.0.0.1, with its
own host key and authorized key in a temporary folder; the login is the current user's."""

from __future__ import annotations

import fcntl
import getpass
import os
import pty
import pwd
import re
import select
import shlex
import shutil
import socket
import signal
import struct
import subprocess
import sys
import termios
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest

from valterm.ui.terminal_writer import LAG

from pty_terminal import BRAILLE, Terminal

ROOT = Path(__file__).resolve().parent.parent
SERVING = ROOT / "docs" / "SERVING.md"
WRAPPER = ROOT / "docs" / "valterm-login.sh"
LIMIT = 60.0  # seconds any step may take before the test fails (a guard, not a timing)

SSHD = shutil.which("sshd") or next((p for p in ("/usr/sbin/sshd", "/usr/local/sbin/sshd") if os.path.exists(p)), None)
SSH, KEYGEN = shutil.which("ssh"), shutil.which("ssh-keygen")
pytestmark = pytest.mark.skipif(not (SSHD and SSH and KEYGEN), reason="needs OpenSSH: sshd, ssh and ssh-keygen")


def recipe_block(starts: str) -> list[str]:
    """The lines of the first fenced block of SERVING.md whose first line starts with ``starts``."""
    blocks = re.findall(r"```[a-z]*\n(.*?)```", SERVING.read_text(), re.S)
    return next(b.splitlines() for b in blocks if b.startswith(starts))


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


@contextmanager
def sshd(tmp_path: Path, valterm: Path, home: Path | None = None,
         alive: tuple[int, int] | None = None) -> Iterator[dict[str, object]]:
    """A real sshd with the recipe's Match block (for the current user, not the group), its
    wrapper starting ``valterm``; ``home``: the login's $HOME (else the user's own);
    ``alive``: ClientAliveInterval and ClientAliveCountMax instead of the recipe's."""
    user = getpass.getuser()
    subprocess.run([KEYGEN, "-q", "-t", "ed25519", "-N", "", "-f", str(tmp_path / "host")], check=True)
    subprocess.run([KEYGEN, "-q", "-t", "ed25519", "-N", "", "-f", str(tmp_path / "user")], check=True)
    (tmp_path / "authorized_keys").write_text((tmp_path / "user.pub").read_text())
    (tmp_path / "authorized_keys").chmod(0o600)
    # ForceCommand runs through the login shell: `env` points the wrapper at the stand-in
    # (works on any OpenSSH; the server-side SetEnv needs 8.7)
    # (the session records go to the test's folder, not the home of whoever runs the tests)
    at_home = f"HOME={home} " if home is not None else ""
    wrapper = f"env {at_home}VALTERM={valterm} VALTERM_NOTE_SECONDS=2 VALTERM_RECORDS={tmp_path / 'records'} {WRAPPER}"
    match = [line.replace("/usr/local/bin/valterm-login", wrapper) for line in recipe_block("Match Group valterm")]
    match[0] = f"Match User {user}"
    if alive is not None:
        match = [line for line in match if not line.strip().startswith("ClientAlive")]
        match += [f"    ClientAliveInterval {alive[0]}", f"    ClientAliveCountMax {alive[1]}"]
    port = free_port()
    config = tmp_path / "sshd_config"
    config.write_text("\n".join([
        f"Port {port}", "ListenAddress 127.0.0.1", f"HostKey {tmp_path / 'host'}", f"PidFile {tmp_path / 'pid'}",
        f"AuthorizedKeysFile {tmp_path / 'authorized_keys'}", "StrictModes no", "UsePAM no",
        "PasswordAuthentication no",
        *match, ""]))
    if os.geteuid() == 0:
        os.makedirs("/run/sshd", mode=0o755, exist_ok=True)  # the privilege-separation folder
    checked = subprocess.run([SSHD, "-t", "-f", str(config)], capture_output=True, text=True)
    assert checked.returncode == 0, f"the recipe's Match block is refused by sshd: {checked.stderr}"
    daemon = subprocess.Popen([SSHD, "-D", "-e", "-f", str(config)], stdout=subprocess.DEVNULL,
                              stderr=open(tmp_path / "sshd.log", "wb"))  # noqa: SIM115
    end = time.monotonic() + LIMIT
    while True:
        try:
            socket.create_connection(("127.0.0.1", port), timeout=1).close()
            break
        except OSError:
            if time.monotonic() > end or daemon.poll() is not None:
                pytest.fail(f"sshd did not start: {(tmp_path / 'sshd.log').read_text()}")
            time.sleep(0.1)
    client = [SSH, "-p", str(port), "-i", str(tmp_path / "user"), "-o", "BatchMode=yes",
              "-o", "StrictHostKeyChecking=no", "-o", f"UserKnownHostsFile={tmp_path / 'known_hosts'}",
              "-o", "LogLevel=ERROR", f"{user}@127.0.0.1"]
    try:
        yield {"client": client, "log": tmp_path / "sshd.log"}
    finally:
        daemon.terminate()
        daemon.wait(timeout=LIMIT)


@pytest.fixture
def server(tmp_path: Path) -> Iterator[dict[str, object]]:
    """sshd with the recipe as written, the simulator a stand-in that says it started and with what."""
    started = tmp_path / "started"
    fake = tmp_path / "valterm"
    fake.write_text(f'#!/bin/sh\necho "SIMULATOR STARTED $*"\ntouch {started}\n')
    fake.chmod(0o755)
    with sshd(tmp_path, fake) as served:
        yield {**served, "started": started}


def on_terminal(argv: list[str], arrivals: list[tuple[float, bytes]] | None = None) -> tuple[int, bytes]:
    """Run ``argv`` (the ssh client) on a terminal of its own, as a person would; its exit
    status and everything the terminal showed (each chunk and when it came, in ``arrivals``)."""
    pid, master = pty.fork()
    if pid == 0:  # the child: exec the client (nothing else runs here)
        os.execv(argv[0], argv)
    seen = b""
    end = time.monotonic() + LIMIT
    try:
        while time.monotonic() < end:
            ready, _, _ = select.select([master], [], [], 0.5)
            if ready:
                try:
                    chunk = os.read(master, 65536)
                except OSError:
                    break
                if not chunk:
                    break
                seen += chunk
                if arrivals is not None:
                    arrivals.append((time.monotonic(), seen))
        else:
            os.kill(pid, 9)
    finally:
        os.close(master)
    _, status = os.waitpid(pid, 0)
    return os.waitstatus_to_exitcode(status), seen


def test_a_key_login_starts_the_simulator_on_the_users_workspace(server) -> None:  # type: ignore[no-untyped-def]
    status, seen = on_terminal([*server["client"], "-t"])
    text = seen.decode(errors="replace")
    assert status == 0, text + server["log"].read_text()
    assert f"SIMULATOR STARTED --workspace {pwd.getpwuid(os.getuid()).pw_dir}/valterm" in text
    assert "is ignored" not in text


def test_a_command_is_said_to_be_ignored_before_the_simulator_starts(server) -> None:  # type: ignore[no-untyped-def]
    arrivals: list[tuple[float, bytes]] = []
    status, seen = on_terminal([*server["client"], "-t", "rm", "-rf", "valterm"], arrivals)
    text = seen.decode(errors="replace")
    assert status == 0, text
    note = text.find("the command 'rm -rf valterm' is ignored")
    assert 0 <= note < text.find("SIMULATOR STARTED"), text
    # and it stays readable: the simulator's screen (which covers the terminal) comes only
    # after the pause (VALTERM_NOTE_SECONDS=2 here), not at once
    said = next(t for t, so_far in arrivals if b"is ignored" in so_far)
    started = next(t for t, so_far in arrivals if b"SIMULATOR STARTED" in so_far)
    assert started - said >= 1.5


def test_no_terminal_is_refused_through_sshd(server) -> None:  # type: ignore[no-untyped-def]
    result = subprocess.run([*server["client"], "-T"], stdin=subprocess.DEVNULL, capture_output=True,
                            text=True, timeout=LIMIT)
    assert result.returncode == 1
    assert "needs a terminal" in result.stderr
    assert not server["started"].exists()


@pytest.mark.skipif(os.geteuid() != 0 or not shutil.which("useradd"), reason="useradd needs root")
def test_the_recipes_useradd_leaves_the_account_unlocked_for_key_login(tmp_path: Path) -> None:
    """The recipe's groupadd/useradd lines, run as written on an empty system of files
    (``--prefix``: nothing of this machine's accounts is touched): the account's password
    field must not start with '!' (locked: sshd without PAM refuses even a key)."""
    fresh = tmp_path / "fresh"
    (fresh / "etc").mkdir(parents=True)
    (fresh / "home").mkdir()
    for name, line in (("passwd", "root:x:0:0:root:/root:/bin/sh"), ("group", "root:x:0:"),
                       ("shadow", "root:*:19000:0:99999:7:::"), ("gshadow", "root:*::")):
        (fresh / "etc" / name).write_text(line + "\n")
    commands = [line.split("#")[0].strip() for line in recipe_block("groupadd valterm")]
    commands = [c for c in commands if c.startswith(("groupadd ", "useradd "))]
    assert any(c.startswith("useradd ") for c in commands), commands
    for command in commands:
        words = shlex.split(command)
        subprocess.run([words[0], "--prefix", str(fresh), *words[1:]], check=True, capture_output=True)
    shadow = dict(line.split(":", 2)[:2] for line in (fresh / "etc" / "shadow").read_text().splitlines())
    users = [w for c in commands if c.startswith("useradd ") for w in shlex.split(c)[-1:]]
    for user in users:
        assert not shadow[user].startswith("!"), f"{user} is locked: {shadow[user]!r}"


# -- a frozen client (issue 38 item 7) ----------------------------------------------------
SPIN = """    ; PROGRAM : SPIN
    ; JOINT 1 TO AND FRO FOR EVER: THE SCREEN KEEPS DRAWING
10  DRIVE 1,-60,100
    DRIVE 1,60,100
    GOTO 10
"""
SLACK = 3.0  # seconds for a loaded machine (sshd's and the app's own timers)


def recipe_alive() -> tuple[int, int, float]:
    """The recipe's ClientAliveInterval, ClientAliveCountMax, and the seconds it says a client
    that does not answer is dropped within ("within N minutes")."""
    block = recipe_block("Match Group valterm")
    interval, count = (next(line for line in block if line.split()[:1] == [key])
                       for key in ("ClientAliveInterval", "ClientAliveCountMax"))
    stated = re.search(r"within (\d+) minutes", count)
    assert stated, f"the recipe does not say when a silent client is dropped: {count!r}"
    return int(interval.split()[1]), int(count.split()[1]), 60.0 * int(stated[1])


def longest_kept(interval: float, count: int) -> float:
    """The longest a frozen client keeps its session: the app stops drawing for a terminal
    that has not answered for LAG s, then sshd drops the client at its count+1-th unanswered
    question. sshd asks only after ``interval`` s in which nothing happened; OpenSSH before
    9.5 (Debian 12's 9.2) waits one to two intervals between questions."""
    return LAG + (count + 1) * 2 * interval


def test_the_recipe_says_how_long_a_frozen_client_is_kept() -> None:
    interval, count, stated = recipe_alive()
    assert longest_kept(interval, count) <= stated + SLACK


def the_app(home: Path) -> int:
    """The pid of the simulator running on ``home``'s workspace (sshd's grandchild)."""
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                argv = Path(f"/proc/{entry}/cmdline").read_bytes().split(b"\0")
            except OSError:
                continue
            if b"valterm" in argv and f"{home}/valterm".encode() in argv:
                return int(entry)
    pytest.fail("the simulator is not running")


def running(pid: int) -> bool:
    try:
        return Path(f"/proc/{pid}/stat").read_text().split()[2] != "Z"
    except OSError:
        return False


@pytest.mark.slow  # some 15 s: a login, a program, a frozen client waited out
def test_a_frozen_client_is_dropped_within_the_recipes_time(tmp_path: Path) -> None:
    """The client stopped (SIGSTOP) while a program draws for ever; the recipe's ClientAlive
    values with 1 s for its interval. Before, the app's frames kept sshd busy until about a
    megabyte was buffered for the client, and only then did sshd start asking."""
    _, count, _ = recipe_alive()
    home = tmp_path / "home"
    (home / "valterm").mkdir(parents=True)
    (home / "valterm" / "SPIN.DAT").write_text(SPIN)
    app = tmp_path / "valterm"
    app.write_text(f'#!/bin/sh\nexec env PYTHONPATH={ROOT} {sys.executable} -m valterm "$@"\n')
    app.chmod(0o755)
    with sshd(tmp_path, app, home, alive=(1, count)) as served:
        client = [*served["client"], "-t"]  # type: ignore[list-item]
        pid, fd = pty.fork()
        if pid == 0:  # the child: a terminal of a size, then the client
            fcntl.ioctl(0, termios.TIOCSWINSZ, struct.pack("HHHH", 30, 100, 0, 0))
            os.execv(client[0], client)
        terminal = Terminal(fd)
        simulator = 0
        try:
            terminal.until(b"COPYRIGHT")
            terminal.keys(b"E")
            os.write(fd, b"\r")  # RETURN: the set-up PROCESS
            terminal.until(b"MAIN MENU", picture=True)
            terminal.keys(b"V", b"V")  # VAL-II mode, its command line
            os.write(fd, b"EXECUTE SPIN\r")
            assert BRAILLE.search(terminal.read(2.0)), "the program is not drawing"
            simulator = the_app(home)
            os.kill(pid, signal.SIGSTOP)
            stopped = time.monotonic()
            while running(simulator) and time.monotonic() - stopped < LIMIT:
                time.sleep(0.1)
            kept = time.monotonic() - stopped
        finally:
            os.kill(pid, signal.SIGCONT)
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
            os.close(fd)
            if simulator and running(simulator):
                os.kill(simulator, signal.SIGKILL)  # kept past the guard: the test fails below
        log = served["log"].read_text()  # type: ignore[attr-defined]
    assert "Timeout, client not responding" in log, log[-2000:]
    assert kept <= longest_kept(1, count) + SLACK, f"the session was kept {kept:.1f} s"
