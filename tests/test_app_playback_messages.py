"""Playback by messages (issue 37, build 1): a screen posts the command to run, the app plays it
on the one player, and the player's poses, lines and end come back to the screen as messages.
No screen or widget holds, reaches or calls the player."""

from __future__ import annotations

import ast
import inspect
import math
from pathlib import Path

from textual.message import Message
from textual.screen import Screen

from app_helpers import sync, until
from valterm.core.session import Session
from valterm.ui.app import ValtermApp
from valterm.ui.messages import RunEnded, RunRequested, SceneShown, TranscriptLines
from valterm.ui.playback import Player
from valterm.ui.screens.valmode import Mode, ValModeScreen

UI = Path(__file__).resolve().parent.parent / "valterm" / "ui"


def _player_reaches(path: Path) -> list[str]:
    """Where a module's code names the player: ``x.player``, ``Player``, the app's ``run_events``
    (VAL-II mode's own ``run_events`` posts RunRequested)."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Attribute) and (node.attr == "player" or (node.attr == "run_events" and (
                isinstance(node.value, ast.Attribute) and node.value.attr == "app"))):
            found.append(f"{path.name}:{node.lineno} .{node.attr}")
        elif isinstance(node, ast.Name) and node.id == "Player":
            found.append(f"{path.name}:{node.lineno} Player")
        elif isinstance(node, ast.alias) and node.name == "Player":
            found.append(f"{path.name}:{node.lineno} import Player")
    return sorted(found)


def test_no_screen_or_widget_names_the_player() -> None:
    modules = sorted([*(UI / "screens").rglob("*.py"), *(UI / "widgets").rglob("*.py")])
    assert len(modules) > 20  # the screens and the widgets were found
    assert [hit for path in modules for hit in _player_reaches(path)] == []


def test_the_check_sees_a_screen_that_calls_the_player(tmp_path: Path) -> None:
    """The check above can fail: code that reaches the player is named."""
    bad = tmp_path / "bad.py"
    bad.write_text("def f(self):\n    self.app.player.abort()\n    self.app.run_events([], self)\n")
    assert _player_reaches(bad) == ["bad.py:2 .player", "bad.py:3 .run_events"]


class Watched(ValModeScreen):
    """VAL-II mode, keeping the player's messages it was sent (its own handlers run too)."""

    def __init__(self) -> None:
        super().__init__(show_menu=False)
        self.got: list[Message] = []

    def on_scene_shown(self, message: SceneShown) -> None:
        self.got.append(message)

    def on_transcript_lines(self, message: TranscriptLines) -> None:
        self.got.append(message)

    def on_run_ended(self, message: RunEnded) -> None:
        self.got.append(message)


class Host(ValtermApp):
    def on_mount(self) -> None:
        pass


def _holds_a_player(node: object) -> bool:
    return any(isinstance(value, Player) for value in vars(node).values())


@sync
async def test_a_typed_move_goes_screen_to_player_to_screen_by_messages(tmp_path: Path) -> None:
    asked: list[RunRequested] = []
    callers: list[str] = []
    app = Host(session=Session(workspace_root=tmp_path / "ws"), motion_rate=math.inf)
    play = app.player.play

    def watched_play(*args, **kwargs):  # type: ignore[no-untyped-def]
        # who called the player: no screen's method is on the stack
        callers.extend(type(frame.frame.f_locals.get("self")).__name__ for frame in inspect.stack()[1:]
                       if isinstance(frame.frame.f_locals.get("self"), Screen))
        return play(*args, **kwargs)

    app.player.play = watched_play  # type: ignore[method-assign]
    async with app.run_test(size=(120, 40), message_hook=lambda m: asked.append(m)
                            if isinstance(m, RunRequested) else None) as pilot:
        screen = Watched()
        await app.push_screen(screen)
        await pilot.pause()
        for line in ("HERE A", "DRIVE 2,-20,100"):
            await pilot.press(*line, "enter")
            await until(pilot, lambda: screen.mode == Mode.COMMAND and not app.moving, "the command's end")
        screen.got.clear()
        before = app.simulator.joints
        await pilot.press(*"MOVE A", "enter")
        await until(pilot, lambda: any(isinstance(m, RunEnded) for m in screen.got), "the MOVE's end")
        await until(pilot, lambda: screen.mode == Mode.COMMAND, "the line again")
        assert app.simulator.joints != before  # it moved, back to A
        assert [m.origin for m in asked] == [screen, screen, screen]  # the screen asked the app, each time
        assert callers == []  # ... and the app, not a screen, called the player
        kinds = [type(m) for m in screen.got]
        assert SceneShown in kinds and kinds[-1] is RunEnded and not screen.got[-1].aborted  # type: ignore[attr-defined]
        assert ". MOVE A" in screen.transcript
        # no screen, nor any of its widgets, keeps the player
        for shown in app.screen_stack:
            assert not _holds_a_player(shown)
            assert not any(_holds_a_player(widget) for widget in shown.walk_children())


def _app_state_read(path: Path) -> list[str]:
    """``self.app.X`` where X is the app's state (no method of it, nor Textual's App's)."""
    from textual.app import App

    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Attribute)
                and node.value.attr == "app" and isinstance(node.value.value, ast.Name)
                and node.value.value.id == "self" and node.attr not in dir(App)
                and not callable(getattr(ValtermApp, node.attr, None))):
            found.append(f"{path.name}:{node.lineno} .app.{node.attr}")
    return found


def test_the_playing_screens_read_the_app_through_its_stage(tmp_path: Path) -> None:
    """MENU screens, VAL-II mode, the pendant, KEYBOARD and MANIPULATION read the app's state
    through one typed, read-only view (``KeyedScreen.stage``, ui/stage.py), not its
    attributes; they change it through the app's methods or by message."""
    names = ("base.py", "valmode.py", "pendant.py", "keyboard.py", "manipulation.py")
    screens = [UI / "screens" / name for name in names]
    assert [hit for path in screens for hit in _app_state_read(path)] == []
    bad = tmp_path / "bad.py"
    bad.write_text("def f(self):\n    self.app.simulator.ready()\n    self.app.say('X')\n")
    assert _app_state_read(bad) == ["bad.py:2 .app.simulator"]


@sync
async def test_keys_do_not_wait_for_a_screen_gone_before_its_run_ended(tmp_path: Path) -> None:
    """Keys wait until the screen that asked has handled its run's end; when it is closed
    with the end still in its queue, the keys go on to the screen below (never held)."""
    from valterm.ui.screens.keyboard import KeyboardScreen

    app = Host(session=Session(workspace_root=tmp_path / "ws"), motion_rate=math.inf)
    async with app.run_test(size=(120, 40)) as pilot:
        below = KeyboardScreen()
        await app.push_screen(below)
        screen = ValModeScreen(show_menu=False)
        await app.push_screen(screen)
        await pilot.pause()
        app.run_events(iter([]), screen)  # ends at once: RunEnded posted to the screen ...
        assert app.moving  # ... which has not handled it yet
        app.pop_screen()  # ... and goes before it does
        await until(pilot, lambda: app.screen is below and not app.moving, "the keys free again")
        assert app.survived == []  # the closing screen's handlers raised nothing
        await pilot.press("v")  # KEYBOARD's V: the command line opens (the key was not kept)
        await until(pilot, lambda: below.asking, "the key at the screen below")


def test_the_players_messages_stay_with_their_screen() -> None:
    """A screen's picture, lines and end are its own: none bubbles up to the app (Textual
    gives a subclass ``bubble=True`` again unless it says otherwise), where each picture was
    dispatched a second time to no handler (issue 40: a running session's CPU)."""
    from valterm.ui import messages

    players = [messages.TranscriptLines, messages.SceneShown, messages.PictureMoved,
               messages.RunEvent, messages.RunPaused, messages.RunEnded]
    assert all(issubclass(kind, messages._Run) for kind in players)
    assert [kind.__name__ for kind in players if kind.bubble] == []
