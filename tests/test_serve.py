"""``valterm serve --web``: the served page names only the public URL (https gives wss), asks
nothing from the internet, and /favicon.ico answers; on 0.0.0.0 pages never say 0.0.0.0.
The server runs as a real process on a free port of 127.0.0.1 and is always stopped."""

from __future__ import annotations

import os
import re
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest


ROOT = Path(__file__).resolve().parent.parent
START_LIMIT = 60.0  # seconds the server may take to answer (a guard, not a timing)
URL = re.compile(r"""(?:https?|wss?):(?://)?[^\s"'<>)]*|(?<=["'(])//[^\s"'<>)]+""")


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def fetch(url: str, headers: dict[str, str] | None = None) -> tuple[int, bytes, str]:
    request = urllib.request.Request(url, headers=headers or {})
    try:
        with urllib.request.urlopen(request, timeout=10) as answer:
            return answer.status, answer.read(), answer.headers.get("Content-Type", "")
    except urllib.error.HTTPError as error:
        return error.code, error.read(), ""


@contextmanager
def server(tmp_path: Path, *args: str) -> Iterator[str]:
    """``valterm serve --web`` on 127.0.0.1:free port; yields its local address."""
    port = free_port()
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    log = (tmp_path / "serve.log").open("wb")
    process = subprocess.Popen(
        [sys.executable, "-m", "valterm", "--workspace", str(tmp_path / "ws"), "serve", "--web",
         "--port", str(port), *args], cwd=tmp_path, env=env, stdout=log, stderr=subprocess.STDOUT)
    local = f"http://127.0.0.1:{port}"
    try:
        end = time.monotonic() + START_LIMIT
        while True:
            if process.poll() is not None:
                pytest.fail(f"the server ended: {(tmp_path / 'serve.log').read_text()}")
            try:
                with socket.create_connection(("127.0.0.1", port), timeout=1):
                    break
            except OSError:
                if time.monotonic() > end:
                    pytest.fail("the server never answered")
                time.sleep(0.2)
        yield local
    finally:
        process.terminate()
        try:
            process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait(timeout=10)
        log.close()


def test_page_names_only_the_public_url_and_nothing_external(tmp_path: Path) -> None:
    public = "https://valterm.example.org"
    with server(tmp_path, "--host", "127.0.0.1", "--public-url", public + "/") as local:
        status, body, _ = fetch(local + "/")
        assert status == 200
        page = body.decode()
        addresses = URL.findall(page)
        assert addresses, page
        assert all(a.startswith((public + "/", "wss://valterm.example.org/")) for a in addresses), addresses
        assert "wss://valterm.example.org/ws" in addresses
        assert "127.0.0.1" not in page and "fonts.googleapis" not in page
        # keys typed before a click: the served page focuses the terminal's input (issue 27)
        assert 'querySelector("#terminal textarea")' in page and "focusTerminal, true" in page
        # everything the page loads is served here (an offline kiosk has nothing else)
        for address in addresses:
            if address.startswith(public):
                status, body, _ = fetch(local + address[len(public):])
                assert status == 200 and body, address
        status, icon, kind = fetch(local + "/favicon.ico")
        assert status == 200 and icon[:4] == b"\x00\x00\x01\x00" and kind == "image/x-icon"


def test_all_addresses_page_points_at_the_browsers_address(tmp_path: Path) -> None:
    with server(tmp_path, "--host", "0.0.0.0") as local:
        page = fetch(local + "/", {"Host": "lab7.example.org:8080"})[1].decode()
        assert "0.0.0.0" not in page
        assert "ws://lab7.example.org:8080/ws" in page
        assert all(a.startswith(("http://lab7.example.org:8080/", "ws://lab7.example.org:8080/"))
                   for a in URL.findall(page))
        # a TLS proxy that says so gets wss
        page = fetch(local + "/", {"Host": "valterm.example.org", "X-Forwarded-Proto": "https"})[1].decode()
        assert "wss://valterm.example.org/ws" in page and "http://" not in page
        assert fetch(local + "/", {"Host": "bad host<script>"})[0] == 400


def test_serve_refuses_a_bad_public_url(capsys: pytest.CaptureFixture[str]) -> None:
    from valterm.cli import main

    assert main(["serve", "--web", "--public-url", "valterm.example.org"]) == 2
    assert "is not an http:// or https:// address" in capsys.readouterr().err
    assert main(["serve"]) == 2
