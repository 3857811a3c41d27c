"""Textual's compositor, rendering only the rows a partial update writes (issue 40).

Textual (pinned 8.2) renders, for a partial update, every line of every widget whose
container overlaps the updated area, then keeps the lines the update writes: when the
picture changes a dozen of its rows, the screen, the row of panels, the text column and the
status line were rendered whole (about 200 lines a frame) for the dozen written. Here a
widget beside the updated area renders nothing, and one in it only the rows the update
writes that no widget in front of it has already covered, a run of rows at a time; what is
written is the same. A full update (a layout, a
screenshot) is Textual's own.

What is written of a row starts where the row's update starts (``SpanUpdate``): Textual wrote
each widget's piece of a row from the widget's left edge, so a picture row changed at its
right end was written whole, a colour sequence for every run on the way. And a run of plain
colour (no bold, no link) sets only the colours that differ from the run before it, with no
reset between them (``colour_runs``): Textual writes both colours and a reset for each run,
about 36 bytes where the picture's dots change colour and 16 are the background's.

A picture's changed spans can skip the compositor altogether (``written_past``): while the
widget shows whole on the screen that has the terminal, nothing in front of it, its changed
rows are rendered (Textual's own pipeline, the widget's rows only) and written straight to the
driver in one synchronized write, the cursor left where Textual leaves it. Textual's frame
(its idle pass, the compositor's spans and chops, the other widgets' rows) costs about as
much as the picture itself; a picture moving at 30 frames a second paid it at every frame.
Anything else (a screen over it, a toast, a layout due, a terminal behind) and the caller
refreshes as before: what Textual draws later reads the same rows.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from functools import lru_cache
from itertools import pairwise

from rich.cells import cell_len
from rich.color import ColorSystem
from rich.console import Console
from rich.control import Control
from rich.segment import Segment
from rich.style import Style
from textual._ansi_sequences import SYNC_END, SYNC_START
from textual._compositor import ChopsUpdate, Compositor
from textual.geometry import Region
from textual.strip import Strip
from textual.widget import Widget

from valterm.ui.terminal_writer import FrameGate


class SpanUpdate(ChopsUpdate):
    """Textual's partial update, each row written from where its update starts."""

    def render_segments(self, console: Console) -> str:
        sequences: list[str] = []
        append = sequences.append
        last_y = self.spans[-1][0]
        for y, x1, x2 in self.spans:
            for end, (x, strip) in zip(self.chop_ends[y], self.chops[y].items()):
                if strip is None or x > x2 or end <= x1:
                    continue
                start = x1 - x if x < x1 and narrow(strip.text[: x1 - x]) else 0
                if start or end > x2:
                    strip = strip.crop(start, min(end, x2) - x)
                append(Control.move_to(x + start, y).segment.text)
                append(colour_runs(strip, console))
            if y != last_y:
                append("\n")
        return "".join(sequences)


def colour_runs(strip: Strip, console: Console) -> str:
    """The strip as terminal sequences (``coded_runs``); Textual's own rendering when a run is
    more than a foreground and a background (an attribute, a link, a control, no colour)."""
    system = console._color_system or ColorSystem.TRUECOLOR  # as Textual's Strip.render
    text = coded_runs((text, None if control or style is None else _colour_codes(style, system))
                      for text, style, control in strip)
    return strip.render(console) if text is None else text


def coded_runs(runs: Iterable[tuple[str, tuple[str, str] | None]]) -> str | None:
    """Runs of text, each with its foreground and background codes, as terminal sequences:
    each run sets only the codes that differ from the run before it, one reset at the end;
    None when a run has no codes (more than two colours: the caller writes it another way)."""
    out: list[str] = []
    fg = bg = ""
    for text, codes in runs:
        if codes is None:
            return None
        if codes[0] != fg:
            out.append(f"\x1b[{codes[0]};{codes[1]}m" if codes[1] != bg else f"\x1b[{codes[0]}m")
        elif codes[1] != bg:
            out.append(f"\x1b[{codes[1]}m")
        out.append(text)
        fg, bg = codes
    if out:
        out.append("\x1b[0m")
    return "".join(out)


def content_only_filtered(widget: Widget) -> bool:
    """Whether Textual's pipeline does nothing to the widget's content cells but apply its
    line filters (no border, outline, tint, opacity, hatch: padding is its own cells)."""
    styles = widget.styles
    return not (styles.border or styles.outline or styles.tint.a or widget.opacity != 1.0
                or styles.text_opacity != 1.0 or styles.has_rule("hatch"))


def plain_codes(widget: Widget, style: Style) -> tuple[str, str] | None:
    """The foreground and background codes ``colour_runs`` writes for a content cell of
    ``style`` once Textual's pipeline has applied the widget's line filters (the ANSI colours
    made true colours, NO_COLOR's monochrome); None when it is more than two colours."""
    strip = Strip([Segment(" ", style)], 1)
    background = widget.background_colors[1]
    for line_filter in widget.get_line_filters():
        strip = strip.apply_filter(line_filter, background)
    filtered = next(iter(strip)).style
    system = widget.app.console._color_system or ColorSystem.TRUECOLOR  # as colour_runs
    return None if filtered is None else _colour_codes(filtered, system)


@lru_cache(maxsize=1024)
def _colour_codes(style: Style, system: ColorSystem) -> tuple[str, str] | None:
    """A style's foreground and background codes; None when it is more than those two."""
    if style._color is None or style._bgcolor is None or style._link or style._attributes & style._set_attributes:
        return None
    return (";".join(style._color.downgrade(system).get_ansi_codes()),
            ";".join(style._bgcolor.downgrade(system).get_ansi_codes(False)))


def narrow(text: str) -> bool:
    """Each character one cell (no wide one to cut in half, nothing of no width)."""
    return cell_len(text) == len(text)


class RowCompositor(Compositor):
    """A compositor that renders a partial update's written rows only, and writes each row
    from where its update starts."""

    def render_partial_update(self) -> ChopsUpdate | None:
        update = super().render_partial_update()
        if update is None:
            return None
        return SpanUpdate(update.chops, update.spans, update.chop_ends)

    def _render_chops(self, crop: Region, is_rendered_line: Callable[[int], bool]) -> Sequence[Mapping[int, Strip]]:
        if crop == self.size.region:  # a full update: every row
            return super()._render_chops(crop, is_rendered_line)
        cuts = self.cuts
        chops: list[dict[int, Strip | None]] = [dict.fromkeys(cut_set[:-1]) for cut_set in cuts]
        # front to back, as Textual paints: the first strip a cut gets is the one it shows
        for widget, (region, clip) in self.visible_widgets.items():
            shown = region.intersection(clip)
            if not crop.overlaps(shown):  # (Textual asks only of its container's)
                continue
            first, last = shown.column_span
            rows = [y for y in range(max(shown.y, crop.y), min(shown.bottom, crop.bottom))
                    if is_rendered_line(y) and _open(chops[y], cuts[y], max(first, crop.x), min(last, crop.right))]
            for start, end in _runs(rows):
                strips = widget.render_lines(Region(shown.x - region.x, start - region.y, shown.width, end - start))
                for y, strip in zip(range(start, end), strips):
                    line_cuts = [cut for cut in cuts[y] if last >= cut >= first]
                    chops_line = chops[y]
                    for cut, piece in zip(line_cuts, strip.divide([cut - shown.x for cut in line_cuts[1:]])):
                        if chops_line.get(cut) is None:
                            chops_line[cut] = piece
        return chops  # type: ignore[return-value]  # every written row's cuts are filled


def _open(chops_line: Mapping[int, Strip | None], line_cuts: list[int], first: int, last: int) -> bool:
    """Whether a piece of the row (from a cut to the next) between columns ``first`` and
    ``last`` has no strip yet (a piece outside them is never written)."""
    return any(chops_line.get(cut, 0) is None for cut, end in pairwise(line_cuts)
               if end > first and cut < last)


def _runs(rows: list[int]) -> Iterator[tuple[int, int]]:
    """Consecutive rows as (start, end) runs."""
    start = previous = None
    for y in rows:
        if previous is not None and y == previous + 1:
            previous = y
            continue
        if start is not None and previous is not None:
            yield start, previous + 1
        start = previous = y
    if start is not None and previous is not None:
        yield start, previous + 1


def written_past(widget: Widget, spans: Sequence[tuple[int, int, int]]) -> bool:
    """Write the widget's changed ``spans`` (row, first column, end column; its content's
    coordinates, as ``refresh`` takes regions) straight to the terminal, past the compositor;
    False (nothing written) when
    it may not be, the caller then refreshes the spans the usual way. True also when the
    frame gate skips the frame: the terminal is behind, the whole screen is drawn when it
    catches up."""
    app = widget.app
    driver = app._driver
    if driver is None or driver.is_headless or driver.is_inline or app._batch_count or not app._running:
        return False
    screen = widget.screen
    if screen is not app.screen or screen._layout_required or not spans:
        return False
    placed = _uncovered(screen._compositor, widget)
    if placed is None:
        return False
    x, y = widget.content_offset  # the spans in the widget's own (outer) coordinates
    spans = [(row + y, a + x, b + x) for row, a, b in spans]
    widget._styles_cache.set_dirty(*(Region(a, row, b - a, 1) for row, a, b in spans))
    gate = getattr(driver, "gate", None)
    if isinstance(gate, FrameGate) and not gate.admit():
        return True
    text = _span_text(widget, placed, spans, app.console)
    cursor = screen.outer_size.clamp_offset(app.cursor_position)
    text += Control.move_to(*cursor).segment.text
    if app._sync_available:
        text = SYNC_START + text + SYNC_END
    mark = gate.handed if isinstance(gate, FrameGate) else 0
    driver.write(text)
    driver.flush()
    if isinstance(gate, FrameGate):
        gate.drawn(mark)
    return True


def _uncovered(compositor: Compositor, widget: Widget) -> Region | None:
    """The widget's region on the screen when it shows whole (not clipped, no widget in front
    of any of it); None otherwise."""
    shown = compositor.visible_widgets.get(widget)
    if shown is None:
        return None
    region, clip = shown
    if region.intersection(clip) != region or region.size != widget.outer_size:
        return None
    for other, (other_region, other_clip) in compositor.visible_widgets.items():
        if other is widget:
            return region
        if other_region.intersection(other_clip).overlaps(region):
            return None
    return None


def _span_text(widget: Widget, placed: Region, spans: Sequence[tuple[int, int, int]], console: Console) -> str:
    """The spans' cells (the widget's outer coordinates) as terminal sequences, each from
    where it changed (as SpanUpdate): the widget's own (its ``span_text``, the picture's,
    made with no strip) or, without one, its rows through Textual's pipeline."""
    own = getattr(widget, "span_text", None)
    text = own(spans, placed.x, placed.y) if callable(own) else None
    if isinstance(text, str):
        return text
    return textual_span_text(widget, placed, spans, console)


def textual_span_text(widget: Widget, placed: Region, spans: Sequence[tuple[int, int, int]], console: Console) -> str:
    """The spans' cells as terminal sequences, the rows rendered by Textual's pipeline."""
    rows = sorted({y for y, _, _ in spans})
    lines: dict[int, Strip] = {}
    for start, end in _runs(rows):
        lines.update(zip(range(start, end), widget.render_lines(Region(0, start, placed.width, end - start))))
    out: list[str] = []
    for y, a, b in spans:
        strip = lines[y]
        if a and not narrow(strip.text[:a]):
            a = 0  # a wide character before the span: from the row's start (no half of it)
        out.append(Control.move_to(placed.x + a, placed.y + y).segment.text)
        out.append(colour_runs(strip.crop(a, b) if a or b < placed.width else strip, console))
    return "".join(out)
