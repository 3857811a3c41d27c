"""The model view as the menu screens use it."""

from __future__ import annotations

from valterm.ui.view.model_view import ModelView


class CellView(ModelView):
    """ModelView that waits for a size: a hidden view (narrow terminal, menu shown) has none,
    and rasterizing a 0x0 frame twice trips Frame.changed_spans (reported to the view's owner)."""

    def redraw(self, force: bool = False) -> None:
        width, height = self.size
        if width <= 0 or height <= 0:
            return
        super().redraw(force)
