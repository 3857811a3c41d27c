"""The app under a pseudo-terminal, as a person's terminal runs it: start time, frames, bytes.

Spawns ``valterm --setup PROCESS`` in a pty of the given size, measures the time until
MAIN MENU is on the screen, then animates a joint move typed at the KEYBOARD mode's V
prompt and counts the frames and the bytes written while it plays. Frames are write
bursts separated by quiet gaps (Textual writes a frame in one go).
"""

from __future__ import annotations

import fcntl
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


def _record(fd: int, duration: float, quiet_end: float = 0.4) -> list[tuple[float, int]]:
    """(time, bytes) of every read until ``quiet_end`` s pass with no output (or duration)."""
    chunks: list[tuple[float, int]] = []
    start = time.perf_counter()
    last = start
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
        elif chunks and now - last > quiet_end:
            break
    return chunks


def bench_app(width: int = 160, height: int = 50, command: str = "DRIVE 1,-150,20") -> dict[str, float]:
    workspace = tempfile.mkdtemp(prefix="valterm-bench-")
    pid, fd = pty.fork()
    if pid == 0:  # the child: a terminal of the asked size, then the app
        fcntl.ioctl(0, termios.TIOCSWINSZ, struct.pack("HHHH", height, width, 0, 0))
        env = dict(os.environ, TERM="xterm-256color", COLORTERM="truecolor")
        os.execve(sys.executable, [sys.executable, "-m", "valterm", "--workspace", workspace,
                                   "--setup", "PROCESS"], env)
    try:
        _, startup = _read_until(fd, b"MAIN MENU", 30.0)
        _drain(fd, 0.5)
        os.write(fd, b"K")
        _read_until(fd, b"KEYBOARD", 10.0)
        _drain(fd, 0.3)
        os.write(fd, b"V")
        _drain(fd, 0.3)
        os.write(fd, command.encode())
        _drain(fd, 0.3)
        os.write(fd, b"\r")
        chunks = _record(fd, 20.0)
    finally:
        os.kill(pid, signal.SIGTERM)
        os.waitpid(pid, 0)
        os.close(fd)
    frames: list[int] = []
    previous = None
    for when, size in chunks:
        if previous is None or when - previous > FRAME_GAP:
            frames.append(0)
        frames[-1] += size
        previous = when
    span = chunks[-1][0] - chunks[0][0] if len(chunks) > 1 else 0.0
    return {
        "app_start_to_main_menu_s": startup,
        f"app_move_fps_{width}x{height}": (len(frames) - 1) / span if span > 0 else 0.0,
        f"app_move_bytes_per_frame_{width}x{height}": sum(frames) / max(1, len(frames)),
        f"app_move_frames_{width}x{height}": float(len(frames)),
    }
