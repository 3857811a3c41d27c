"""Keys typed before a just-opened field has focus go to the field, not nowhere."""

from __future__ import annotations

from textual import events
from textual.app import App, ComposeResult
from textual.widgets import Input

from valterm.ui.widgets.prompt import type_ahead


class FieldApp(App[None]):
    AUTO_FOCUS = None  # nothing focused, as on the menu screens

    def compose(self) -> ComposeResult:
        yield Input(id="field")

    def on_mount(self) -> None:
        self.submitted: list[str] = []
        self.set_focus(None)

    def on_input_submitted(self, event: Input.Submitted) -> None:
        self.submitted.append(event.value)


def key(name: str, character: str | None) -> events.Key:
    return events.Key(name, character)


async def test_keys_reach_an_unfocused_open_field_then_enter_submits() -> None:
    app = FieldApp()
    async with app.run_test() as pilot:
        field = app.query_one("#field", Input)
        app.set_focus(None)
        await pilot.pause()
        assert not field.has_focus
        for name, char in [("M", "M"), ("O", "O"), ("V", "V"), ("E", "E"), ("X", "X"),
                           ("backspace", None), ("space", " "), ("A", "A")]:
            assert type_ahead(key(name, char), field)
        assert field.value == "MOVE A"
        assert type_ahead(key("enter", None), field)
        await pilot.pause()
        assert app.submitted == ["MOVE A"]
        # a focused or closed field is left to Textual
        field.disabled = True
        assert not type_ahead(key("B", "B"), field)
