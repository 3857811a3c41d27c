"""Issue 35 (build 1) and issue 39: one text path for the VAL-II transcript at every width. A
line is wrapped at the log's width, at spaces where it can be, and never cut; when the log's
width changes (the terminal resized, the picture shown or hidden) what it holds is wrapped
again. The wrapping is the core's ``wrap_line``; the app's log is read back from the screen."""

from __future__ import annotations

import itertools
import re
from pathlib import Path

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from textual.app import App, ComposeResult

from valterm.core.text.transcript import wrap_line
from valterm.core.val.limits import RunLimits
from valterm.testing import Simulation, screen_rows
from valterm.ui.widgets.transcript_log import TranscriptLog

# -- the wrapping function, any width, any message ----------------------------------------

WORD = st.text("ABCDEFGHIJKLMNOPQRSTUVWXYZabcxyz0123456789", min_size=1, max_size=12)
PUNCTUATION = st.text(".,:;()[]'\"-=+*/<>!?_#", min_size=1, max_size=4)
LONG_TOKEN = st.text("ABCXYZ0123456789-.,/_", min_size=30, max_size=400)  # a path, a number run
SPACES = st.text(" ", min_size=1, max_size=4)
MESSAGE = st.lists(st.one_of(WORD, WORD, PUNCTUATION, LONG_TOKEN, SPACES), max_size=60).map("".join)


def taken_out(message: str, pieces: list[str]) -> list[str] | None:
    """The whitespace taken out of the message at each break, when the pieces, in order, are
    the message with only whitespace taken out at the breaks (else None)."""
    pattern = r"\s*" + r"(\s*)".join(re.escape(piece) for piece in pieces) + r"\s*"
    found = re.fullmatch(pattern, message)
    return None if found is None else list(found.groups())


@settings(max_examples=400, deadline=None)
@given(message=MESSAGE, width=st.integers(40, 240), indent=st.sampled_from(["", "  ", "      "]))
@example(message="0" * 60 + " " + "0" * 30, width=40, indent="")   # a cut token's rest, then a token after a space
def test_every_character_arrives_in_order_within_the_width(message: str, width: int, indent: str) -> None:
    pieces = wrap_line(message, width, indent)
    assert pieces, "a line is at least one row, an empty one too"
    assert all(len(piece) <= width for piece in pieces)
    assert all(piece.startswith(indent) for piece in pieces[1:])  # a menu's hanging indent
    text = [pieces[0], *(piece.removeprefix(indent) for piece in pieces[1:])]
    spaces = taken_out(message, text)
    assert spaces is not None, (message, pieces)
    for (piece, after), space in zip(itertools.pairwise(text), spaces):
        if piece and after and not piece[-1].isspace() and not after[0].isspace() and not space:
            assert len(piece) + (0 if piece is text[0] else len(indent)) == width, (piece, after)  # a long token cut


@pytest.mark.parametrize(("line", "width", "rows"), [
    ("", 40, [""]),
    ("SHORT", 40, ["SHORT"]),
    ("OPENED         XW       YW", 40, ["OPENED         XW       YW"]),  # columns kept
    ("AAAA BBBB CCCC", 9, ["AAAA BBBB", "CCCC"]),
    ("A-B-C-D-E-F", 5, ["A-B-C", "-D-E-", "F"]),  # no break after a hyphen: it is cut
])
def test_wrap_line_breaks_at_spaces_and_keeps_a_short_line_as_it_is(line: str, width: int,
                                                                  rows: list[str]) -> None:
    assert wrap_line(line, width) == rows


def test_a_menu_row_hangs_under_its_description() -> None:
    row = "TYPE X=          - TYPES THE VALUE OF A VARIABLE ON THE TERMINAL"
    assert wrap_line(row, 40, " " * 19) == ["TYPE X=          - TYPES THE VALUE OF A",
                                            "                   VARIABLE ON THE",
                                            "                   TERMINAL"]
    assert wrap_line(row, 30, " " * 19) == ["TYPE X=          - TYPES THE", "VALUE OF A VARIABLE ON THE",
                                            "TERMINAL"]  # an indent of half the width or more: none


# -- the app: read back from the screen ---------------------------------------------------

RUNAWAY = "10  TYPE HELLO\n    GOTO 10\n"
REACH = "    APPRO P2, 80\n"  # refused in a program: the line names the program and step too
REFUSAL = ("*** REACH STEP 1: CONFIGURATION MISMATCH: P2 WAS TAUGHT LEFTY ABOVE NOFLIP, THE INDICATORS ARE"
           " RIGHTY ABOVE NOFLIP (TYPE LEFTY, OR TEACH P2 AGAIN)")
UNKNOWN = "*** WHEREABOUTS IS NOT A COMMAND THE SIMULATOR ACCEPTS (SEE COMMAND.DAT)"
LIMIT = "*** LOOP STEP 2: RUN LIMIT REACHED: 40 LINES OF OUTPUT (raise it with --max-lines)"


def log_rows(sim: Simulation) -> list[str]:
    """The transcript's rows as the screen shows them (inside its border and padding)."""
    region = sim.screen.query_one("#val-log").content_region
    rows = sim.rows()
    return [rows[y][region.x:region.right].rstrip() if y < len(rows) else ""
            for y in range(region.y, region.bottom)]


def shows_whole(sim: Simulation, message: str) -> bool:
    """The message is on the screen whole: the log's rows joined, whitespace aside, hold it."""
    return "".join(message.split()) in "".join("".join(log_rows(sim)).split())


async def run_lines(sim: Simulation, *lines: str) -> None:
    for line in lines:
        await sim.type(line, enter=True)
        await sim.settle()


@pytest.mark.parametrize("size", [(120, 40), (160, 50), (200, 50)])
async def test_the_lefty_refusal_and_the_run_limit_are_whole_beside_the_picture(
        tmp_path: Path, size: tuple[int, int]) -> None:
    (tmp_path / "LOOP.DAT").write_text(RUNAWAY)
    (tmp_path / "REACH.DAT").write_text(REACH)
    async with Simulation(tmp_path, setup="PROCESS", size=size) as sim:
        sim.session.interpreter.limits = RunLimits(lines=40)
        await sim.press("escape", "escape", "V", "V")  # MAIN, VAL-II mode, its command line
        assert sim.screen.query_one("#val-model").display  # the picture stands beside
        await run_lines(sim, "LEFTY", "DRIVE 2,60,100", "HERE P2", "READY", "EXEC REACH")
        assert REFUSAL in sim.transcript()
        assert shows_whole(sim, REFUSAL), log_rows(sim)
        await run_lines(sim, "WHEREABOUTS X")  # issue 39: the refusal was cut at `(SEE COMM`
        assert shows_whole(sim, UNKNOWN), log_rows(sim)
        await run_lines(sim, "EXEC LOOP")
        assert LIMIT in sim.transcript()
        assert shows_whole(sim, LIMIT), log_rows(sim)
        assert all(len(row) <= sim.screen.query_one("#val-log").content_region.width for row in log_rows(sim))


async def test_the_transcript_is_wrapped_again_when_the_terminal_is_resized(tmp_path: Path) -> None:
    (tmp_path / "REACH.DAT").write_text(REACH)
    async with Simulation(tmp_path, setup="PROCESS", size=(100, 30)) as sim:  # no picture beside
        await sim.press("escape", "escape", "V", "V")
        await run_lines(sim, "LEFTY", "DRIVE 2,60,100", "HERE P2", "READY", "EXEC REACH", "STATUS")
        status = next(line for line in sim.transcript() if line.startswith("RULES 1985"))
        for size in ((120, 40), (80, 24), (200, 50), (100, 30)):
            await sim.pilot.resize_terminal(*size)
            await sim.pilot.pause()
            await sim.pilot.pause()
            assert shows_whole(sim, REFUSAL), (size, log_rows(sim))
            assert shows_whole(sim, status), (size, log_rows(sim))
            room = sim.screen.query_one("#val-log").content_region.width
            assert max(map(len, log_rows(sim))) <= room < max(map(len, sim.transcript()))


# -- the widget alone ---------------------------------------------------------------------

class LogHost(App[None]):
    CSS = """TranscriptLog { width: 30; height: 12; border: round white; padding: 0 1;
                             scrollbar-visibility: hidden; }"""

    def compose(self) -> ComposeResult:
        yield TranscriptLog(id="log")


def widget_rows(app: LogHost) -> list[str]:
    region = app.query_one(TranscriptLog).content_region
    rows = screen_rows(app)
    return [rows[y][region.x:region.right].rstrip() for y in range(region.y, region.bottom)]


async def test_the_log_wraps_wide_glyphs_too_and_a_wipe_forgets_what_it_held() -> None:
    app = LogHost()
    async with app.run_test(size=(60, 14)) as pilot:
        log = app.query_one(TranscriptLog)
        wide = "TYPE " + "\u65e5\u672c" * 10  # 20 double-width glyphs: 45 cells, 25 characters
        log.write_lines(["A" * 60, wide])
        await pilot.pause()
        assert log.room == 24  # inside the border, the padding and the (unseen) scroll bar's gutter
        rows = widget_rows(app)
        assert rows[4:6] == ["\u65e5\u672c" * 6, "\u65e5\u672c" * 4]  # folded at 24 cells, not cut
        assert "".join(rows).replace(" ", "") == ("A" * 60 + wide).replace(" ", ""), rows
        log.clear()  # W_WIPE
        log.write_lines(["AFTER THE WIPE"])
        log.styles.width = 40  # wider: wrapped again, the wiped lines stay gone
        await pilot.pause()
        await pilot.pause()
        assert log.room == 34
        assert [row for row in widget_rows(app) if row] == ["AFTER THE WIPE"]
