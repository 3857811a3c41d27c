"""CTRL-Q with unsaved work: say what would be lost and ask (Y leaves, N or ESC stays)."""

from __future__ import annotations

from textual import events
from textual.app import App, ComposeResult
from textual.binding import Binding
from textual.containers import Vertical
from textual.widgets import Static

from valterm.ui import keymap, legends
from valterm.ui.screens.keyed import KeyedModalScreen


def unsaved_work(app: App) -> list[str]:  # type: ignore[type-arg]
    """What leaving now would lose: a moved set-up, taught locations no .LOC file holds,
    programs with unsaved edits."""
    from valterm.ui.screens.editor import EditorScreen

    lost = []
    session = getattr(app, "session", None)
    if session is not None and getattr(app, "setup_modified", False):
        lost.append(f"THE MOVED PARTS OF {session.setup_name or 'THE'}.SET")
    if session is not None:
        names = session.simulator.unsaved_locations()
        if names:
            shown = ", ".join(names[:8]) + (f" AND {len(names) - 8} MORE" if len(names) > 8 else "")
            lost.append(f"{len(names)} LOCATION{'S' if len(names) != 1 else ''} ({shown}): "
                        "STOREL NAME SAVES THEM")
    for screen in app.screen_stack:
        editor = getattr(screen, "editor", None)
        if isinstance(screen, EditorScreen) and editor is not None and editor.dirty:
            lost.append(f"THE EDITS OF {editor.name}.DAT (KEPT IN ITS JOURNAL)")
    return lost


def confirm_quit(app: App) -> None:  # type: ignore[type-arg]
    if isinstance(app.screen, QuitScreen):
        return
    lost = unsaved_work(app)
    if not lost:
        app.exit(0)
        return
    app.push_screen(QuitScreen(lost))


class QuitScreen(KeyedModalScreen[None]):
    """The one question before leaving with unsaved work."""

    DEFAULT_CSS = """
    QuitScreen { align: center middle; }
    QuitScreen > Vertical { width: 70; max-width: 100%; height: auto; border: heavy $warning;
                            padding: 0 1; background: $surface; }
    QuitScreen Static { width: 100%; height: auto; }
    """
    AUTO_FOCUS = ""
    BINDINGS = [
        Binding("y,Y", "leave", "Exit without saving", id="quit.yes"),
        Binding("n,N,escape", "stay", "Stay", id="quit.no"),
    ]

    def __init__(self, lost: list[str]) -> None:
        super().__init__()
        self.lost = lost

    def compose(self) -> ComposeResult:
        with Vertical():
            yield Static("NOT SAVED:\n" + "\n".join(f"  {line}" for line in self.lost))
            yield Static("EXIT WITHOUT SAVING (Y/N) ?", id="quit-question")

    def action_leave(self) -> None:
        self.app.exit(0)

    def action_stay(self) -> None:
        self.close()

    def wrong_key(self, event: events.Key) -> None:
        answers = legends.keys_of(self, "quit.yes", "quit.no")
        wrong = keymap.wrong_answer(event, answers, legends.fill(self, "{quit.no|ESC}"))
        self.query_one("#quit-question", Static).update(f"EXIT WITHOUT SAVING (Y/N) ?  {wrong}")

    def close(self) -> None:
        """Dismiss this screen if it is still the one on top: keys typed ahead reach a screen's
        queue before it closes, and a second close must not close the screen below."""
        if self.app.screen is self:
            self.dismiss(None)
