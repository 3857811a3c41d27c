"""ModelView in a tiny Textual app: braille on screen, row-span repaints, the motion driver."""

from __future__ import annotations

import asyncio
from typing import Any, Callable, Coroutine

import numpy as np
from rich.style import Style
from textual.app import App, ComposeResult

from valterm.core.cell.polyhedron import Polyhedron
from valterm.ui.view.model_view import ModelView
from valterm.core.render.raster import Scene, object_colour

LO, HI = np.array([-60.0, -60, -60]), np.array([60.0, 60, 60])


def two_boxes(dy_bottom: float = 0.0) -> Scene:
    top = Polyhedron.box(LO + [0, -300, 700], HI + [0, -300, 700])
    bottom = Polyhedron.box(LO + [0, dy_bottom, -400], HI + [0, dy_bottom, -400])
    return Scene.build([(top, object_colour(1)), (bottom, object_colour(2))])


class ViewApp(App[None]):
    def compose(self) -> ComposeResult:
        yield ModelView(two_boxes())


def sync(test: Callable[[], Coroutine[Any, Any, None]]) -> Callable[[], None]:
    """Run an async Pilot test without an async pytest plugin."""

    def run() -> None:
        asyncio.run(test())

    run.__name__ = test.__name__
    return run


def is_braille(ch: str) -> bool:
    return 0x2801 <= ord(ch) <= 0x28FF


def screen_lines(view: ModelView) -> list[str]:
    """What the screen shows (the compositor's strips: stale row caches would show here)."""
    return [strip.text for strip in view.app.screen._compositor.render_strips()]


@sync
async def test_braille_on_screen_and_row_span_repaints() -> None:
    app = ViewApp()
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause()
        view = app.query_one(ModelView)
        assert tuple(view.size) == (80, 24)
        lines = screen_lines(view)
        assert len(lines) == 24 and all(len(line) == 80 for line in lines)
        braille_rows = [y for y, line in enumerate(lines) if any(is_braille(ch) for ch in line)]
        assert braille_rows
        # what the app painted on the screen is what the widget holds
        assert lines == view.frame.lines()
        redraws = view.redraws

        # the same scene again: nothing to draw
        view.update_scene(view.scene)
        assert view.redraws == redraws

        # move only the bottom box: only its rows are repainted, in spans, not whole rows
        top_rows = set(np.flatnonzero((view.frame.colours == object_colour(1)).any(axis=1)).tolist())
        view.update_scene(two_boxes(dy_bottom=250.0))
        await pilot.pause()
        assert view.redraws == redraws + 1
        assert view.dirty_rows and len(view.dirty_rows) < 24
        assert not top_rows & set(view.dirty_rows)
        assert all(0 <= x0 < x1 <= 80 and x1 - x0 < 80 for _, x0, x1 in view.dirty_spans)
        assert screen_lines(view) == view.frame.lines()


@sync
async def test_options_redraw_and_ascii() -> None:
    app = ViewApp()
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause()
        view = app.query_one(ModelView)
        view.rotate_by("y", 30)
        view.rotate_by("x", 20)
        n = view.redraws
        view.back_faces = False
        await pilot.pause()
        assert view.redraws == n + 1
        view.axes = True
        await pilot.pause()
        assert any("Z" in line for line in screen_lines(view))
        view.ascii = True
        await pilot.pause()
        text = "".join(screen_lines(view))
        assert text.isascii() and text.strip()
        view.reset_view()
        assert np.allclose(view.view.rotation, np.eye(3))


@sync
async def test_constructor_options() -> None:
    class AsciiApp(App[None]):
        def compose(self) -> ComposeResult:
            yield ModelView(two_boxes(), ascii=True, axes=True, back_faces=False)

    app = AsciiApp()
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause()
        view = app.query_one(ModelView)
        assert view.ascii and view.axes and not view.back_faces
        text = "".join(screen_lines(view))
        assert text.isascii() and "Z" in text


@sync
async def test_resize_redraws_at_the_new_size() -> None:
    app = ViewApp()
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause()
        await pilot.resize_terminal(60, 20)
        await pilot.pause()
        view = app.query_one(ModelView)
        assert view.frame is not None and view.frame.chars.shape == (20, 60)


@sync
async def test_the_widgets_own_style_is_read_once_for_all_colours() -> None:
    """Each colour's style is the widget's own plus the colour: the widget's (``rich_style``,
    a walk of its ancestors) is read once for them all, and again after a restyle (issue 25:
    the first frame has about 25 colours)."""
    reads = []
    rich_style = ModelView.rich_style

    class Counted(ModelView):
        @property
        def rich_style(self):  # type: ignore[no-untyped-def]
            reads.append(1)
            return rich_style.fget(self)  # type: ignore[attr-defined]

    class CountedApp(App[None]):
        def compose(self) -> ComposeResult:
            yield Counted(two_boxes())

    app = CountedApp()
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause()
        view = app.query_one(Counted)
        assert len(view._styles) >= 2 and len(reads) == 1
        base = rich_style.fget(view)  # type: ignore[attr-defined]
        assert all(style == base or style == base + Style(color=view._palette[colour])
                   for colour, style in view._styles.items())
        view.set_palette({1: "red"})
        view.render_line(0)
        assert len(reads) == 2
