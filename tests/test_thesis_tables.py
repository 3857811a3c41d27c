"""Tables C-1..C-3 of the thesis typed as the seed prints them (issue 39): the rows are
transcribed in tests/data/thesis/TABLES_C1_C3.ROWS (its header lists the OCR slips corrected),
pressed through the whole app under --keys 1985 from the start screen, and each row with a
figure whose text the thesis gives is compared with the screen."""

from __future__ import annotations

import asyncio
import math
import re
from dataclasses import dataclass
from pathlib import Path

import pytest
from app_helpers import screen_text, until

from valterm.core.val.checker import check_statement, read_as_1985
from valterm.ui.app import ValtermApp

ROWS = Path(__file__).parent / "data" / "thesis" / "TABLES_C1_C3.ROWS"

# The figures' text as the seed prints it (App. C), for the rows that name them; the seed's
# figure column is at times a row late (as its explanations are: K's row says "Main Menu
# display"), so a row's figure is looked for on the screen before and after its keys.
FIGURE_TEXT = {
    "C-2": ["MAIN MENU", "ENTER SUBMENUS BY PRESSING:", "K_KEYBOARD : TO KEYBOARD (MONITOR) MODE"],
    "C-3": ["KEYBOARD MENU", "S_SMOOTH : COLLISION CHECKS (ON/OFF)", "F_FACES : BACK FACES (ON/OFF)"],
    "C-5": ["MANIPULATION MENU"],
    "C-8": ["EDITOR COMMANDS", 'TYPE "EDIT" AND THEN PROGRAM NAME TO START EDIT SESSION'],
    "C-12 a": ["CLAMP IS NEAR PART 10"],
    "C-13": ["VAL-II MENU", "ENTER COMMANDS BY TYPING IN:"],
    "C-17 a": ["IT IS POSSIBLE TO GRASP THIS PART"],  # a program's output: in the transcript
}


@dataclass(frozen=True)
class Row:
    table: str
    printed: str
    figure: str
    keys: str

    def presses(self) -> list[str]:
        """The row's keys as Pilot names them: "TEXT" typed, RETURN enter, a letter lower case."""
        if self.keys == "OUT":
            return []
        pressed: list[str] = []
        for quoted, word in re.findall(r'"([^"]*)"|(\S+)', self.keys):
            if word:
                pressed.append("enter" if word == "RETURN" else word.lower() if word.isalpha() else word)
            else:
                pressed += ["space" if c == " " else c for c in quoted]
        return pressed


def read_rows() -> list[Row]:
    rows = []
    for line in ROWS.read_text(encoding="utf-8").splitlines():
        if line.strip() and not line.startswith(";"):
            rows.append(Row(*(field.strip() for field in line.split("|"))))
    return rows


def _files(workspace: Path) -> set[str]:
    """The workspace's files (not its hidden lock files, which no table could name)."""
    return {p.name for p in workspace.iterdir() if not p.name.startswith(".")}


def _norm(text: str) -> str:
    return " ".join(text.split())


def test_the_row_file_is_the_seeds_rows() -> None:
    """Every row of the three tables, in order; the keys differ from the printed input only
    where the header lists a departure (or by a RETURN ending a typed line)."""
    rows = read_rows()
    assert [sum(r.table == t for r in rows) for t in ("C-1", "C-2", "C-3")] == [27, 33, 32]
    text = ROWS.read_text(encoding="utf-8")
    departures = text[text.index("; Departures from the seed's text"):text.index("; Not departures")]
    for row in rows:
        if row.keys == "OUT" or row.printed == '"R ROBSIM", RETURN E':
            continue
        # typed text as printed, blanks and all; the single keys as printed, commas aside
        same_text = re.findall(r'"([^"]*)"', row.printed) == [
            t for t in re.findall(r'"([^"]*)"', row.keys) if not re.fullmatch(r"[-\d,]+", t)]
        printed = re.sub(r"[,\s]|RETURN", "", re.sub(r'"[^"]*"', "", row.printed))
        typed = re.sub(r"[,\s]|RETURN", "", re.sub(r'"[^"]*"', "", row.keys))
        numbers = "".join(re.findall(r'"([-\d,]+)"', row.keys)).replace(",", "")
        if not (same_text and printed.upper() == typed.upper() + numbers):
            assert row.printed in departures, f"{row} departs from the seed and the header does not say so"


def test_close_i_50_is_read_as_the_1985_program_read_it() -> None:
    assert check_statement(" CLOSE I 50") is not None  # the modern checker refuses it as typed
    assert read_as_1985(" CLOSE I 50") == " CLOSEI 50"
    assert read_as_1985("10  DEPART S 100") == "10  DEPARTS 100"
    assert read_as_1985(" MOVE A") is None and read_as_1985(" CLOSE X 50") is None


@pytest.mark.slow  # CI runs it (pytest -m slow); the default run stays under 5 minutes
def test_tables_c1_to_c3_typed_as_printed(tmp_path: Path) -> None:
    workspace = tmp_path / "ws"
    rows = read_rows()
    figures_seen: dict[str, list[str]] = {}
    seen: dict[str, object] = {}

    async def body() -> None:
        workspace.mkdir()
        app = ValtermApp(workspace, motion_rate=math.inf, keys="1985")
        async with app.run_test(size=(140, 48)) as pilot:
            await pilot.pause()
            before = screen_text(app)
            for row in rows:
                if row is rows[2]:  # DEMO3.SET read: the workspace is open (and seeded)
                    seen["files"] = _files(workspace)
                await pilot.press(*row.presses())  # keys typed ahead wait their turn (1985)
                await pilot.pause()
                if not app.is_running:
                    break
                await until(pilot, lambda: not app.moving and not app.keys_waiting, f"row {row.printed}")
                after = screen_text(app)
                transcript = getattr(app.screen, "transcript", None)
                if transcript is not None:
                    seen["transcript"] = list(transcript)
                if row.figure:
                    figures_seen[row.figure] = [before, after]
                if row.printed == 'Y, "TEST.DAT" RETURN':
                    seen["saved message"] = after
                if row.printed == '" CLOSE I 50"':
                    seen["read as"] = after
                before = after
            seen["running"] = app.is_running

    asyncio.run(body())
    assert not seen["running"]  # Table C-3's S, Y ended the session
    steps = [s.strip() for s in (workspace / "TEST.DAT").read_text().splitlines() if s.strip()]
    assert steps == ["MOVE A", "MOVE B", "MOVE E", "STOP"]
    assert "SET-UP SAVED AS TEST.SET (TEST.DAT TAKEN AS TEST" in str(seen["saved message"])
    assert "CLOSE I 50 READ AS CLOSEI 50" in str(seen["read as"])
    transcript = "\n".join(seen["transcript"])  # type: ignore[arg-type]
    assert "PROGRAM PROCESS COMPLETED" in transcript
    written = _files(workspace) - seen["files"]  # type: ignore[operator]
    assert written == {"TEST.SET", "TEST.DAT"}, written
    for figure, lines in FIGURE_TEXT.items():
        screens = [_norm(s) for s in figures_seen.get(figure, [])]
        where = screens + ([_norm(transcript)] if figure == "C-17 a" else [])
        for line in lines:
            assert any(_norm(line) in text for text in where), (figure, line)


@pytest.mark.parametrize("keys", ["modern", "1985"])
def test_test_dat_as_a_set_up_name_by_keyboard(tmp_path: Path, keys: str) -> None:
    """Table C-1's M .. Y, "TEST.DAT" RETURN from DEMO3: the 1985 keys save TEST.SET (and
    say so); the default keyboard is as it was: no set-up name, the prompt asks again."""
    rows = read_rows()
    start = next(i for i, row in enumerate(rows) if row.printed == "M")
    end = next(i for i, row in enumerate(rows) if "TEST.DAT" in row.printed)

    async def body() -> str:
        app = ValtermApp(tmp_path, "DEMO3", motion_rate=math.inf, keys=keys)
        async with app.run_test(size=(140, 48)) as pilot:
            await pilot.pause()
            for row in rows[start:end + 1]:
                for key in row.presses():
                    await pilot.press(key)
                    await pilot.pause()
            return screen_text(app)

    text = _norm(asyncio.run(body()))
    if keys == "modern":
        assert "A SETUP FILE NAME ENDS IN .SET" in text and not (tmp_path / "TEST.SET").exists()
        assert "ENTER SET-UP FILE NAME" in text  # the prompt is still open
    else:
        assert "SET-UP SAVED AS TEST.SET (TEST.DAT TAKEN AS TEST" in text and "MAIN MENU" in text
        assert (tmp_path / "TEST.SET").is_file() and not (tmp_path / "TEST.DAT").exists()


def test_1985_editor_clears_a_rejected_line_and_ignores_a_stray_return(tmp_path: Path) -> None:
    """--keys 1985: a step the checker rejects is said and cleared, and the next keys are the
    editor's menu keys (here S, E: saved, back at MAIN); a RETURN at MAIN means nothing."""

    async def body() -> tuple[str, str]:
        app = ValtermApp(tmp_path, "DEMO3", motion_rate=math.inf, keys="1985")
        async with app.run_test(size=(140, 48)) as pilot:
            await pilot.pause()
            await pilot.press("enter")
            await pilot.pause()
            at_main = screen_text(app)
            for key in ["e", *"EDIT T1", "enter", "c", *" MOVE A", "enter", *" CLOSE X 50", "enter"]:
                await pilot.press(key)
                await pilot.pause()
            rejected = screen_text(app)
            for key in ["s", "e"]:
                await pilot.press(key)
                await pilot.pause()
            return at_main, rejected + screen_text(app)

    at_main, after = asyncio.run(body())
    assert "IS NOT A KEY" not in at_main
    assert "REJECTED: CLOSE X 50" in _norm(after) and "MAIN MENU" in after
    assert (tmp_path / "T1.DAT").read_text().split() == ["MOVE", "A"]


def test_demo_keys_types_the_tables_as_the_row_file_does() -> None:
    """The museum demo's DEMO.KEYS, up to its CONV1 part, presses exactly the keys of the rows
    (so its departures from the seed are the ones its header and the row file list)."""
    from valterm.core.files.demokeys import load_demo

    items = load_demo()
    end = next(i for i, item in enumerate(items) if item.kind == "caption" and "CONV1" in item.value)
    demo = [key for item in items[:end] for key in item.keys()]
    rows = [key for row in read_rows() for key in row.presses()]
    assert demo == rows


def test_readouts_print_no_minus_zero_and_t_at_180_as_the_convention_keeps_it() -> None:
    """Fig. 2-8's readout: two decimals, never -0.00; O, A, T in (-180, 180]: a T that rounds
    to -180 is 180.00 (the thesis never prints -180; its T is 170.05, 158.35, 0.00)."""
    from valterm.core.events import Where
    from valterm.core.text.transcript import where_lines

    where = Where(xyz=(-0.001, 150.75, 990.6), oat=(90.0, -90.0, -179.999),
                  joints=(-0.004, -90.0, 90.0, 0.0, -0.001, 180.0), config={}, clamp="OPENED")
    text = "\n".join(where_lines(where))
    assert "-0.00" not in text and "-180.00" not in text
    assert where_lines(where)[1].split()[-1] == "180.00"
    from valterm.core.events import Near

    near = Near(a="CLAMP", b="PART 10", program="PICK", step=5, clamp=(-0.001, 465.0, -0.004))
    assert near.located == " (PICK STEP 5, CLAMP AT 0.00 465.00 0.00)"
