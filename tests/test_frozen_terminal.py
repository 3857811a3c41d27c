"""Frames are dropped, not queued, when the terminal does not read (issue 38 item 7).

The app under a pseudo-terminal whose reader is a small terminal of this test's: it reads the
app's output and answers the cursor-position probes (``ESC [ 6 n``) as every VT100 does. While
a motion plays, it stops reading for a while, as a frozen SSH client does (its sshd buffers
then stop taking the app's output). The app must go on taking keys meanwhile (its loop never
waits on the terminal), send nothing more until the terminal answers again, and then draw the
whole screen afresh (no frame is left half-drawn)."""

from __future__ import annotations

import fcntl
import os
import pty
import re
import signal
import struct
import sys
import termios
import time
from pathlib import Path

from valterm.ui.terminal_writer import LAG, MAX_CHARS, MAX_WRITES, PROBE, FrameGate

from pty_terminal import ANSWER, BRAILLE, Terminal

ROOT = Path(__file__).resolve().parent.parent
WIDTH, HEIGHT = 100, 30
STALL = LAG + 2.5  # seconds the terminal does not read


def spawn(workspace: Path, record: Path) -> tuple[int, Terminal]:
    pid, fd = pty.fork()
    if pid == 0:  # the child: a terminal of the test's size, then the app
        fcntl.ioctl(0, termios.TIOCSWINSZ, struct.pack("HHHH", HEIGHT, WIDTH, 0, 0))
        env = dict(os.environ, TERM="xterm-256color", PYTHONPATH=str(ROOT))
        env.pop("COLUMNS", None)  # the pty's size, not one a test runner set (pytest does)
        env.pop("LINES", None)
        os.execve(sys.executable, [sys.executable, "-m", "valterm", "--workspace", str(workspace),
                                   "--setup", "PROCESS", "--record", str(record)], env)
    return pid, Terminal(fd)


def recorded(record: Path, key: str, within: float) -> bool:
    end = time.monotonic() + within
    while time.monotonic() < end:
        if f'"key": "{key}"' in record.read_text():
            return True
        time.sleep(0.05)
    return False


def rows_drawn(output: bytes) -> set[int]:
    """The rows a frame puts the cursor on at their first column (a full repaint: all)."""
    return {int(row) for row in re.findall(rb"\x1b\[(\d+);1H", output)}


def test_a_terminal_that_stops_reading_gets_no_queued_frames_and_then_a_whole_screen(tmp_path: Path) -> None:
    record = tmp_path / "session.rec"
    pid, terminal = spawn(tmp_path / "work", record)
    try:
        terminal.until(b"MAIN MENU", picture=True)
        terminal.read(0.5)
        os.write(terminal.fd, b"K")
        terminal.until(b"KEYBOARD")
        terminal.keys(b"V")
        os.write(terminal.fd, b"DRIVE 1,-150,2\r")  # a slow joint move: seconds of drawing
        assert BRAILLE.search(terminal.read(0.8)), "the motion is not drawing"
        # the terminal stops reading; a key typed meanwhile is taken (recorded as typed)
        time.sleep(LAG + 0.5)
        os.write(terminal.fd, b"Z")
        assert recorded(record, "Z", STALL - LAG - 0.5), "the app stopped taking keys while the terminal did not read"
        # it reads again, without answering: what the app had written, and then nothing
        held = terminal.read(1.0, answer=False)
        assert PROBE.encode() in held
        assert terminal.read(0.8, answer=False) == b"", "frames sent to a terminal that has not answered"
        assert len(held) < 256 * 1024, f"{len(held)} bytes queued for a terminal that did not read"
        # it answers: the whole screen, every row, drawn afresh
        os.write(terminal.fd, ANSWER)
        after = terminal.read(1.0)
        assert rows_drawn(after) >= set(range(1, HEIGHT + 1)), sorted(rows_drawn(after))
    finally:
        os.kill(pid, signal.SIGTERM)
        os.waitpid(pid, 0)
        os.close(terminal.fd)


# -- the gate itself, on a clock of the test's ------------------------------------------
class Gate:
    def __init__(self) -> None:
        self.now = 0.0
        self.sent: list[str] = []
        self.repaints = 0
        self.gate = FrameGate(self.write, self.repainted, lambda: self.now)

    def write(self, text: str) -> None:
        self.gate.queued(text)
        self.sent.append(text)

    def frame(self) -> None:
        """A frame written, as ValtermApp._display does when the gate admits it."""
        mark = self.gate.handed
        self.write("a frame")
        self.gate.drawn(mark)

    def repainted(self) -> None:
        self.repaints += 1


def test_one_question_at_a_time_and_none_without_a_frame() -> None:
    g = Gate()
    g.gate.drawn(g.gate.handed)  # Textual wrote nothing (batching, closing): nothing asked
    assert g.sent == []
    g.frame()
    g.frame()
    assert g.sent.count(PROBE) == 1
    g.gate.answered()
    g.frame()
    assert g.sent.count(PROBE) == 2


def test_a_terminal_that_never_answers_is_not_held_back() -> None:
    g = Gate()
    g.frame()
    g.now = 100 * LAG
    assert g.gate.admit()


def test_an_unanswered_question_skips_frames_and_the_answer_repaints_once() -> None:
    g = Gate()
    g.frame()
    g.gate.answered()  # it answers: its silence from now on means something
    g.frame()
    g.now = LAG * 0.9
    assert g.gate.admit()  # not yet late
    g.now = LAG * 1.1
    assert not g.gate.admit() and not g.gate.admit()
    assert g.repaints == 0
    g.gate.answered()
    assert g.repaints == 1 and g.gate.admit()
    g.gate.answered()  # a second answer, nothing skipped since: no repaint
    assert g.repaints == 1


def test_a_key_from_the_terminal_asks_again_a_question_gone_late() -> None:
    """An answer lost (inside a paste, say) must not hold frames for ever; a key shows the
    terminal runs. Without keys nothing is asked again: a frozen client gets silence."""
    g = Gate()
    g.frame()
    g.gate.answered()
    g.frame()
    g.gate.stirred()  # not late: no second question
    assert g.sent.count(PROBE) == 2
    g.now = LAG * 1.1
    assert not g.gate.admit()
    g.gate.stirred()
    assert g.sent.count(PROBE) == 3
    assert not g.gate.admit()  # asked again, and still late until it answers
    g.gate.answered()
    assert g.repaints == 1 and g.gate.admit()


def test_a_backlog_at_the_writer_skips_frames_until_half_of_it_is_written() -> None:
    g = Gate()
    for _ in range(MAX_WRITES + 1):
        g.gate.queued("x" * 100)
    assert not g.gate.admit()
    g.gate.written("x" * 100)  # no longer over the limit, but not caught up: still skipped
    assert g.repaints == 0 and not g.gate.admit()
    while g.gate.writes * 2 > MAX_WRITES:
        g.gate.written("x" * 100)
    assert g.repaints == 1 and g.gate.admit()
    g.gate.queued("x" * (MAX_CHARS + 1))
    assert not g.gate.admit()
    g.gate.written("x" * (MAX_CHARS + 1))
    assert g.repaints == 2 and g.gate.admit()
