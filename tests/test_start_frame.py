"""The first frame of MAIN MENU (issue 25, the start): drawn once, with the model in it."""

from __future__ import annotations

from pathlib import Path

import pytest

from valterm.ui.app import ValtermApp

BRAILLE = range(0x2801, 0x2900)


async def test_no_frame_is_drawn_while_the_app_holds_a_batch(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Textual draws a screen's frame during the app's mount (one batch of updates) and drops
    it; valterm's screens wait for the batch's end, so MAIN MENU is drawn once before it shows."""
    from textual._compositor import Compositor

    app = ValtermApp(tmp_path, "PROCESS")
    drawn: list[tuple[str, int]] = []
    render_update = Compositor.render_update

    def counted(self: Compositor, *args: object, **kwargs: object) -> object:
        drawn.append((type(self.root).__name__ if self.root is not None else "", app._batch_count))
        return render_update(self, *args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(Compositor, "render_update", counted)
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.pause()
        assert type(app.screen).__name__ == "MainMenuScreen"
    main_menu = [batch for name, batch in drawn if name == "MainMenuScreen"]
    assert main_menu and not any(main_menu)


async def test_the_model_is_in_the_frame_that_first_paints_it(tmp_path: Path) -> None:
    """A model view painted before its resize event came draws the picture then and there,
    not a blank frame first (the first MAIN MENU frame holds the model)."""
    app = ValtermApp(tmp_path, "PROCESS")
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.pause()
        view = app.screen.model_view  # type: ignore[attr-defined]
        view._frame, view._drawn_key = None, None  # as before its first resize
        rows = [view.render_line(y).text for y in range(view.size.height)]
        assert view.frame is not None and view.frame.height == view.size.height
        assert sum(1 for row in rows for ch in row if ord(ch) in BRAILLE) > 100


async def test_a_pushed_screen_is_styled_at_its_mount_not_again_at_its_first_resume(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Textual restyles every widget of a screen when it resumes; a screen just pushed was
    styled as it mounted, so its first resume does not (MAIN MENU was styled twice before
    its first frame). A later resume that asks for it (a mode's switch) still restyles."""
    from textual import events
    from textual.screen import Screen

    restyled: list[str] = []
    update_node_styles = Screen.update_node_styles

    def counted(self: Screen[object], animate: bool = True) -> None:
        restyled.append(type(self).__name__)
        update_node_styles(self, animate)

    monkeypatch.setattr(Screen, "update_node_styles", counted)
    app = ValtermApp(tmp_path, "PROCESS")
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.pause()
        assert type(app.screen).__name__ == "MainMenuScreen"
        assert "MainMenuScreen" not in restyled
        app.screen.post_message(events.ScreenResume())  # as a mode's switch sends it
        await pilot.pause()
        assert restyled.count("MainMenuScreen") == 1
