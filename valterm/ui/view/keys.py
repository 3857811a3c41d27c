"""The view keys, the same on every screen that shows the model (MAIN, PENDANT, MANIPULATION,
KEYBOARD, VAL-II mode): app bindings, so a screen's own keys (letters, digits) win, and a
screen that asks a typed answer keeps its keys (the focused input takes them first).

Arrows orbit, + / - (or PAGE UP / PAGE DOWN) zoom, F2 cycles the iso / side / front / top
views, F3 frames the whole cell, F4 follows the clamp, F5 shows or hides the tool-path
trace, F6 / F7 (or < / >) make the playback slower / faster, F8 shows the model alone or the
menu again (HELP topic VIEW). KEYBOARD's ORIENT takes the
arrows and + / - itself while it is on (the screen stops those keys), as the thesis has it.
The view never changes world data.
"""

from __future__ import annotations

from textual.binding import Binding

from valterm.ui.view.model_view import ModelView

# The view maths (valterm.core.render.views, numpy) load with the first key that needs them:
# the app's first frame is drawn without them (issue 25, the start).

VIEW_BINDINGS = [
    Binding("left", "orbit(-1, 0)", "Turn left", show=False, id="view.left"),
    Binding("right", "orbit(1, 0)", "Turn right", show=False, id="view.right"),
    Binding("up", "orbit(0, 1)", "Look down", show=False, id="view.up"),
    Binding("down", "orbit(0, -1)", "Look up", show=False, id="view.down"),
    Binding("plus,equals_sign,pageup", "zoom(1)", "Zoom in", show=False, id="view.zoom_in"),
    Binding("minus,pagedown", "zoom(-1)", "Zoom out", show=False, id="view.zoom_out"),
    Binding("f2", "next_view", "Iso/side/front/top", show=False, id="view.preset"),
    Binding("f3", "frame_all", "Whole cell", show=False, id="view.frame"),
    Binding("f4", "follow_clamp", "Follow the clamp", show=False, id="view.follow"),
    Binding("f5", "toggle_trace", "Tool path", show=False, id="view.trace"),
    Binding("f6,less_than_sign", "pace(1)", "Slower", show=False, id="view.slower"),
    Binding("f7,greater_than_sign", "pace(-1)", "Faster", show=False, id="view.faster"),
    Binding("f8", "toggle_model", "The model alone / the menu again", show=False, id="view.model"),
]


class ViewActions:
    """The view keys' actions; mixed into the app (which holds the shared view state:
    ``view_transform``, ``trace``, ``show_trace``, ``follow_clamp``, ``player``)."""

    def _model_views(self) -> list[ModelView]:
        screen = self.screen  # type: ignore[attr-defined]
        return [view for view in screen.query(ModelView) if view.display]

    def check_action(self, action: str, parameters: tuple[object, ...]) -> bool | None:
        """View keys count only where a model is shown (else the key goes on as usual)."""
        if action in {"orbit", "zoom", "next_view", "frame_all", "follow_clamp", "toggle_trace"}:
            return bool(self._model_views()) and getattr(self, "session_read", None) is not None
        if action == "toggle_model":
            return callable(getattr(self.screen, "toggle_model", None))  # type: ignore[attr-defined]
        return True

    def action_toggle_model(self) -> None:
        """F8: the model alone, or the menu (the text) again, on every screen with a model."""
        self.screen.toggle_model()  # type: ignore[attr-defined]

    def _redraw_views(self) -> None:
        for view in self._model_views():
            view.set_view(self.view_transform)  # type: ignore[attr-defined]
        self.changed()  # type: ignore[attr-defined]

    def _say(self, text: str) -> None:
        """A line on the screen's messages (or VAL-II mode's log)."""
        screen = self.screen  # type: ignore[attr-defined]
        for name in ("say", "log_line"):
            tell = getattr(screen, name, None)
            if callable(tell):
                tell(text)
                return

    def action_orbit(self, d_azimuth: int, d_elevation: int) -> None:
        from valterm.core.render import views

        views.orbit(self.view_transform, d_azimuth * views.ORBIT_STEP,  # type: ignore[attr-defined]
                    d_elevation * views.ORBIT_STEP)
        self._redraw_views()

    def action_zoom(self, direction: int) -> None:
        from valterm.core.render import views

        views.zoom(self.view_transform, views.ZOOM_STEP ** direction)  # type: ignore[attr-defined]
        self._redraw_views()

    def action_next_view(self) -> None:
        from valterm.core.render import views

        name = views.next_preset(self.view_transform)  # type: ignore[attr-defined]
        self.follow_clamp = False
        self.set_view_angles(*views.preset_angles(name))
        self._say(f"VIEW: {name.upper()}")

    def action_frame_all(self) -> None:
        from valterm.core.render import views

        self.follow_clamp = False
        self.set_view_angles(*views.angles(self.view_transform))  # type: ignore[attr-defined]
        self._say("VIEW: THE WHOLE CELL")

    def action_follow_clamp(self) -> None:
        self.follow_clamp = not self.follow_clamp
        if self.follow_clamp:
            self.frame_clamp()
            self._redraw_views()
        else:
            self.action_frame_all()
        self._say(f"VIEW: FOLLOW THE CLAMP {'ON' if self.follow_clamp else 'OFF'}")

    def action_toggle_trace(self) -> None:
        self.show_trace = not self.show_trace
        self._redraw_views()
        self._say(f"TOOL PATH {'ON' if self.show_trace else 'OFF'}")

    def action_pace(self, steps: int) -> None:
        factor = self.player.change_factor(steps)  # type: ignore[attr-defined]
        self._say(f"PLAYBACK: TIME x{factor:g} OF THE REAL PUMA")
        for view in self._model_views():
            view.redraw()  # the status line shows the factor

    def view_caption(self) -> str:
        """The model view's status line: which view, following the clamp, the playback factor."""
        from valterm.core.render import views

        azimuth, elevation = views.angles(self.view_transform)  # type: ignore[attr-defined]
        name = next((n.upper() for n, (az, el) in views.PRESETS.items()
                     if abs(el - elevation) < 0.5 and (abs(el) >= 89.5 or abs(az - azimuth) < 0.5)),
                    f"AZ {azimuth:.0f} EL {elevation:.0f}")
        follow = "  FOLLOW" if self.follow_clamp else ""
        factor = self.player.factor  # type: ignore[attr-defined]
        return f"{name}{follow}  TIME x{factor:g}"

    # -- the shared view state ---------------------------------------------------------
    follow_clamp: bool = False
    show_trace: bool = True

    def set_view_angles(self, azimuth: float, elevation: float) -> None:
        """Look from (azimuth, elevation) at the whole cell."""
        from valterm.core.render import views
        from valterm.core.render.overlays import cell_points

        view = views.orient(self.view_transform, azimuth, elevation)  # type: ignore[attr-defined]
        session = getattr(self, "session", None)
        if session is not None:
            views.fit_points(view, cell_points(session.simulator, self.trace if self.show_trace else None))  # type: ignore[attr-defined]
        self._redraw_views()

    def frame_clamp(self) -> None:
        """Fit the view on the clamp and the part under it, keeping the direction and zoom."""
        from valterm.core.render import views
        from valterm.core.render.overlays import clamp_points

        session = getattr(self, "session", None)
        if session is None:
            return
        view = self.view_transform  # type: ignore[attr-defined]
        scale = view.scale
        views.fit_points(view, clamp_points(session.simulator))
        view.scale = scale
