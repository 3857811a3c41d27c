"""A lean server (issue 38 item 7): an app idle at the VAL-II prompt writes next to nothing.

The cursor of every line the app asks on is steady (Textual's blinks: a redraw of the line
twice a second, ~2 KB/s down every idle SSH session). Measured as a person's terminal sees
it: the app under a pseudo-terminal, VAL-II mode's prompt open, 10 s without a key."""

from __future__ import annotations

import pytest

import os
import select
import tempfile
import time

from valterm.bench.pty import _drain, _end, _read_until, _spawn

IDLE_SECONDS = 10.0
IDLE_BYTES = 100  # the most an idle app may write in IDLE_SECONDS


def _bytes_written(fd: int, seconds: float) -> int:
    written = 0
    end = time.monotonic() + seconds
    while (left := end - time.monotonic()) > 0:
        if select.select([fd], [], [], left)[0]:
            try:
                written += len(os.read(fd, 65536))
            except OSError:
                break
    return written


@pytest.mark.slow  # ten seconds of an idle terminal: CI runs it (pytest -m slow)
def test_an_idle_app_at_the_val_ii_prompt_writes_almost_nothing() -> None:
    with tempfile.TemporaryDirectory() as workspace:
        pid, fd = _spawn(120, 40, workspace)
        try:
            _read_until(fd, b"MAIN MENU", 30.0)
            _drain(fd, 0.5)
            os.write(fd, b"V")
            _read_until(fd, b"VAL-II", 10.0)
            _drain(fd, 0.3)
            os.write(fd, b"V")  # VAL-II mode's V: the command line
            _read_until(fd, b"II COMMAND", 10.0)  # its placeholder, the cursor on its V
            _drain(fd, 1.0, limit=15.0)  # the prompt's first frames (and the picture) are out, however loaded the host
            written = _bytes_written(fd, IDLE_SECONDS)
        finally:
            _end(pid, fd)
    assert written < IDLE_BYTES, f"{written} bytes in {IDLE_SECONDS:g} s at an idle VAL-II prompt"
