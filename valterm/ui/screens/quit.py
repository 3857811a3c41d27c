"""The one question before unsaved work is lost: CTRL-Q (exit), MAIN's I_INITIALIZE and
B_BEGIN (a fresh session) say what would be lost, and what goes back to its start, and ask
(Y goes on, N or ESC stays and loses nothing). Nothing to lose: no question."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

from textual import events
from textual.app import App, ComposeResult
from textual.binding import Binding
from textual.containers import Vertical
from textual.widgets import Static

from valterm.ui import keymap, legends
from valterm.ui.screens.keyed import KeyedModalScreen

if TYPE_CHECKING:
    from valterm.core.simulator import Simulator


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


def settings(sim: Simulator) -> list[tuple[str, str]]:
    """(what, its state) of what a fresh session starts afresh: SPEED, the checks, the user's
    configuration (LEFTY ...), the arm's pose, the clamp, the rules, BASE."""
    pose = "READY" if [round(j, 6) for j in sim.joints] == [round(j, 6) for j in sim.arm.ready] else "MOVED"
    return [("SPEED", f"{sim.speed:g}"),
            ("COLLISION CHECKS", "ON" if sim.collision_checks else "OFF"),
            ("AUTOCONFIG", "ON" if sim.autoconfig else "OFF"),
            *(("", word) for word in sim.config.words),
            ("THE ARM", pose),
            ("THE CLAMP", "CLOSED" if sim.clamp_closed else "OPEN"),
            ("RULES", str(sim.rules).upper()),
            ("BASE", ", ".join(f"{v:g}" for v in sim.base_offsets))]


def resets(before: Simulator, after: Simulator) -> list[str]:
    """What changes from simulator ``before`` to ``after``: "SPEED 50 BACK TO 100", "LEFTY
    BACK TO RIGHTY" ..."""
    return [f"{what} {old} BACK TO {new}".strip()
            for (what, old), (_, new) in zip(settings(before), settings(after), strict=True) if old != new]


def fresh_simulator(app: App) -> Simulator:  # type: ignore[type-arg]
    """The simulator a fresh session would start with (as ``App.open_session`` makes it)."""
    from valterm.core.simulator import Simulator

    fresh = Simulator(model=app.active_session.simulator.model)  # type: ignore[attr-defined]
    rules = getattr(app, "rules", None)
    if rules is not None:
        fresh.set_rules(rules)
    return fresh


def ask_first(app: App, what: str, then: Callable[[], object], reset: Sequence[str] = (),  # type: ignore[type-arg]
              cancelled: Callable[[], object] | None = None) -> None:
    """``then`` at once when nothing would be lost, else the question: Y ``then``, N or ESC
    ``cancelled`` (nothing lost, nothing reset)."""
    if isinstance(app.screen, QuitScreen):
        return
    lost = unsaved_work(app)
    if not lost:
        then()
        return

    def answered(yes: bool | None) -> None:
        if yes:
            then()
        elif cancelled is not None:
            cancelled()

    app.push_screen(QuitScreen(lost, what, reset), answered)


def confirm_quit(app: App) -> None:  # type: ignore[type-arg]
    ask_first(app, "EXIT", lambda: app.exit(0))


class QuitScreen(KeyedModalScreen[bool]):
    """The one question before unsaved work is lost: True goes on (Y), False stays."""

    DEFAULT_CSS = """
    QuitScreen { align: center middle; }
    QuitScreen > Vertical { width: 70; max-width: 100%; height: auto; border: heavy $warning;
                            padding: 0 1; background: $surface; }
    QuitScreen Static { width: 100%; height: auto; }
    """
    AUTO_FOCUS = ""
    BINDINGS = [
        Binding("y,Y", "leave", "Go on without saving (exit, initialize, begin)", id="quit.yes"),
        Binding("n,N,escape", "stay", "Stay: nothing lost", id="quit.no"),
    ]

    def __init__(self, lost: list[str], what: str = "EXIT", reset: Sequence[str] = ()) -> None:
        super().__init__()
        self.lost = lost
        self.what = what  # EXIT, INITIALIZE, BEGIN
        self.reset = list(reset)

    @property
    def question(self) -> str:
        return f"{self.what} WITHOUT SAVING (Y/N) ?"

    def compose(self) -> ComposeResult:
        with Vertical():
            yield Static("NOT SAVED:\n" + "\n".join(f"  {line}" for line in self.lost))
            if self.reset:
                yield Static("BACK TO THEIR START:\n" + "\n".join(f"  {line}" for line in self.reset))
            yield Static(self.question, id="quit-question")

    def action_leave(self) -> None:
        self.close(True)

    def action_stay(self) -> None:
        self.close(False)

    def wrong_key(self, event: events.Key) -> None:
        answers = legends.keys_of(self, "quit.yes", "quit.no")
        wrong = keymap.wrong_answer(event, answers, legends.fill(self, "{quit.no|ESC}"))
        self.query_one("#quit-question", Static).update(f"{self.question}  {wrong}")

    def close(self, yes: bool = False) -> None:
        """Dismiss this screen if it is still the one on top: keys typed ahead reach a screen's
        queue before it closes, and a second close must not close the screen below."""
        if self.app.screen is self:
            self.dismiss(yes)
