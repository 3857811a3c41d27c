"""What a frame costs to make (issue 40): a redraw rebuilds only the rows it changed, a row is
as many style runs as its dots have colours, the readouts and the status line are repainted
only when they read differently, a line in a full transcript lays out no screen, and a paced
motion is drawn on its own 30-frame clock. Mechanisms, not timings."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from rich.style import Style
from textual.app import App, ComposeResult
from textual.widgets import Static

from app_helpers import FakeClock, make_app, sync
from test_view_widget import ViewApp, two_boxes
from valterm.core.render.overlays import Trace
from valterm.ui.playback import DRAW_RATE
from valterm.ui.view.model_view import BLANK, ModelView, blanks_coloured
from valterm.ui.widgets.readouts import ReadoutLines, show_text
from valterm.ui.widgets.status import StatusLine
from valterm.ui.widgets.transcript_log import TranscriptLog


def test_blanks_take_the_colour_of_the_next_dot_in_their_row() -> None:
    colours = np.array([[0, 5, 0, 0, 5, 0, 7, 0, 0],
                        [0, 0, 0, 0, 0, 0, 0, 0, 0]], dtype=np.uint8)
    blank = colours == 0
    blank[1] = True
    coloured = blanks_coloured(colours, blank)
    # leading and inner blanks: the next dot's colour; the trailing ones: the last dot's
    assert coloured[0].tolist() == [5, 5, 5, 5, 5, 7, 7, 7, 7]
    assert coloured[1].tolist() == [0] * 9  # a row without dots
    assert (coloured[~blank] == colours[~blank]).all()  # no dot changes colour


def _runs(strip: Any) -> list[tuple[str, Any]]:
    return [(segment.text, segment.style) for segment in strip]


@sync
async def test_a_redraw_rebuilds_only_the_rows_it_changed() -> None:
    app = ViewApp()
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause()
        view = app.query_one(ModelView)
        strips = [view.render_line(y) for y in range(24)]
        view.update_scene(two_boxes(dy_bottom=250.0))  # the bottom box moves, the top one stays
        await pilot.pause()
        changed = set(view.dirty_rows)
        assert changed and len(changed) < 24
        after = [view.render_line(y) for y in range(24)]
        for y in range(24):
            if y in changed:
                assert after[y] is not strips[y]
            else:
                assert after[y] is strips[y], f"row {y} was rebuilt though the redraw left it"


@sync
async def test_a_row_is_as_many_runs_as_its_dots_have_colours() -> None:
    """Each run's dots are of its colour, and two runs side by side differ in colour: a blank
    cell (it shows no colour) never splits a run."""
    app = ViewApp()
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause()
        view = app.query_one(ModelView)
        frame = view.frame
        assert frame is not None
        rows_with_dots = 0
        for y in range(frame.height):
            runs = _runs(view.render_line(y))
            drawn = frame.colours[y][frame.chars[y] != BLANK]
            # as many runs as colour changes among the row's dots, plus one
            changes = int((drawn[1:] != drawn[:-1]).sum()) if len(drawn) else 0
            assert len(runs) == changes + 1, (y, runs)
            rows_with_dots += bool(len(drawn))
            x = 0
            for text, style in runs:
                for ch in text:
                    if ord(ch) != BLANK:
                        assert style == view._style(int(frame.colours[y][x])), (y, x)
                    x += 1
            assert x == frame.width
        assert rows_with_dots >= 2


class StaticApp(App[None]):
    def compose(self) -> ComposeResult:
        yield Static("X 1\nY 2", id="lines")


@sync
async def test_show_text_updates_only_what_reads_differently() -> None:
    app = StaticApp()
    async with app.run_test(size=(40, 10)) as pilot:
        await pilot.pause()
        static = app.query_one("#lines", Static)
        updates: list[bool] = []
        update = static.update

        def counted(content: Any = "", *, layout: bool = True) -> None:
            updates.append(layout)
            update(content, layout=layout)

        static.update = counted  # type: ignore[method-assign]
        show_text(static, "X 1\nY 2")
        assert updates == []  # the same text: nothing repainted
        show_text(static, "X 3\nY 2")
        assert updates == [False]  # the same shape: repainted, no layout
        show_text(static, "X 3\nY 2\nZ 4")
        assert updates == [False, True]  # a line more: laid out again
        assert str(static.content) == "X 3\nY 2\nZ 4"


@sync
async def test_the_status_line_repaints_only_when_its_text_changes(tmp_path: Path) -> None:
    app = make_app(tmp_path)
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.press("K")
        await pilot.pause()
        status = app.screen.query_one(StatusLine)
        refreshes: list[int] = []
        refresh = status.refresh

        def counted(*args: Any, **kwargs: Any) -> Any:
            refreshes.append(1)
            return refresh(*args, **kwargs)

        status.refresh = counted  # type: ignore[method-assign]
        app.screen.update_status()
        app.screen.update_status()
        assert refreshes == []  # a pose that changed nothing the line says
        app.session.simulator.set_speed(50.0)
        app.screen.update_status()
        assert refreshes == [1]
        await pilot.pause()
        assert "SP 50" in status.text  # (SPEED 50 where the long words fit)


class LogApp(App[None]):
    def compose(self) -> ComposeResult:
        yield TranscriptLog(id="log")


@sync
async def test_a_line_in_a_full_log_lays_out_no_screen() -> None:
    """Textual lays the screen out (and writes all of it) whenever a log's virtual size changes;
    the transcript asks for a layout only when a scroll bar comes or goes."""
    app = LogApp()
    async with app.run_test(size=(40, 8)) as pilot:
        log = app.query_one(TranscriptLog)
        log.write_lines([f"LINE {n}" for n in range(20)])  # more than it shows: a scroll bar
        await pilot.pause()
        assert log.show_vertical_scrollbar
        layouts: list[int] = []
        screen = app.screen
        refresh_layout = screen._refresh_layout

        def counted(*args: Any, **kwargs: Any) -> None:
            layouts.append(1)
            refresh_layout(*args, **kwargs)

        screen._refresh_layout = counted  # type: ignore[method-assign]
        log.write_lines(["LINE 20", "LINE 21"])
        await pilot.pause()
        assert layouts == []
        # scrolled to the new end, the bar sized for the new lines
        assert log.scroll_y == log.max_scroll_y and log.virtual_size.height == 22
        assert log.vertical_scrollbar.window_virtual_size == 22
        assert "LINE 21" in "\n".join(strip.text for strip in screen._compositor.render_strips())


class AutoBarLogApp(LogApp):
    CSS = "TranscriptLog { overflow-y: auto; }"  # the bar only when the lines need it


@sync
async def test_the_first_lines_past_the_logs_height_bring_its_scroll_bar() -> None:
    """The log grows past its height: the scroll bar comes (a layout), and the lines scroll."""
    app = AutoBarLogApp()
    async with app.run_test(size=(40, 8)) as pilot:
        log = app.query_one(TranscriptLog)
        log.write_lines(["ONE"])
        await pilot.pause()
        assert not log.show_vertical_scrollbar
        log.write_lines([f"LINE {n}" for n in range(20)])
        await pilot.pause()
        assert log.show_vertical_scrollbar and log.scroll_y == log.max_scroll_y


@sync
async def test_a_paced_motion_is_drawn_on_the_streams_frame_clock(tmp_path: Path) -> None:
    """Frames fall at whole multiples of 1 / DRAW_RATE from the stream's start: a tick that
    came late waits less, one just before a frame waits for the one after (no frame twice)."""
    clock = FakeClock()
    app = make_app(tmp_path, rate=40.0, clock=clock)
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.press("K")
        player = app.player
        waits: list[float] = []
        player._schedule = waits.append  # type: ignore[method-assign]
        clock.t += 0.013  # the stream starts between two frames of any clock
        app.run_events(app.session.simulator.drive(1, 60.0))  # 5 poses, about 1/3 s
        origin = player._frame_origin
        assert origin == clock.t
        period = 1.0 / DRAW_RATE
        for late in (0.2, 0.6, 0.9):  # a tick this far into a frame period
            clock.t = origin + 2 * period + late * period
            player._tick()
            assert waits[-1] == pytest.approx((1.0 - late) * period if late < 0.75 else (2.0 - late) * period)
        player.skip_to_end()
        await pilot.pause()


@sync
async def test_a_stream_draws_at_most_one_picture_a_frame(tmp_path: Path) -> None:
    """Ticks a millisecond apart through two motions and the DELAY between them: one picture
    in each frame of the stream's clock at most (a motion's end and the next one's start
    wait for the next frame), the stream's end drawn as it ends."""
    from itertools import chain

    from valterm.core.events import Delay
    from valterm.ui.messages import PictureMoved, RunEnded, SceneShown

    clock = FakeClock()
    app = make_app(tmp_path, rate=40.0, clock=clock)
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.press("K")
        player = app.player
        player._schedule = lambda delay: None  # type: ignore[method-assign]
        simulator = app.session.simulator
        posted: list[tuple[float, object]] = []
        events = chain(simulator.drive(1, 20.0), simulator.drive(2, 15.0), [Delay(0.05)],
                       simulator.drive(3, -15.0))
        player.play(events, lambda message: posted.append((clock.t, message)))
        origin = player._frame_origin
        while player.playing:
            clock.t += 0.001
            player._tick()
        pictures = [t for t, message in posted if isinstance(message, (SceneShown, PictureMoved))]
        frames = [math.floor((t - origin) * DRAW_RATE + 0.25) for t in pictures]
        # the end's picture is drawn at once (no tick comes after it)
        assert frames[:-1] == sorted(set(frames[:-1])), "two pictures in one frame"
        seconds = clock.t - origin
        assert 0.8 * seconds * DRAW_RATE <= len(pictures) <= seconds * DRAW_RATE + 2  # frame 0 and the end
        assert isinstance(posted[-1][1], RunEnded) and isinstance(posted[-2][1], SceneShown)
        await pilot.pause()


class ReadoutApp(App[None]):
    def compose(self) -> ComposeResult:
        yield ReadoutLines(id="where")


@sync
async def test_a_pose_repaints_only_the_readout_lines_that_changed() -> None:
    """The WHERE lines' heads stay, their numbers change at every pose: only those are drawn
    again (their strips rebuilt, their rows alone marked for the screen)."""
    app = ReadoutApp()
    async with app.run_test(size=(40, 10)) as pilot:
        readout = app.query_one(ReadoutLines)
        readout.show_lines(["X Y", "1 2", "J1 J2", "10 20"])
        await pilot.pause()
        assert readout.size.height == 4
        strips = [readout.render_line(y) for y in range(4)]
        regions: list[tuple[Any, ...]] = []
        refresh = readout.refresh

        def counted(*args: Any, **kwargs: Any) -> Any:
            regions.append(args)
            return refresh(*args, **kwargs)

        readout.refresh = counted  # type: ignore[method-assign]
        readout.show_lines(["X Y", "1 2", "J1 J2", "10 20"])
        assert regions == []  # nothing reads differently
        readout.show_lines(["X Y", "3 4", "J1 J2", "10 20"])
        assert [tuple(region.y for region in args) for args in regions] == [(1,)]
        after = [readout.render_line(y) for y in range(4)]
        assert [a is b for a, b in zip(after, strips)] == [True, False, True, True]
        await pilot.pause()
        rows = [strip.text for strip in app.screen._compositor.render_strips()]
        assert rows[1].startswith("3 4") and rows[3].startswith("10 20")


def test_the_trace_is_one_array_until_it_changes() -> None:
    """The picture asks for the tool path 30 times a second: the same arrays come back until
    a point is added or the trace is cleared (a long session's trace holds thousands)."""
    trace = Trace([(0.0, 0.0, 0.0), (100.0, 0.0, 0.0)])
    points, segments = trace.points(), trace.segments()
    assert trace.points() is points and trace.segments() is segments
    assert not points.flags.writeable  # shared: no one may change it in place
    trace.add((100.0, 0.0, 0.0))  # where the path already is: no new point
    assert trace.points() is points
    trace.add((100.0, 200.0, 0.0))
    assert trace.points() is not points and len(trace.points()) == 3
    assert trace.segments().tolist() == [[[0.0, 0.0, 0.0], [100.0, 0.0, 0.0]],
                                         [[100.0, 0.0, 0.0], [100.0, 200.0, 0.0]]]
    trace.clear()
    assert len(trace.points()) == 0 and len(trace.segments()) == 0


@sync
async def test_a_partial_update_renders_only_the_rows_it_writes(tmp_path: Path) -> None:
    """The screen's compositor writes what Textual's own writes for the same dirty regions
    (picture rows, a readout row), but renders only the written rows of the widgets that
    show in them: a picture row renders no container behind the picture (Textual rendered
    every line of every widget whose container the update touched)."""
    from textual._compositor import ChopsUpdate, Compositor
    from textual.geometry import Region
    from textual.widget import Widget

    from valterm.testing import Simulation
    from valterm.ui.compositor import RowCompositor

    async with Simulation(tmp_path, size=(160, 50)) as sim:
        await sim.press("V", "V")
        screen = sim.app.screen
        compositor = screen._compositor
        assert isinstance(compositor, RowCompositor)
        model = screen.query_one(ModelView)
        x = model.region.x
        assert model.frame is not None
        dotted = [y for y in range(49) if (model.frame.chars[y] != BLANK).any()]
        top, low = dotted[len(dotted) // 3], dotted[2 * len(dotted) // 3]  # rows with dots
        rendered: list[tuple[str, int]] = []
        render_lines = Widget.render_lines

        def counted(self: Widget, crop: Region) -> Any:
            rendered.append((type(self).__name__, crop.height))
            return render_lines(self, crop)

        for regions in ([Region(x + 8, top, 70, 1), Region(x, low, 80, 2)],
                        [Region(x + 8, top, 70, 1), Region(0, 43, 60, 1), Region(x, 47, 88, 1)]):
            spans = list(compositor._regions_to_spans(regions))
            rows = {y for y, _, _ in spans}
            crop = Region.from_union(regions)
            Widget.render_lines = counted  # type: ignore[method-assign]
            try:
                ours = compositor._render_chops(crop, rows.__contains__)
            finally:
                Widget.render_lines = render_lines  # type: ignore[method-assign]
            theirs = Compositor._render_chops(compositor, crop, rows.__contains__)
            ends = [cut_set[1:] for cut_set in compositor.cuts]
            written = ChopsUpdate(ours, spans, ends).render_segments(sim.app.console)
            assert written == ChopsUpdate(theirs, spans, ends).render_segments(sim.app.console)
            assert any("\u2801" <= ch <= "\u28ff" for ch in written)  # the picture's dots among it
            if len(regions) == 2:  # the picture's rows alone: the picture renders them, no one else
                assert rendered == [("ModelView", 1), ("ModelView", 2)]
            else:
                assert sum(height for _, height in rendered) <= 4 * len(rows)
            rendered.clear()


def test_a_row_is_written_from_where_its_update_starts() -> None:
    """A picture row changed at its right end: the cells from the update's start are
    written, not the row from the widget's left edge; a row with a wide character before
    the start is written as Textual writes it (from the piece's start: no half character)."""
    from rich.console import Console
    from rich.segment import Segment
    from textual._compositor import ChopsUpdate
    from textual.strip import Strip

    from valterm.ui.compositor import SpanUpdate

    console = Console(color_system="truecolor", force_terminal=True)
    red, blue = Style(color="red"), Style(color="blue")
    left = Strip([Segment("MENU      ", None)], 10)
    picture = Strip([Segment("  ⠁⠂  ", red), Segment("⣿⣿⣿⣿⣿⣿⣿⣿⣿⣿⣿⣿⣿⣿", blue)], 20)
    chops = [{0: left, 10: picture}]
    spans = [(0, 26, 29)]  # cells 26-28: three of the blue run
    written = SpanUpdate(chops, spans, [[10, 30]]).render_segments(console)
    assert written == "\x1b[1;27H" + Strip([Segment("⣿⣿⣿", blue)], 3).render(console)
    textual = ChopsUpdate(chops, spans, [[10, 30]]).render_segments(console)
    assert textual.startswith("\x1b[1;11H") and len(written) < len(textual)
    # an update from the piece's start, to its end: the same as Textual's
    spans = [(0, 10, 30)]
    assert SpanUpdate(chops, spans, [[10, 30]]).render_segments(console) == \
        ChopsUpdate(chops, spans, [[10, 30]]).render_segments(console)
    wide = [{0: left, 10: Strip([Segment("漢字" + "⣿" * 16, red)], 20)}]
    spans = [(0, 13, 20)]  # starts inside the characters after the wide ones
    assert SpanUpdate(wide, spans, [[10, 30]]).render_segments(console) == \
        ChopsUpdate(wide, spans, [[10, 30]]).render_segments(console)


def _cells(written: str) -> dict[tuple[int, int], tuple[str, str, str]]:
    """What a terminal shows after ``written``: (row, column) -> (character, foreground,
    background), for the cursor moves and colour sequences a frame uses."""
    import re

    cells: dict[tuple[int, int], tuple[str, str, str]] = {}
    y = x = 0
    fg = bg = "default"
    for move, sgr, char in re.findall(r"\x1b\[(\d+;\d+)H|\x1b\[([\d;]*)m|(.)", written, re.S):
        if move:
            row, column = move.split(";")
            y, x = int(row) - 1, int(column) - 1
        elif char:
            cells[y, x] = (char, fg, bg)
            x += 1
        else:
            codes = sgr.split(";")
            while codes:
                code = codes.pop(0)
                if code in ("", "0"):
                    fg = bg = "default"
                elif code in ("38", "48"):
                    colour = ";".join(codes[:4]) if codes[0] == "2" else ";".join(codes[:2])
                    codes = codes[4:] if codes[0] == "2" else codes[2:]
                    fg, bg = (colour, bg) if code == "38" else (fg, colour)
                else:
                    raise AssertionError(f"a code the test does not read: {code}")
    return cells


def test_colour_runs_set_only_the_colours_that_change() -> None:
    """A row of plain colour runs shows on a terminal exactly as Textual writes it, in fewer
    bytes: the background once, no reset between runs, one at the end; a run with an
    attribute is written as Textual writes it."""
    from rich.console import Console
    from rich.segment import Segment
    from textual.strip import Strip

    from valterm.ui.compositor import colour_runs

    console = Console(color_system="truecolor", force_terminal=True)
    ground = Style(bgcolor="rgb(18,18,18)")
    runs = [Segment("  ⠁⠂", ground + Style(color="rgb(255,135,0)")),
            Segment("⣿⣿", ground + Style(color="rgb(158,158,158)")),
            Segment(" ⢸", ground + Style(color="rgb(255,135,0)")),
            Segment("AB", Style(color="rgb(255,135,0)", bgcolor="rgb(0,0,90)"))]
    strip = Strip(runs, 10)
    ours, textual = colour_runs(strip, console), strip.render(console)
    assert _cells("\x1b[3;5H" + ours) == _cells("\x1b[3;5H" + textual)
    assert ours.count("48;2;18;18;18") == 1 and ours.count("\x1b[0m") == 1 and ours.endswith("\x1b[0m")
    assert len(ours) < 0.7 * len(textual)
    bold = Strip([*runs, Segment("!", ground + Style(color="red", bold=True))], 11)
    assert colour_runs(bold, console) == bold.render(console)
