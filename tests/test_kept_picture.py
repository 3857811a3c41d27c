"""Issue 40 (the picture at start): the picture of the last start is kept and shown in MAIN
MENU's first frame, before the set-up is read (and numpy loaded); the picture the reading
draws replaces it, cell for cell the same; a changed set-up file, other options or other
code show none."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from valterm.core.render import kept
from valterm.ui.app import ValtermApp

BRAILLE = range(0x2801, 0x2900)


def _braille(rows: list[str]) -> int:
    return sum(1 for row in rows for ch in row if ord(ch) in BRAILLE)


def _rows(app: ValtermApp) -> list[str]:
    view = app.screen.model_view  # type: ignore[attr-defined]
    return [view.render_line(y).text for y in range(view.size.height)]


async def _start(workspace: Path, cache: Path, **options: object) -> tuple[list[str], list[str], bool]:
    """One start of ``--setup PROCESS``: the picture as the first frame paints it (just before
    the set-up is read), the picture once it is read, and whether a session was open then."""
    app = ValtermApp(workspace, "PROCESS", **options)  # type: ignore[arg-type]
    app.kept_path = cache
    before: list[list[str]] = []
    opened: list[bool] = []
    open_setup = app._open_setup_to_open

    def first_frame_then_read() -> None:
        opened.append(app.session_read is not None)
        before.append(_rows(app))
        open_setup()

    app._open_setup_to_open = first_frame_then_read  # type: ignore[method-assign]
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.pause()
        await pilot.pause()
        after = _rows(app)
        assert app.screen.model_view.frame is not None  # type: ignore[attr-defined]
    return before[0], after, opened[0]


async def test_the_next_start_shows_the_kept_picture_in_its_first_frame(tmp_path: Path) -> None:
    cache = tmp_path / "cache" / "start-picture"
    first, drawn, opened = await _start(tmp_path, cache)
    assert not opened and _braille(first) == 0  # nothing kept yet: MAIN MENU, then the picture
    assert _braille(drawn) > 100 and cache.is_file()
    kept_rows = [text for text, _ in kept.read_kept(cache, cache.read_text("utf-8").split("\n")[1]).rows]  # type: ignore[union-attr]
    assert kept_rows == drawn  # kept as painted, caption and all

    second, redrawn, opened = await _start(tmp_path, cache)
    assert not opened  # no session yet: the first frame
    assert second == drawn  # the kept picture, cell for cell
    assert redrawn == drawn  # and the set-up's own picture, the same


async def test_a_new_workspace_shows_the_picture_kept_from_another(tmp_path: Path) -> None:
    """A workspace not filled yet reads the bundled PROCESS.SET: the picture kept from
    another workspace's start on the same file shows."""
    cache = tmp_path / "start-picture"
    _, drawn, _ = await _start(tmp_path / "one", cache)
    first, _, opened = await _start(tmp_path / "two", cache)
    assert not opened and first == drawn


async def test_a_changed_setup_file_shows_no_kept_picture_and_keeps_its_own(tmp_path: Path) -> None:
    cache = tmp_path / "start-picture"
    _, drawn, _ = await _start(tmp_path, cache)
    setup = tmp_path / "PROCESS.SET"
    setup.write_text(setup.read_text("utf-8").replace("440.00    -50.00", "300.00    -50.00", 1), "utf-8")
    first, moved, _ = await _start(tmp_path, cache)
    assert _braille(first) == 0 and moved != drawn  # a part moved: drawn afresh
    again, _, _ = await _start(tmp_path, cache)
    assert again == moved  # the moved cell's picture was kept


@pytest.mark.parametrize("option", [{"ascii": True}, {"robot": "PUMA560"}])
async def test_other_options_show_no_kept_picture(tmp_path: Path, option: dict[str, object]) -> None:
    cache = tmp_path / "start-picture"
    await _start(tmp_path, cache)
    first, drawn, _ = await _start(tmp_path, cache, **option)
    assert first == [" " * len(row) for row in first] and drawn != first


async def test_a_damaged_kept_file_is_drawn_afresh(tmp_path: Path) -> None:
    cache = tmp_path / "start-picture"
    _, drawn, _ = await _start(tmp_path, cache)
    lines = cache.read_text("utf-8").split("\n")
    cache.write_text("\n".join([*lines[:5], lines[5][:-3], *lines[6:]]), "utf-8")  # a row cut short
    first, again, _ = await _start(tmp_path, cache)
    assert _braille(first) == 0 and again == drawn
    assert kept.read_kept(cache, lines[1]) is not None  # kept whole again


def test_a_picture_round_trips_and_only_its_key_reads_it(tmp_path: Path) -> None:
    picture = kept.KeptPicture("k1", 3, [("\u2801 x", ((5, 2), (0, 1))), ("abc", ((1, 3),))])
    path = tmp_path / "sub" / "start-picture"
    assert kept.write_kept(path, picture)
    assert kept.read_kept(path, "k1") == picture
    assert kept.read_kept(path, "k2") is None
    path.write_text(path.read_text("utf-8").replace("abc", "a\x1bc"), "utf-8")
    assert kept.read_kept(path, "k1") is None  # an escape would be painted to the terminal
    assert kept.runs_of([4, 4, 0, 4]) == ((4, 2), (0, 1), (4, 1))


@pytest.mark.skipif(not hasattr(__import__("os"), "mkfifo"), reason="no FIFOs here")
def test_a_fifo_in_the_kept_files_place_is_no_picture_and_no_wait(tmp_path: Path) -> None:
    import os

    os.mkfifo(tmp_path / "start-picture")
    assert kept.read_kept(tmp_path / "start-picture", "k1") is None


def test_the_code_stamp_follows_the_files(tmp_path: Path) -> None:
    (tmp_path / "a.py").write_text("x = 1\n")
    stamp = kept._tree_stamp(tmp_path, 0)
    assert kept._tree_stamp(tmp_path, 0) == stamp
    (tmp_path / "a.py").write_text("x = 12\n")
    assert kept._tree_stamp(tmp_path, 0) != stamp


FIRST_FRAME_PROBE = """
import asyncio, json, sys
from pathlib import Path
import valterm.cli
from valterm.ui.app import ValtermApp

async def main():
    app = ValtermApp({workspace!r}, "PROCESS")
    app.kept_path = Path({cache!r})
    seen = []
    open_setup = app._open_setup_to_open
    def first_frame_then_read():
        view = app.screen.model_view
        rows = [view.render_line(y).text for y in range(view.size.height)]
        seen.append([sum(1 for r in rows for c in r if 0x2801 <= ord(c) < 0x2900), "numpy" in sys.modules])
        open_setup()
    app._open_setup_to_open = first_frame_then_read
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.pause()
        await pilot.pause()
    print(json.dumps(seen[0]))

asyncio.run(main())
"""


def test_the_kept_picture_is_painted_before_numpy_loads(tmp_path: Path) -> None:
    """What makes the picture come with the menu: the first frame paints the kept picture
    with neither numpy nor the raster loaded (they load when the set-up is read)."""
    probe = FIRST_FRAME_PROBE.format(workspace=str(tmp_path), cache=str(tmp_path / "start-picture"))
    seen = []
    for _ in range(2):  # the first start keeps its picture, the second shows it
        out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
        seen.append(json.loads(out.stdout.strip().splitlines()[-1]))
    assert seen[0] == [0, False]
    assert seen[1][0] > 100 and seen[1][1] is False
