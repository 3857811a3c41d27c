"""A terminal for tests that run the app under a pseudo-terminal: it reads what the app
writes and answers the app's cursor-position probes (``ESC [ 6 n``) as every VT100 does, or
stops reading (a frozen client). tests/test_frozen_terminal.py, tests/test_serve_sshd.py."""

from __future__ import annotations

import os
import re
import select
import time

import pytest

from valterm.ui.terminal_writer import PROBE

ANSWER = b"\x1b[1;1R"  # the cursor-position report a terminal sends back
BRAILLE = re.compile(rb"\xe2[\xa0-\xa3]")  # UTF-8 of U+2800-U+28FF: the picture's cells
LIMIT = 60.0  # seconds any wait may take before the test fails (a guard, not a timing)


class Terminal:
    """The master side of a pty: reads, answers probes, or stops reading."""

    def __init__(self, fd: int) -> None:
        self.fd = fd
        self.tail = b""

    def read(self, seconds: float, answer: bool = True) -> bytes:
        """What arrives in ``seconds``; each probe answered at once when ``answer``."""
        got = b""
        end = time.monotonic() + seconds
        while (left := end - time.monotonic()) > 0:
            if select.select([self.fd], [], [], left)[0]:
                try:
                    chunk = os.read(self.fd, 65536)
                except OSError:
                    break
                got += chunk
                if answer:
                    self.answer(chunk)
        return got

    def answer(self, chunk: bytes) -> None:
        """Answer the probes in ``chunk`` (one split across two reads counts once)."""
        probe = PROBE.encode()
        joined = self.tail + chunk
        count = joined.count(probe) - self.tail.count(probe)
        self.tail = joined[-(len(probe) - 1):]
        if count:
            os.write(self.fd, ANSWER * count)

    def until(self, needle: bytes, picture: bool = False) -> bytes:
        """Read (answering) until ``needle`` is shown (and, with ``picture``, braille after it)."""
        seen = b""
        end = time.monotonic() + LIMIT
        while needle not in seen or (picture and not BRAILLE.search(seen.split(needle, 1)[1])):
            if time.monotonic() > end:
                pytest.fail(f"{needle!r} never appeared: {seen[-300:]!r}")
            seen += self.read(0.1)
        return seen

    def keys(self, *keys: bytes, settle: float = 0.3) -> None:
        """Type each of ``keys``, reading (answering) ``settle`` s after each."""
        for key in keys:
            os.write(self.fd, key)
            self.read(settle)
