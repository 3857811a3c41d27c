"""Keys typed before a just-opened field has focus go to the field, not nowhere."""

from __future__ import annotations

import asyncio
from pathlib import Path

from textual import events
from textual.app import App, ComposeResult
from textual.message import Message
from textual.widgets import Input

from app_helpers import sync, until
from valterm.testing import Simulation
from valterm.ui.screens.valmode import ValModeScreen
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


class Stall(Message):
    """Holds the screen's queue for a moment, as a busy machine does."""


class StallingValMode(ValModeScreen):
    async def on_stall(self, message: Stall) -> None:
        await asyncio.sleep(0.3)


@sync
async def test_return_in_the_line_is_taken_before_the_keys_typed_after_it(tmp_path: Path) -> None:
    """RETURN in VAL-II mode's line bubbles to the screen, which takes the line: the keys
    typed after it wait for that, even while the screen is slow to get to it (on a loaded
    machine 18 of 25 probes ran ``TYPE AT`` and ``YPE B``)."""
    async with Simulation(tmp_path / "ws") as sim:
        screen = StallingValMode(show_menu=False)
        await sim.app.push_screen(screen)
        await sim.pilot.pause()
        await sim.type("TYPE A")
        screen.post_message(Stall())
        await sim.burst("enter", *"TYPE B", "enter")
        await until(sim.pilot, lambda: any(line.endswith("B") for line in screen.transcript),
                    "the second line", limit=20.0)
        assert [line for line in screen.transcript if line.startswith(". ")][-2:] == [". TYPE A", ". TYPE B"]
