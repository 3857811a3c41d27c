"""The app under a pseudo-terminal, as a person's terminal runs it: start time, frames, bytes.

Spawns ``valterm --setup PROCESS`` in a pty of the given size and measures the time until
MAIN MENU is on the screen. Then, with the playback factor at its fastest (``>`` twice at
KEYBOARD: x0.25, so poses fall due faster than any screen shows them and the figure is the
app's drawing rate, not the motion's step rate), it counts the frames and bytes written

- while a joint move typed at the KEYBOARD mode's V prompt plays (``app_move_*``);
- while the thesis's PROCESS program runs in VAL-II mode, its locations read from
  PROCESS.LOC with CTRL-T D as a person defines them (``app_program_*``).

Frames are write bursts separated by quiet gaps (Textual writes a frame in one go); the
rate counts only the time a motion was drawing (a DELAY or a TYPE line is not a frame gap).
"""

from __future__ import annotations

import fcntl
import math
from collections.abc import Callable
from itertools import pairwise
import os
import pty
import select
import signal
import struct
import sys
import tempfile
import termios
import time

FRAME_GAP = 0.004  # seconds of quiet between two frames
DRAWING_GAP = 0.1  # a longer gap between frames is not drawing (a DELAY, a prompt)
LOCATIONS = "ABCDEF"  # the locations of PROCESS.LOC, accepted one by one


def _read_until(fd: int, needle: bytes, timeout: float) -> tuple[bytes, float]:
    start = time.perf_counter()
    seen = b""
    while time.perf_counter() - start < timeout:
        ready, _, _ = select.select([fd], [], [], 0.05)
        if ready:
            try:
                seen += os.read(fd, 65536)
            except OSError:
                break
            if needle in seen:
                return seen, time.perf_counter() - start
    raise TimeoutError(f"{needle!r} did not appear within {timeout} s")


def _drain(fd: int, quiet: float) -> None:
    while select.select([fd], [], [], quiet)[0]:
        try:
            os.read(fd, 65536)
        except OSError:
            return


def _record(fd: int, duration: float, quiet_end: float = 0.4,
            until: bytes | None = None) -> list[tuple[float, int]]:
    """(time, bytes) of every read until ``quiet_end`` s pass with no output (after ``until``
    was seen, when given), or ``duration`` s in all."""
    chunks: list[tuple[float, int]] = []
    start = time.perf_counter()
    last = start
    tail = b""
    seen = until is None
    while time.perf_counter() - start < duration:
        ready, _, _ = select.select([fd], [], [], 0.01)
        now = time.perf_counter()
        if ready:
            try:
                data = os.read(fd, 65536)
            except OSError:
                break
            chunks.append((now, len(data)))
            last = now
            if not seen and until is not None:
                tail = (tail + data)[-4096:]
                seen = until in tail
        elif seen and chunks and now - last > quiet_end:
            break
    return chunks


def frame_figures(chunks: list[tuple[float, int]], name: str, size: str) -> dict[str, float]:
    """Frames a second while drawing, bytes a frame and frames in all, from timed reads."""
    starts: list[float] = []
    sizes: list[int] = []
    previous = None
    for when, count in chunks:
        if previous is None or when - previous > FRAME_GAP:
            starts.append(when)
            sizes.append(0)
        sizes[-1] += count
        previous = when
    gaps = [b - a for a, b in pairwise(starts) if b - a <= DRAWING_GAP]
    drawing = sum(gaps)
    return {
        f"{name}_fps_{size}": len(gaps) / drawing if drawing > 0 else 0.0,
        f"{name}_bytes_per_frame_{size}": sum(sizes) / max(1, len(sizes)),
        f"{name}_frames_{size}": float(len(sizes)),
    }


def _spawn(width: int, height: int, workspace: str) -> tuple[int, int]:
    pid, fd = pty.fork()
    if pid == 0:  # the child: a terminal of the asked size, then the app
        fcntl.ioctl(0, termios.TIOCSWINSZ, struct.pack("HHHH", height, width, 0, 0))
        env = dict(os.environ, TERM="xterm-256color", COLORTERM="truecolor")
        os.execve(sys.executable, [sys.executable, "-m", "valterm", "--workspace", workspace,
                                   "--setup", "PROCESS"], env)
    return pid, fd


# the peer of the start time: a bare Textual app that shows one line and waits
BARE_APP = """
from textual.app import App
from textual.widgets import Static

class Bare(App):
    def compose(self):
        yield Static("MAIN MENU")

Bare().run()
"""


def _spawn_bare(width: int, height: int) -> tuple[int, int]:
    pid, fd = pty.fork()
    if pid == 0:
        fcntl.ioctl(0, termios.TIOCSWINSZ, struct.pack("HHHH", height, width, 0, 0))
        env = dict(os.environ, TERM="xterm-256color", COLORTERM="truecolor")
        os.execve(sys.executable, [sys.executable, "-c", BARE_APP], env)
    return pid, fd


def cache_bytecode() -> bool:
    """Compile the package's modules to cached bytecode, as ``pip install`` does for a wheel
    (Textual's and numpy's already are). With PYTHONDONTWRITEBYTECODE set and a source
    checkout, every start would otherwise compile some 90 modules, which an installed app
    never pays. False when the package's folder cannot be written (its bytecode as it is)."""
    import compileall
    from pathlib import Path

    import valterm

    try:
        return bool(compileall.compile_dir(Path(valterm.__file__).parent, quiet=2))
    except OSError:
        return False


def start_times(width: int = 160, height: int = 50, rounds: int = 5) -> dict[str, float]:
    """Seconds from start to MAIN MENU on screen, the app and a bare Textual app taken in turn
    (the median of ``rounds`` each), and their ratio; both with their bytecode cached
    (``cache_bytecode``)."""
    compiled = cache_bytecode()
    workspace = tempfile.mkdtemp(prefix="valterm-bench-")
    times: dict[str, list[float]] = {"app": [], "bare": []}
    spawners: tuple[tuple[str, Callable[[], tuple[int, int]]], ...] = (
        ("app", lambda: _spawn(width, height, workspace)), ("bare", lambda: _spawn_bare(width, height)))
    for _ in range(rounds):
        for name, spawn in spawners:
            start = time.perf_counter()
            pid, fd = spawn()
            try:
                _read_until(fd, b"MAIN MENU", 30.0)
                times[name].append(time.perf_counter() - start)
            finally:
                os.kill(pid, signal.SIGTERM)
                os.waitpid(pid, 0)
                os.close(fd)
    app, bare = sorted(times["app"])[rounds // 2], sorted(times["bare"])[rounds // 2]
    return {"app_start_median_s": app, "app_start_bare_textual_s": bare, "app_start_vs_bare_x": app / bare,
            "app_start_bytecode_cached": float(compiled)}


def _keys(fd: int, keys: str, settle: float = 0.3) -> None:
    for key in keys:
        os.write(fd, key.encode())
        _drain(fd, settle)


def _line(fd: int, text: str) -> None:
    os.write(fd, text.encode())
    _drain(fd, 0.3)
    os.write(fd, b"\r")


def _play_drive(fd: int, command: str) -> list[tuple[float, int]]:
    """KEYBOARD, playback at its fastest, V, the joint move; back to MAIN after it."""
    os.write(fd, b"K")
    _read_until(fd, b"KEYBOARD", 10.0)
    _drain(fd, 0.3)
    _keys(fd, ">>V")
    _line(fd, command)
    chunks = _record(fd, 20.0)
    _keys(fd, "\x1bR")  # the V prompt closes; R: the MAIN MENU
    return chunks


def _define_locations(fd: int) -> None:
    """VAL-II mode: PROCESS.LOC's locations accepted one by one (CTRL-T D), as a person does."""
    _keys(fd, "VV")
    os.write(fd, b"\x14")  # CTRL-T: D_DEFINE
    _drain(fd, 0.3)
    _keys(fd, "D")
    _line(fd, "PROCESS.LOC")
    for name in LOCATIONS:
        _read_until(fd, f"POINT {name}".encode(), 20.0)
        os.write(fd, b"A")
    _read_until(fd, b"LOCATIONS DEFINED", 20.0)
    _drain(fd, 0.5)


def _play_program(fd: int) -> list[tuple[float, int]]:
    """VAL-II mode: PROCESS.LOC's locations defined (``_define_locations``), then EXECUTE PROCESS."""
    _define_locations(fd)
    _line(fd, "EXECUTE PROCESS")
    return _record(fd, 60.0, until=b"COMPLETED")


def _rss_mib(pid: int) -> float:
    with open(f"/proc/{pid}/status", encoding="ascii") as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return math.nan


# a program that loops for ever without changing the cell (PROCESS moves its parts and shifts
# E each pass, and stops with an error on the second): PROCESS.LOC's locations, no grasp
LOOPS_DAT = """    ; PROGRAM : LOOPS
    ; PROCESS'S PATH WITHOUT TAKING THE PARTS OR SHIFTING E
    READY
    LEFTY
    ABOVE
    APPRO A, -50
    TYPE AT THE FIRST PART
    MOVE A
    DEPARTS 100
    MOVES E
    MOVES F
    DELAY 1
    DEPARTS 200
    APPROS C, -50
    MOVES C
    DEPARTS 100
    APPROS B, -50
    MOVES B
    TYPE AT THE SECOND PART
    DEPARTS 100
    MOVES E
    DELAY 1
    APPROS D, -50
    MOVES D
    DEPARTS 100
    READY
    STOP
"""


def bench_memory(minutes: float = 10.0, every: float = 10.0, width: int = 160,
                 height: int = 50) -> dict[str, float]:
    """The app's resident memory while a program loops in VAL-II mode at real pace (x1):
    sampled every ``every`` s for ``minutes``; the growth over the last two thirds of the
    span in MiB a minute (least squares), the first and last samples and the samples."""
    workspace = tempfile.mkdtemp(prefix="valterm-bench-")
    with open(os.path.join(workspace, "LOOPS.DAT"), "w", encoding="ascii") as program:
        program.write(LOOPS_DAT)
    pid, fd = _spawn(width, height, workspace)
    samples: list[tuple[float, float]] = []
    written = 0
    try:
        _read_until(fd, b"MAIN MENU", 30.0)
        _drain(fd, 0.5)
        _define_locations(fd)
        _line(fd, "EXECUTE LOOPS,-1")
        start = time.perf_counter()
        while time.perf_counter() - start < minutes * 60.0:
            # the app's output read as a terminal would; its bytes show it kept drawing
            written += sum(n for _, n in _record(fd, every, quiet_end=math.inf))
            samples.append(((time.perf_counter() - start) / 60.0, _rss_mib(pid)))
    finally:
        os.kill(pid, signal.SIGTERM)
        os.waitpid(pid, 0)
        os.close(fd)
    tail = samples[len(samples) // 3:]
    t = [a for a, _ in tail]
    r = [b for _, b in tail]
    mean_t, mean_r = sum(t) / len(t), sum(r) / len(r)
    slope = sum((a - mean_t) * (b - mean_r) for a, b in zip(t, r)) / max(1e-12, sum((a - mean_t) ** 2 for a in t))
    return {"app_rss_first_mib": samples[0][1], "app_rss_last_mib": samples[-1][1],
            "app_rss_growth_mib_per_min": slope, "app_rss_minutes": samples[-1][0],
            "app_rss_tail_low_mib": min(r), "app_rss_tail_high_mib": max(r),
            "app_rss_samples": float(len(samples)), "app_kib_written_per_min": written / 1024.0 / samples[-1][0]}


def bench_app(width: int = 160, height: int = 50, command: str = "DRIVE 1,-150,20",
              program: bool = True) -> dict[str, float]:
    workspace = tempfile.mkdtemp(prefix="valterm-bench-")
    pid, fd = _spawn(width, height, workspace)
    size = f"{width}x{height}"
    try:
        _, startup = _read_until(fd, b"MAIN MENU", 30.0)
        _drain(fd, 0.5)
        figures = {"app_start_to_main_menu_s": startup, **start_times(width, height)}
        figures.update(frame_figures(_play_drive(fd, command), "app_move", size))
        if program:
            figures.update(frame_figures(_play_program(fd), "app_program", size))
    finally:
        os.kill(pid, signal.SIGTERM)
        os.waitpid(pid, 0)
        os.close(fd)
    return figures
