"""The model view as the menu screens use it."""

from __future__ import annotations

from rich.segment import Segment
from textual.strip import Strip

from valterm.core.render.kept import KeptPicture, runs_of
from valterm.core.render.legend import AXES_COLOUR
from valterm.ui.view.model_view import ModelView


class CellView(ModelView):
    """ModelView that waits for a size: a hidden view (narrow terminal, menu shown) has none,
    and rasterizing a 0x0 frame twice trips Frame.changed_spans (reported to the view's owner).

    Until its first scene it paints the kept picture of the last start (core/render/kept.py)
    when the app has one of its size (its ``kept_picture``): the picture comes with MAIN
    MENU's first frame."""

    def redraw(self, force: bool = False) -> None:
        width, height = self.size
        if width <= 0 or height <= 0:
            return
        super().redraw(force)

    def render_line(self, y: int) -> Strip:
        kept: KeptPicture | None = getattr(self.app, "kept_picture", None)
        if kept is not None and self.scene is None and self.frame is None:
            width, height = self.size
            if kept.fits(width, height) and y < height:
                text, runs = kept.rows[y]
                return Strip(self._kept_segments(text, runs), width)
        return super().render_line(y)

    def _kept_segments(self, text: str, runs: tuple[tuple[int, int], ...]) -> list[Segment]:
        segments: list[Segment] = []
        start = 0
        for colour, cells in runs:
            segments.append(Segment(text[start:start + cells], self._style(colour)))
            start += cells
        return segments

    def painted(self, key: str) -> KeptPicture | None:
        """The picture as painted now (its caption over the last row, as ``_build_strip``
        lays it), to be kept for the next start drawn from ``key``; None without one."""
        frame = self.frame
        if frame is None or self.scene is None or not frame.height or not frame.width:
            return None
        rows = []
        for y in range(frame.height):
            text, colours = frame.row_text(y), frame.colours[y].tolist()
            caption = f" {self.caption} " if self.caption and y == frame.height - 1 else ""
            if caption and len(caption) < frame.width:
                text = text[: frame.width - len(caption)] + caption
                colours[frame.width - len(caption):] = [AXES_COLOUR] * len(caption)
            rows.append((text, runs_of(colours)))
        return KeptPicture(key, frame.width, rows)
