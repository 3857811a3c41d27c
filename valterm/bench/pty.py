"""The app under a pseudo-terminal, as a person's terminal runs it: start time, frames, bytes.

Spawns ``valterm --setup PROCESS`` in a pty of the given size and measures the time until
MAIN MENU is on the screen. Then, with the playback factor at its fastest (``>`` twice at
KEYBOARD: x0.25, so poses fall due faster than any screen shows them and the figure is the
app's drawing rate, not the motion's step rate), it counts the frames and bytes written

- while a joint move typed at the KEYBOARD mode's V prompt plays (``app_move_*``);
- while the thesis's PROCESS program runs in VAL-II mode, its locations read from
  PROCESS.LOC with CTRL-T D as a person defines them (``app_program_fastest_*``).

Frames are write bursts separated by quiet gaps (Textual writes a frame in one go); the
rate counts only the time a motion was drawing (a DELAY or a TYPE line is not a frame gap).

What a user sees (``app_program_*``): PROCESS in a second app at real pace (x1, each motion
takes the real PUMA's time), the robot drawings (bursts that write braille: the picture
changed) per second of motion, the motions' seconds summed from the same program run
headless (``Motion.seconds``), and the bytes of those drawings.
"""

from __future__ import annotations

import fcntl
import math
from itertools import pairwise
import os
import re
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
# the model's picture in VAL-II mode on a 160x50 terminal (the peer's widget is this size)
PICTURE_SIZE = (88, 49)
LOCATIONS = "ABCDEF"  # the locations of PROCESS.LOC, accepted one by one
BRAILLE = re.compile(rb"\xe2[\xa0-\xa3]")  # UTF-8 of U+2800-U+28FF: the picture's cells


def terminal_env() -> dict[str, str]:
    """The child's environment: a true-colour xterm, its size the pty's own (COLUMNS and LINES,
    which pytest-xdist's workers set to 80x24, would override it)."""
    env = {k: v for k, v in os.environ.items() if k not in ("COLUMNS", "LINES")}
    return dict(env, TERM="xterm-256color", COLORTERM="truecolor")


def _read_until(fd: int, needle: bytes, timeout: float, picture: bool = False) -> tuple[bytes, float]:
    """Read until ``needle`` is on the screen (and, with ``picture``, the model's braille too)."""
    start = time.perf_counter()
    seen = b""
    while time.perf_counter() - start < timeout:
        ready, _, _ = select.select([fd], [], [], 0.05)
        if ready:
            try:
                seen += os.read(fd, 65536)
            except OSError:
                break
            if needle in seen and (not picture or BRAILLE.search(seen)):
                return seen, time.perf_counter() - start
    raise TimeoutError(f"{needle!r} did not appear within {timeout} s")


def _drain(fd: int, quiet: float, limit: float = math.inf) -> None:
    """Read until ``quiet`` s pass with no output, or ``limit`` s in all (a terminal that never
    goes quiet, an animating program, would otherwise hold it for ever)."""
    end = time.monotonic() + limit
    while time.monotonic() < end and select.select([fd], [], [], quiet)[0]:
        try:
            os.read(fd, 65536)
        except OSError:
            return


Chunk = tuple[float, int, bool]  # when read, bytes, braille among them (the picture drawn)


def _record(fd: int, duration: float, quiet_end: float = 0.4,
            until: bytes | None = None) -> list[Chunk]:
    """(time, bytes, braille?) of every read until ``quiet_end`` s pass with no output (after
    ``until`` was seen, when given), or ``duration`` s in all."""
    chunks: list[Chunk] = []
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
            chunks.append((now, len(data), BRAILLE.search(data) is not None))
            last = now
            if not seen and until is not None:
                tail = (tail + data)[-4096:]
                seen = until in tail
        elif seen and chunks and now - last > quiet_end:
            break
    return chunks


def _bursts(chunks: list[Chunk]) -> list[tuple[float, int, bool]]:
    """Write bursts (frames): (start, bytes, braille in it), reads closer than FRAME_GAP joined."""
    bursts: list[tuple[float, int, bool]] = []
    previous = None
    for when, count, drawn in chunks:
        if previous is None or when - previous > FRAME_GAP:
            bursts.append((when, 0, False))
        start, total, seen = bursts[-1]
        bursts[-1] = (start, total + count, seen or drawn)
        previous = when
    return bursts


def frame_figures(chunks: list[Chunk], name: str, size: str) -> dict[str, float]:
    """Frames a second while drawing, bytes a frame and frames in all, from timed reads."""
    bursts = _bursts(chunks)
    starts = [when for when, _, _ in bursts]
    sizes = [count for _, count, _ in bursts]
    gaps = [b - a for a, b in pairwise(starts) if b - a <= DRAWING_GAP]
    drawing = sum(gaps)
    return {
        f"{name}_fps_{size}": len(gaps) / drawing if drawing > 0 else 0.0,
        f"{name}_bytes_per_frame_{size}": sum(sizes) / max(1, len(sizes)),
        f"{name}_frames_{size}": float(len(sizes)),
    }


def drawing_figures(chunks: list[Chunk], motion_seconds: float, name: str, size: str) -> dict[str, float]:
    """Robot drawings (frames that write braille: the picture changed) per second of motion,
    and their bytes a drawing, from timed reads and the motions' seconds."""
    drawn = [count for _, count, braille in _bursts(chunks) if braille]
    return {
        f"{name}_fps_{size}": len(drawn) / motion_seconds if motion_seconds > 0 else 0.0,
        f"{name}_bytes_per_frame_{size}": sum(drawn) / max(1, len(drawn)),
        f"{name}_frames_{size}": float(len(drawn)),
        f"{name}_motion_s_{size}": motion_seconds,
    }


def program_motion_seconds(program: str = "PROCESS") -> float:
    """The motions' seconds of ``program`` run headless on the PROCESS cell and locations
    (what the app's playback takes at x1), from where the app starts it: D_DEFINE moved the
    arm to each location as it was accepted (``_define_locations``), so the program's READY
    starts at the last (2.1 s that a run from the set-up's pose does not have)."""
    from valterm.core.errors import ValtermError
    from valterm.core.events import Motion
    from valterm.core.session import Session

    session = Session(workspace_root=tempfile.mkdtemp(prefix="valterm-bench-"), setup="PROCESS")
    session.load_locations("PROCESS")
    simulator = session.simulator
    for name in LOCATIONS:
        try:
            for _ in simulator.move(simulator.location(name), name=name):
                pass
        except ValtermError:
            pass  # the app says it cannot reach it there, and the arm stays
    return sum(float(e.seconds) for e in session.interpreter.execute(program) if isinstance(e, Motion))


def _spawn(width: int, height: int, workspace: str, cache: str | None = None) -> tuple[int, int]:
    """The app in a pty; ``cache``: its $XDG_CACHE_HOME (where it keeps its start's picture)."""
    pid, fd = pty.fork()
    if pid == 0:  # the child: a terminal of the asked size, then the app
        fcntl.ioctl(0, termios.TIOCSWINSZ, struct.pack("HHHH", height, width, 0, 0))
        env = terminal_env()
        if cache is not None:
            env["XDG_CACHE_HOME"] = cache
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
        env = terminal_env()
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
    """Seconds from start to MAIN MENU on screen, the app and a bare Textual app (its one line)
    taken in turn (the median of ``rounds`` each), and their ratio; both with their bytecode
    cached (``cache_bytecode``). The app's MAIN MENU counts when its menu is drawn (it takes
    keys from then on); the model's picture beside it is timed in the same start
    (``app_start_picture_*``): a start after the first on the set-up, whose first frame holds
    the picture kept from the start before (core/render/kept.py). Each round also starts the
    app with nothing kept (``app_start_picture_cold_*``: a set-up's first start, or the first
    after an update), whose picture is drawn once the set-up is read after the menu's frame.
    The app keeps its picture in a cache folder of the bench's own. Both run on this Python,
    so both pay what its site-packages load at every start (an editable install's path
    finder, when the package is installed so)."""
    compiled = cache_bytecode()
    workspace = tempfile.mkdtemp(prefix="valterm-bench-")
    cache = tempfile.mkdtemp(prefix="valterm-bench-cache-")
    times: dict[str, list[float]] = {"cold": [], "app": [], "picture": [], "bare": []}
    for _ in range(rounds):
        _forget_kept(cache)
        times["cold"].append(_app_start(width, height, workspace, cache)[1])  # keeps its picture
        menu, picture = _app_start(width, height, workspace, cache)  # shows the kept one
        times["app"].append(menu)
        times["picture"].append(picture)
        start = time.perf_counter()
        pid, fd = _spawn_bare(width, height)
        try:
            _read_until(fd, b"MAIN MENU", 30.0)
            times["bare"].append(time.perf_counter() - start)
        finally:
            _end(pid, fd)
    app, picture, cold, bare = (sorted(times[name])[rounds // 2] for name in ("app", "picture", "cold", "bare"))
    return {"app_start_median_s": app, "app_start_bare_textual_s": bare, "app_start_vs_bare_x": app / bare,
            "app_start_picture_s": picture, "app_start_picture_vs_bare_x": picture / bare,
            "app_start_picture_cold_s": cold, "app_start_picture_cold_vs_bare_x": cold / bare,
            "app_start_bytecode_cached": float(compiled)}


def _app_start(width: int, height: int, workspace: str, cache: str) -> tuple[float, float]:
    """Seconds to MAIN MENU and to the model's picture (braille) in one start of the app."""
    start = time.perf_counter()
    pid, fd = _spawn(width, height, workspace, cache)
    try:
        seen, menu = _read_until(fd, b"MAIN MENU", 30.0)
        if not BRAILLE.search(seen):
            _read_until(fd, b"", 30.0, picture=True)
        return menu, time.perf_counter() - start
    finally:
        _end(pid, fd)


def _forget_kept(cache: str) -> None:
    import shutil

    shutil.rmtree(os.path.join(cache, "valterm"), ignore_errors=True)


def _end(pid: int, fd: int) -> None:
    try:
        os.kill(pid, signal.SIGTERM)
    except ProcessLookupError:
        pass  # it has ended by itself (the peer's animation)
    os.waitpid(pid, 0)
    os.close(fd)


def _keys(fd: int, keys: str, settle: float = 0.3) -> None:
    for key in keys:
        os.write(fd, key.encode())
        _drain(fd, settle)


def _line(fd: int, text: str) -> None:
    os.write(fd, text.encode())
    _drain(fd, 0.3)
    os.write(fd, b"\r")


def _play_drive(fd: int, command: str) -> list[Chunk]:
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


def _play_program(fd: int, seconds: float = 60.0) -> list[Chunk]:
    """VAL-II mode: PROCESS.LOC's locations defined (``_define_locations``), then EXECUTE PROCESS."""
    _define_locations(fd)
    _line(fd, "EXECUTE PROCESS")
    return _record(fd, seconds, until=b"COMPLETED")


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


def bench_memory(minutes: float = 30.0, every: float = 30.0, width: int = 160,
                 height: int = 50) -> dict[str, float]:
    """The app's resident memory while a program loops in VAL-II mode at real pace (x1):
    sampled every ``every`` s for ``minutes``; the growth over the last two thirds of the
    span in MiB a minute (least squares) and its low and high (the goal: flat, high - low
    <= 2 MiB over the last 20 of 30 minutes), the first sample, those at a third and two
    thirds of the span, and the last."""
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
            written += sum(n for _, n, _ in _record(fd, every, quiet_end=math.inf))
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
    def at(fraction: float) -> float:
        return min(samples, key=lambda sample: abs(sample[0] - fraction * samples[-1][0]))[1]

    return {"app_rss_first_mib": samples[0][1], "app_rss_last_mib": samples[-1][1],
            "app_rss_third_mib": at(1 / 3), "app_rss_two_thirds_mib": at(2 / 3),
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
            figures.update(frame_figures(_play_program(fd), "app_program_fastest", size))
    finally:
        os.kill(pid, signal.SIGTERM)
        os.waitpid(pid, 0)
        os.close(fd)
    if program:
        figures.update(bench_program_real_pace(width, height))
    return figures


def cpu_seconds(pid: int) -> float:
    """The CPU seconds (user + system) process ``pid`` has used so far (/proc/PID/stat)."""
    with open(f"/proc/{pid}/stat", encoding="ascii") as stat:
        fields = stat.read().rsplit(")", 1)[1].split()  # after the name, which may hold spaces
    # utime and stime are the stat's 14th and 15th fields; fields[0] here is its 3rd
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def bench_program_real_pace(width: int = 160, height: int = 50) -> dict[str, float]:
    """PROCESS at real pace (x1) in a fresh app: robot drawings per second of motion, their
    bytes, and the app's CPU while the program runs, in cores: its CPU seconds from EXECUTE to
    COMPLETED over the motions' seconds (its DELAYs and TYPEs counted against it); then the
    peer, a bare Textual app animating a widget of the picture's size at the same frame rate
    for the same seconds (``bench_bare_animation``). CPU seconds hold on a loaded machine (other
    processes' time is not counted); the frames a second and the wall-clock figures need an
    idle one."""
    workspace = tempfile.mkdtemp(prefix="valterm-bench-")
    pid, fd = _spawn(width, height, workspace)
    size = f"{width}x{height}"
    motion = program_motion_seconds()
    try:
        _read_until(fd, b"MAIN MENU", 30.0)
        _drain(fd, 0.5)
        _define_locations(fd)
        os.write(fd, b"EXECUTE PROCESS")
        _drain(fd, 0.3)
        cpu = cpu_seconds(pid)
        os.write(fd, b"\r")
        chunks = _record(fd, 120.0, until=b"COMPLETED")
        cpu = cpu_seconds(pid) - cpu
    finally:
        _end(pid, fd)
    figures = drawing_figures(chunks, motion, "app_program", size)
    figures[f"app_program_cpu_s_{size}"] = cpu
    figures[f"app_program_cores_{size}"] = cpu / motion
    fps = figures[f"app_program_fps_{size}"]
    figures.update(bench_bare_animation(width, height, fps if fps > 0 else 30.0, motion))
    return figures


# the peer of a running session: a bare Textual app whose one widget, the size of the
# app's picture (argv: width, height, frames a second, seconds), draws a turning braille
# line, repainted whole at the given rate (Textual's own way: refresh()); a line of text
# says it is done
BARE_ANIMATION = """
import math, sys
from textual.app import App
from textual.strip import Strip
from textual.widget import Widget
from rich.segment import Segment

WIDTH, HEIGHT, FPS, SECONDS = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])

class Arm(Widget):
    DEFAULT_CSS = "Arm { width: %d; height: %d; }" % (WIDTH, HEIGHT)
    angle = 0.0

    def render_line(self, y):
        dx, dy = math.cos(self.angle), math.sin(self.angle)
        row = ["\u2801"] + [" "] * (WIDTH - 1)  # a mark in every row: each frame draws braille
        if abs(dy) > 1e-6:
            x = int(WIDTH / 2 + (y - HEIGHT / 2) * dx / dy * 2)
            if 0 <= x < WIDTH:
                row[x] = chr(0x28FF)
        return Strip([Segment("".join(row))], WIDTH)

class BareAnimation(App):
    def compose(self):
        yield Arm()

    def on_mount(self):
        self.frames = 0
        self.set_interval(1 / FPS, self.tick)

    def tick(self):
        self.frames += 1
        if self.frames > FPS * SECONDS:
            self.exit()
            return
        arm = self.query_one(Arm)
        arm.angle += 0.05
        arm.refresh()

BareAnimation().run()
print("ANIMATION DONE")
"""


def bench_bare_animation(width: int, height: int, fps: float, seconds: float) -> dict[str, float]:
    """The peer of ``bench_program_real_pace``: BARE_ANIMATION in a pty of the same size, its
    widget the picture's (``PICTURE_SIZE``), its CPU over its seconds, frames and bytes."""
    picture_width, picture_height = PICTURE_SIZE
    pid, fd = pty.fork()
    if pid == 0:
        fcntl.ioctl(0, termios.TIOCSWINSZ, struct.pack("HHHH", height, width, 0, 0))
        env = terminal_env()
        os.execve(sys.executable, [sys.executable, "-c", BARE_ANIMATION, str(picture_width),
                                   str(picture_height), f"{fps:.3f}", f"{seconds:.3f}"], env)
    size = f"{width}x{height}"
    try:
        _read_until(fd, b"", 30.0, picture=True)  # its first frame
        cpu = cpu_seconds(pid)
        chunks = _record(fd, seconds + 30.0, until=b"ANIMATION DONE")
    except BaseException:
        _end(pid, fd)
        raise
    os.kill(pid, signal.SIGTERM)  # nothing to a process that has ended (not yet reaped)
    _, _, usage = os.wait4(pid, 0)  # all its CPU
    os.close(fd)
    cpu = usage.ru_utime + usage.ru_stime - cpu
    figures = drawing_figures(chunks, seconds, "app_program_bare", size)
    figures[f"app_program_bare_cpu_s_{size}"] = cpu
    figures[f"app_program_bare_cores_{size}"] = cpu / seconds
    return figures
