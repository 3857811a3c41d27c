"""The picture's changed spans written past Textual's compositor (issue 40 item 1): made
from the frame's arrays, they read on a terminal as Textual's pipeline writes the same rows,
and they never land on what covers the picture (a help screen, a toast)."""

from __future__ import annotations

import random
import re
from pathlib import Path
from typing import Any

from app_helpers import sync
from valterm.testing import Simulation
from valterm.ui.compositor import textual_span_text, written_past
from valterm.ui.view.model_view import ModelView
from valterm.ui.widgets.readouts import ReadoutLines

_SEQUENCE = re.compile(r"\x1b\[([\d;?]*)([A-Za-z])|\x1b\][^\x07\x1b]*(?:\x07|\x1b\\)|\x1b[=>78]|(.)", re.S)
def _standard(codes: list[str], foreground: bool) -> str:
    """A 256-colour or truecolour code as the 16-colour one it stands for: Rich keeps a
    style's sequence from the first console that rendered it, so one colour can come as
    either in a test process (Textual's headless console has 16 colours)."""
    from rich.color import Color, ColorSystem

    colour = Color.from_ansi(int(codes[1])) if codes[0] == "5" else Color.from_rgb(*map(float, codes[1:4]))
    return ";".join(colour.downgrade(ColorSystem.STANDARD).get_ansi_codes(foreground))


_ATTRIBUTE_OFF = {"21": "1", "22": "12", "23": "3", "24": "4", "25": "5", "27": "7", "28": "8", "29": "9"}


class Terminal:
    """What a terminal shows after what it was written: (row, column) -> (character,
    foreground, background, attributes), for the cursor moves and SGR sequences Textual
    writes (any other sequence moves nothing here)."""

    def __init__(self) -> None:
        self.cells: dict[tuple[int, int], tuple[str, str, str, str]] = {}
        self.y = self.x = 0
        self.fg = self.bg = "default"
        self.attributes: set[str] = set()

    def seen(self) -> dict[tuple[int, int], tuple[str, str, str, str]]:
        """The cells as a person sees them: a space shows its background only."""
        return {cell: ((char, "", bg, "") if char == " " else (char, fg, bg, attributes))
                for cell, (char, fg, bg, attributes) in self.cells.items()}

    def feed(self, written: str) -> None:
        for parameters, final, char in _SEQUENCE.findall(written):
            if char:
                if char not in "\r\n\x07":
                    self.cells[self.y, self.x] = (char, self.fg, self.bg, "".join(sorted(self.attributes)))
                    self.x += 1
            elif final == "H":
                row, _, column = parameters.partition(";")
                self.y, self.x = int(row or 1) - 1, int(column or 1) - 1
            elif final == "m":
                self._sgr(parameters.split(";"))

    def _sgr(self, codes: list[str]) -> None:
        while codes:
            code = codes.pop(0)
            if code in ("", "0"):
                self.fg = self.bg = "default"
                self.attributes.clear()
            elif code in ("38", "48"):
                size = 4 if codes[0] == "2" else 2
                colour, codes = _standard(codes[:size], code == "38"), codes[size:]
                if code == "38":
                    self.fg = colour
                else:
                    self.bg = colour
            elif code == "39":
                self.fg = "default"
            elif code == "49":
                self.bg = "default"
            elif code in _ATTRIBUTE_OFF:
                self.attributes.difference_update(_ATTRIBUTE_OFF[code])
            elif 30 <= int(code) <= 37 or 90 <= int(code) <= 97:
                self.fg = code
            elif 40 <= int(code) <= 47 or 100 <= int(code) <= 107:
                self.bg = code
            else:
                self.attributes.add(code)


def _repainted(app: Any) -> dict[tuple[int, int], tuple[str, str, str, str]]:
    """The screen as Textual draws it whole (a resize, a repaint)."""
    terminal = Terminal()
    terminal.feed(app.screen._compositor.render_update(full=True).render_segments(app.console))
    return terminal.seen()


@sync
async def test_the_pictures_spans_read_as_textuals_pipeline_writes_them(tmp_path: Path) -> None:
    """Spans of a picture that moved (its caption on the last row among them) written from
    the frame's arrays show on a terminal cell for cell as the same spans of the rows Textual's
    pipeline renders, and take the same bytes (the same runs and colour codes); so do the
    WHERE lines' spans (a padded widget, a line longer than it)."""
    async with Simulation(tmp_path, size=(160, 50)) as sim:
        await sim.press("V", "V")
        model = sim.screen.query_one(ModelView)
        placed = model.region
        chances = random.Random(40)
        for turn in range(4):
            if turn == 3:  # another theme: another background, the codes made again
                sim.app.theme = "textual-light"
            model.rotate_by("z", 7.0 + turn)
            await sim.pilot.pause()
            frame = model.frame
            assert frame is not None and model.caption
            spans = [(y, 0, frame.width) for y in range(frame.height)]
            spans += [(y, chances.randrange(0, 40), chances.randrange(40, frame.width)) for y in range(frame.height)]
            spans = sorted(spans + list(model.dirty_spans), key=lambda span: span[0])  # by row, as written
            model._styles_cache.clear()  # the rows as Textual renders them now
            ours = model.span_text(spans, placed.x, placed.y)
            theirs = textual_span_text(model, placed, spans, sim.app.console)
            assert ours is not None and any("\u2801" <= ch <= "\u28ff" for ch in ours)
            assert ours == theirs
            readout = sim.screen.query_one(ReadoutLines)  # the WHERE lines (padded), one long
            readout.show_lines([*readout.lines[:-1], "X" * (readout.size.width + 5)])
            await sim.pilot.pause()
            left, top = readout.content_offset
            rows = [(row + top, left + a, left + readout.size.width - b)
                    for row in range(len(readout.lines)) for a, b in ((0, 0), (3, 9))]
            readout._styles_cache.clear()
            shown = readout.span_text(rows, readout.region.x, readout.region.y)
            assert shown is not None and shown == textual_span_text(readout, readout.region, rows, sim.app.console)
            written, read = Terminal(), Terminal()
            written.feed(ours)
            read.feed(sim.app.screen._compositor.render_update(full=True).render_segments(sim.app.console))
            assert all(read.cells[cell] == shown for cell, shown in written.cells.items())


class ToastSimulation(Simulation):
    """The app as Simulation runs it, its toasts shown (Textual's tests hide them)."""

    async def __aenter__(self) -> ToastSimulation:
        self._context = self.app.run_test(size=self.size, notifications=True)
        self.pilot = await self._context.__aenter__()
        await self.pilot.pause()
        return self


async def _terminal_app(sim: Simulation, monkeypatch: Any) -> Terminal:
    """The headless app writing to a terminal that reads it (as a pty's would)."""
    from textual.drivers.headless_driver import HeadlessDriver

    terminal = Terminal()
    monkeypatch.setattr(HeadlessDriver, "is_headless", property(lambda driver: False))
    sim.app._driver.write = terminal.feed  # type: ignore[union-attr, method-assign]
    sim.app.refresh()
    await sim.pilot.pause()
    return terminal


@sync
async def test_the_picture_written_past_the_compositor_shows_what_textual_would(
        tmp_path: Path, monkeypatch: Any) -> None:
    """A motion drawn at real pace: the picture's frames go past the compositor while nothing
    covers the picture, and the terminal then reads as Textual's own whole repaint; a help
    screen over it, and a toast over its corner, are never drawn over (Textual draws the
    picture then)."""
    from valterm.ui.screens.help import HelpScreen

    async with ToastSimulation(tmp_path, size=(160, 50), animate=True) as sim:
        await sim.press("V", "V")
        terminal = await _terminal_app(sim, monkeypatch)
        passed: list[bool] = []
        readouts: list[bool] = []  # the WHERE lines (padded: their rows made by Textual)
        model = sim.screen.query_one(ModelView)
        counted = written_past

        def past(widget: Any, spans: Any) -> bool:
            (passed if widget is model else readouts).append(counted(widget, spans))
            return (passed if widget is model else readouts)[-1]

        monkeypatch.setattr("valterm.ui.view.model_view.written_past", past)
        monkeypatch.setattr("valterm.ui.widgets.readouts.written_past", past)
        await sim.type("DRIVE 1,-120,30", enter=True)
        for _ in range(4):
            await sim.advance(0.1)
        assert sim.moving and any(passed) and any(readouts), "no frame went past the compositor"
        assert terminal.seen() == _repainted(sim.app)
        for cover in ("help", "toast"):
            if cover == "help":
                sim.app.push_screen(HelpScreen(""))
            else:
                sim.app.notify("A TOAST OVER THE PICTURE", timeout=30)
            await sim.pilot.pause(0.1)
            await sim.pilot.pause()
            passed.clear()
            await sim.advance(0.1)
            model.rotate_by("z", 45.0)  # the picture changes nearly everywhere, under the cover too
            model.scale_by(2.5 if cover == "help" else 0.4)
            await sim.pilot.pause()
            assert terminal.seen() == _repainted(sim.app), cover
            assert passed and not any(passed) and sim.moving, cover
            if cover == "help":
                sim.app.pop_screen()
                await sim.pilot.pause()
                assert terminal.seen() == _repainted(sim.app)
