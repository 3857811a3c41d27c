"""The model view widget: the braille wireframe of robot and cell, drawn with the Line API.

It rasterizes only when the scene, a view option or its size changes, and then repaints
only the row spans that differ from the previous frame, so one pose over SSH costs a few
kilobytes. Without a scene it is blank and has loaded neither the raster nor numpy: the
app's first frame is drawn before the session is read (issue 25, the start).
"""

from __future__ import annotations

import sys
import time
from typing import TYPE_CHECKING, Iterator, Mapping, Sequence

from rich.color import Color
from rich.segment import Segment
from rich.style import Style
from textual.events import Resize
from textual.geometry import Region
from textual.reactive import var
from textual.strip import Strip
from textual.widget import Widget

from valterm.core.render.legend import (
    AXES_COLOUR,
    DIM_OFFSET,
    GHOST_COLOUR,
    HIGHLIGHT_COLOUR,
    LED_COLOUR,
    LINK_COLOUR_BASE,
    N_OBJECT_COLOURS,
    OBJECT_COLOUR_BASE,
    SEEN_COLOUR,
    TRACE_COLOUR,
)
from valterm.ui.compositor import coded_runs, content_only_filtered, narrow, plain_codes, written_past

if TYPE_CHECKING:
    import numpy as np

    from valterm.core.render.raster import Frame, Scene, ViewTransform

# Colour index -> terminal colour: warm tones for the robot, cool/bright ones for objects,
# all light enough for dark backgrounds (256-colour names degrade well over SSH).
_LINK_COLOURS = ("grey70", "gold1", "orange1", "light_goldenrod1", "dark_orange", "khaki1", "wheat1", "sandy_brown")
_OBJECT_COLOURS = (
    "deep_sky_blue1", "spring_green1", "orchid1", "light_sky_blue1", "pale_green1", "plum1",
    "aquamarine1", "medium_purple1", "sky_blue1", "light_green", "violet", "turquoise2",
    "cornflower_blue", "green_yellow", "hot_pink", "cyan1",
)
BRIGHT_PALETTE: dict[int, str] = {
    AXES_COLOUR: "grey62",
    LED_COLOUR: "red1",
    HIGHLIGHT_COLOUR: "bright_red",
    TRACE_COLOUR: "magenta1",
    GHOST_COLOUR: "white",
    SEEN_COLOUR: "yellow1",
    **{LINK_COLOUR_BASE + i: c for i, c in enumerate(_LINK_COLOURS)},
    **{OBJECT_COLOUR_BASE + i: c for i, c in enumerate(_OBJECT_COLOURS[:N_OBJECT_COLOURS])},
}


def _dim(name: str, amount: float = 0.55) -> str:
    """The same colour, darker (the depth cue for what is far from the viewer)."""
    r, g, b = Color.parse(name).get_truecolor()
    return f"rgb({int(r * amount)},{int(g * amount)},{int(b * amount)})"


DEFAULT_PALETTE: dict[int, str] = {
    **BRIGHT_PALETTE,
    **{index + DIM_OFFSET: _dim(name) for index, name in BRIGHT_PALETTE.items()},
}


def braille_supported(stream: object = None) -> bool:
    """Whether the output can carry braille (a UTF encoding); else use the ASCII fallback."""
    encoding = getattr(sys.stdout if stream is None else stream, "encoding", None) or ""
    return "utf" in encoding.lower()


class ModelView(Widget):
    """The robot and its work cell as a wireframe (§2.1-§2.3).

    Feed it with :meth:`update_scene` (None: blank); ORIENT goes through :meth:`rotate_by`,
    :meth:`scale_by`, :meth:`pan_by`, :meth:`reset_view` (or :meth:`set_view`).
    ``back_faces`` (FACES), ``axes`` (AXES) and ``ascii`` (no braille) are settable.
    """

    DEFAULT_CSS = """
    ModelView {
        width: 1fr;
        height: 1fr;
    }
    """

    # var, not reactive: a change must not repaint the whole widget, redraw() does it by rows
    back_faces: var[bool] = var(True)
    axes: var[bool] = var(False)
    ascii: var[bool] = var(False)

    def __init__(
        self,
        scene: Scene | None = None,
        view: ViewTransform | None = None,
        *,
        back_faces: bool = True,
        axes: bool = False,
        ascii: bool = False,
        palette: Mapping[int, str] | None = None,
        dot_aspect: float = 1.0,
        name: str | None = None,
        id: str | None = None,
        classes: str | None = None,
    ) -> None:
        super().__init__(name=name, id=id, classes=classes)
        self.set_reactive(ModelView.back_faces, back_faces)
        self.set_reactive(ModelView.axes, axes)
        self.set_reactive(ModelView.ascii, ascii)
        self._scene = scene
        self._view = view
        self._palette = dict(DEFAULT_PALETTE if palette is None else palette)
        self.dot_aspect = dot_aspect
        self._styles: dict[int, Style] = {}
        self._base_style: Style | None = None  # the widget's own (rich_style walks its ancestors)
        self._frame: Frame | None = None
        self._strips: list[Strip | None] = []
        self._drawn_key: tuple[object, ...] | None = None
        self._scene_version = 0  # not id(scene): a freed scene's id can come back
        # bookkeeping of the last redraw (for tests and `valterm bench`)
        self.redraws = 0
        self.dirty_rows: tuple[int, ...] = ()
        self.dirty_spans: tuple[tuple[int, int, int], ...] = ()  # (row, x0, x1)
        self.last_raster_ms = 0.0
        self.caption = ""  # shown over the last row (see _update_caption)
        self._painting = False  # render_line draws the picture for the frame being painted
        # the colours' terminal codes (span_text), kept until the style changes (_restyle)
        self._codes: dict[int, tuple[str, str] | None] = {}
        self._plain: bool | None = None  # Textual's pipeline only filters the rows (None: not looked at)

    # -- inputs --------------------------------------------------------------------
    @property
    def scene(self) -> Scene | None:
        return self._scene

    @property
    def view(self) -> ViewTransform:
        """The current view transform (mutating it in place needs a :meth:`redraw`)."""
        if self._view is None:
            from valterm.core.render.raster import ViewTransform

            self._view = ViewTransform()
        return self._view

    @property
    def frame(self) -> Frame | None:
        return self._frame

    def update_scene(self, scene: Scene | None) -> None:
        if scene is not self._scene:
            self._scene = scene
            self._scene_version += 1
        self.redraw()

    def set_view(self, view: ViewTransform) -> None:
        self._view = view
        self.redraw()

    def rotate_by(self, axis: str, degrees: float) -> None:
        self.view.rotate_by(axis, degrees)
        self.redraw()

    def scale_by(self, factor: float) -> None:
        self.view.scale_by(factor)
        self.redraw()

    def pan_by(self, dx: float, dy: float) -> None:
        self.view.pan_by(dx, dy)
        self.redraw()

    def reset_view(self) -> None:
        self.view.reset()
        self.redraw()

    def fit(self, bounds: tuple[Sequence[float], Sequence[float]] | None = None) -> None:
        """Fit the view to ``bounds`` (world lo, hi), by default the current scene's."""
        if bounds is not None:
            self.view.fit(bounds)
        elif self._scene is not None:
            self.view.fit(self._scene.bounds())
        else:
            return  # no scene, nothing to fit
        self.redraw()

    def set_palette(self, palette: Mapping[int, str]) -> None:
        self._palette = dict(palette)
        self._restyle()

    def watch_back_faces(self) -> None:
        self.redraw()

    def watch_axes(self) -> None:
        self.redraw()

    def watch_ascii(self) -> None:
        self.redraw()

    def on_resize(self, event: Resize) -> None:
        self.redraw()

    def notify_style_update(self) -> None:
        super().notify_style_update()
        self._restyle()

    # -- drawing -------------------------------------------------------------------
    def redraw(self, force: bool = False) -> None:
        """Rasterize if anything that shows changed, and repaint the changed row spans."""
        if not self.is_mounted:
            return
        width, height = self.size
        if width <= 0 or height <= 0:
            return  # hidden (a narrow screen shows the menu): nothing to draw until a size comes
        if self._scene is None:
            self._blank()
            return
        self._update_caption(height)
        key = (self._scene_version, self.view.key(), self.back_faces, self.axes, self.ascii, width, height)
        if key == self._drawn_key and not force:
            return
        self._drawn_key = key
        from valterm.core.render.raster import rasterize  # loaded with the first scene

        t0 = time.perf_counter()
        frame = rasterize(self._scene, self.view, width, height, back_faces=self.back_faces,
                          axes=self.axes, ascii=self.ascii, dot_aspect=self.dot_aspect)
        self.last_raster_ms = (time.perf_counter() - t0) * 1000
        previous = self._frame
        rows, x0, x1 = frame.changed_spans(previous)
        self._frame = frame
        self.redraws += 1
        self.dirty_rows = tuple(int(r) for r in rows)
        self.dirty_spans = tuple((int(r), int(a), int(b)) for r, a, b in zip(rows, x0, x1))
        if previous is None or previous.chars.shape != frame.chars.shape:
            self._strips = [None] * height
            if not self._painting:
                self.refresh()
            return
        for r in self.dirty_rows:
            self._strips[r] = None
        if self.dirty_spans and not written_past(self, self.dirty_spans):
            self.refresh(*(Region(a, r, b - a, 1) for r, a, b in self.dirty_spans))

    def _blank(self) -> None:
        """No scene: no picture (the rows are painted blank)."""
        if self._frame is None:
            return
        self._frame, self._drawn_key, self._strips = None, None, []
        if not self._painting:
            self.refresh()

    def _update_caption(self, height: int) -> None:
        """The status line in the picture's bottom right corner: the view and the playback
        factor, from the app's ``view_caption()`` (none in an app without one)."""
        source = getattr(self.app, "view_caption", None)
        caption = source() if callable(source) else ""
        if caption == self.caption:
            return
        self.caption = caption
        if self._frame is not None and len(self._strips) == height and height:
            self._strips[height - 1] = None
            self.refresh(Region(0, height - 1, self.size.width, 1))

    def _restyle(self) -> None:
        self._styles.clear()
        self._plain = None
        self._base_style = None
        self._strips = [None] * len(self._strips)
        if self.is_mounted:
            self.refresh()

    def _style(self, colour: int) -> Style:
        style = self._styles.get(colour)
        if style is None:
            # the same for every colour until restyled: once, not once a colour (the first
            # frame has about 25 colours, issue 25)
            if self._base_style is None:
                self._base_style = self.rich_style
            base = self._base_style
            name = self._palette.get(colour)
            style = base + Style(color=name) if (colour and name) else base
            self._styles[colour] = style
        return style

    def render_line(self, y: int) -> Strip:
        frame = self._frame
        width, height = self.size  # read once a line: a property that walks the layout (issue 25)
        if frame is None or frame.width != width or frame.height != height:
            # a size came and on_resize has not run yet (the first frame): the picture now,
            # not a frame without it first (issue 25, the start)
            self._painting = True  # no repaint asked: this frame is being painted
            try:
                self.redraw()
            finally:
                self._painting = False
            frame = self._frame
        if frame is None or y >= frame.height or frame.width != width:
            return Strip.blank(width, self.rich_style)
        strip = self._strips[y]
        if strip is None:
            self._build_strips(frame)
            strip = self._strips[y]
        assert strip is not None
        return strip

    def _build_strips(self, frame: Frame) -> None:
        """Every row not built yet (those a redraw changed), as runs of equal colour (few
        segments per row: cheap to send), with one pass of numpy over all of them."""
        rows = [y for y, strip in enumerate(self._strips) if strip is None]
        width = frame.width
        for y, line, row, cuts in self._row_runs(frame, rows):
            starts = [0, *cuts]
            firsts = row[starts].tolist()
            segments = [Segment(line[a:b], self._style(c)) for a, b, c in zip(starts, [*cuts, width], firsts)]
            self._strips[y] = Strip(segments, width)

    def _row_runs(self, frame: Frame, rows: list[int]) -> Iterator[tuple[int, str, np.ndarray, list[int]]]:
        """The rows as drawn (the caption over the last): each row's number, text, colour per
        cell (a blank cell the colour of the next dot) and where its colour changes."""
        import numpy as np  # loaded with the first scene (see the module's docstring)

        width, height, text = frame.width, frame.height, frame.text()
        colours = blanks_coloured(frame.colours[rows], frame.chars[rows] == BLANK)
        caption = f" {self.caption} " if self.caption else ""
        if 0 < len(caption) < width and rows and rows[-1] == height - 1:
            colours[-1, width - len(caption):] = AXES_COLOUR
        else:
            caption = ""
        changes, cuts = np.nonzero(colours[:, 1:] != colours[:, :-1])
        cuts_of = np.split(cuts + 1, np.cumsum(np.bincount(changes, minlength=len(rows)))[:-1])
        for i, y in enumerate(rows):
            line = text[y * (width + 1): y * (width + 1) + width]
            if caption and y == height - 1:
                line = line[: width - len(caption)] + caption
            yield y, line, colours[i], cuts_of[i].tolist()

    def span_text(self, spans: Sequence[tuple[int, int, int]], x: int, y: int) -> str | None:
        """The changed ``spans`` (row, first column, end column) as terminal sequences, the
        widget placed at (x, y) on the screen (its region: a widget with padding or a border
        has its rows made by Textual, this returns None): cell for cell what Textual's pipeline makes of
        the rows (``compositor.colour_runs`` of its strips), made from the frame's arrays
        with no strip; None when Textual's pipeline does more to them than colour (the
        caller renders them through it)."""
        frame, codes = self._frame, self._plain_codes()
        if frame is None or codes is None or not narrow(self.caption):
            return None
        ends: dict[int, list[tuple[int, int]]] = {}
        for row, a, b in spans:
            ends.setdefault(row, []).append((a, b))
        out: list[str] = []
        for row, line, colours, cuts in self._row_runs(frame, sorted(ends)):
            for a, b in ends[row]:
                starts = [a, *(c for c in cuts if a < c < b)]
                runs = coded_runs((line[start:end], self._plain_code(colour, codes))
                                  for start, end, colour in zip(starts, [*starts[1:], b], colours[starts].tolist()))
                if runs is None:
                    return None
                out += (f"\x1b[{y + row + 1};{x + a + 1}H", runs)
        return "".join(out)

    def _plain_codes(self) -> dict[int, tuple[str, str] | None] | None:
        """The colours' terminal codes as Textual's pipeline would write them (the line
        filters applied), while that pipeline does nothing else to the widget's rows (no
        border, padding, outline, tint, opacity, hatch); None when it does more. Looked at
        again after a change of style (``_restyle``: a theme, the CSS, the ANSI colours),
        as the palette's styles are."""
        if self._plain is None:
            self._plain = not any(self.styles.gutter) and content_only_filtered(self)
            self._codes = {}
        return self._codes if self._plain else None

    def _plain_code(self, colour: int, codes: dict[int, tuple[str, str] | None]) -> tuple[str, str] | None:
        """One colour's codes, kept in ``codes`` once worked out."""
        if colour not in codes:
            codes[colour] = plain_codes(self, self._style(colour))
        return codes[colour]


BLANK = 0x20  # a cell with no dot (the raster's blank)


def blanks_coloured(colours: np.ndarray, blank: np.ndarray) -> np.ndarray:
    """Rows of colours with each blank cell given the colour of the next cell in its row that
    is not blank (the last ones, of the one before them; a row of blanks, 0): a space shows
    no colour, so a row is as many runs as its dots have colours, not twice as many; each run
    is one style sequence written to the terminal (issue 40: a frame's bytes and the work to
    make them)."""
    import numpy as np

    height, width = colours.shape
    index = np.broadcast_to(np.arange(width), (height, width))
    drawn = ~blank
    following = np.minimum.accumulate(np.where(drawn, index, width)[:, ::-1], axis=1)[:, ::-1]
    preceding = np.maximum.accumulate(np.where(drawn, index, -1), axis=1)
    source = np.where(following < width, following, preceding)
    coloured = np.take_along_axis(colours, np.maximum(source, 0), axis=1)
    coloured[source < 0] = 0
    return coloured
