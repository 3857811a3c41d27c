"""The I/O panel (issue 14): the controller's numbered outputs and inputs, shown live.

Reached from VAL-II mode by F10, also while a program runs (the program goes on beneath).
Outputs 1-24 and inputs 1001-1024 are drawn as lamps (``*`` on, ``.`` off); any other
signal that is on is listed. The user sets inputs and software signals (2001-2512) from the
keyboard: ``1001`` ENTER toggles input 1001, ``1001 ON`` / ``1001 OFF`` set it; a program's ``WAIT SIG(1001)``
sees the change at its next look. ESC returns to VAL-II mode.

The lamps follow the session's ``SignalPanel`` (``valterm.core.signals``), looked at a few
times a second: outputs set by ``SIGNAL`` change here while the program runs.
"""

from __future__ import annotations

from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Vertical
from textual.widgets import Input, Static

from valterm.core.errors import RefusedValue, ValtermError
from valterm.core.session import Session
from valterm.core.signals import INPUTS, INTERNAL, OUTPUTS, SETTABLE, SignalPanel
from valterm.ui import legends
from valterm.ui.screens.keyed import KeyedModalScreen

SHOWN = 24  # lamps drawn per kind: two rows of 12 (the panel fits an 80 x 24 terminal)
ROW = 12
LOOK_EVERY = 0.1  # seconds between two looks at the panel
KEYS = "1001-1512, 2001-2512, ENTER: TOGGLE   1001 ON / OFF: SET   {signals.escape}: RETURN"  # legends.fill


def lamp_rows(panel: SignalPanel, first: int, label: str) -> list[str]:
    """Two rows of 12 lamps from signal ``first``, each under its number."""
    lines = []
    for start in range(first, first + SHOWN, ROW):
        numbers = range(start, start + ROW)
        lines.append(f"{label:<9}" + "".join(f"{n:>5}" for n in numbers))
        lines.append(" " * 9 + "".join(f"{'*' if n in panel.on else '.':>5}" for n in numbers))
        label = ""
    return lines


def panel_lines(panel: SignalPanel) -> list[str]:
    """The panel as text: the lamps of outputs and inputs, then every other signal that is on."""
    shown = set(range(OUTPUTS.start, OUTPUTS.start + SHOWN)) | set(range(INPUTS.start, INPUTS.start + SHOWN))
    others = sorted(n for n in panel.on if n not in shown)
    internal = [n for n in others if n in INTERNAL]
    beyond = [n for n in others if n not in INTERNAL]
    return [
        *lamp_rows(panel, OUTPUTS.start, "OUTPUTS"),
        *lamp_rows(panel, INPUTS.start, "INPUTS"),
        "ALSO ON: " + (" ".join(str(n) for n in beyond) or "NONE")
        + "   INTERNAL ON: " + (" ".join(str(n) for n in internal) or "NONE"),
    ]


def parse_input_command(typed: str, panel: SignalPanel) -> tuple[int, bool]:
    """``1001`` (toggle), ``1001 ON`` or ``1001 OFF`` -> (input or software signal, new state);
    RefusedValue says why."""
    words = typed.replace(",", " ").upper().split()
    if words and words[0] in ("INPUT", "SIG", "SIGNAL"):
        words = words[1:]
    if not words or len(words) > 2 or not words[0].lstrip("-").isdigit():
        raise RefusedValue("TYPE AN INPUT NUMBER (1001-1512) OR A SOFTWARE SIGNAL (2001-2512), THEN ENTER;"
                           " OR 1001 ON / 1001 OFF")
    number = int(words[0])
    if number not in INPUTS and number not in INTERNAL:
        raise RefusedValue(f"{number} IS NOT AN INPUT: {SETTABLE.upper()}")
    if len(words) == 1:
        return number, number not in panel.on
    if words[1] not in ("ON", "OFF", "1", "0"):
        raise RefusedValue(f"{words[1]}: TYPE ON OR OFF")
    return number, words[1] in ("ON", "1")


class SignalsScreen(KeyedModalScreen[None]):
    """The I/O panel over VAL-II mode."""

    DEFAULT_CSS = """
    SignalsScreen { align: center bottom; }
    SignalsScreen #io-box { width: 76; max-width: 100%; height: auto; border: round $primary;
                            background: $surface; padding: 0 1; }
    SignalsScreen #io-line { border: none; height: 1; padding: 0; }
    SignalsScreen #io-title { text-style: bold; }
    SignalsScreen #io-lamps { height: auto; }
    SignalsScreen #io-state, SignalsScreen #io-message { height: 1; color: $accent; }
    SignalsScreen #io-keys { height: auto; color: $accent; }
    """
    BINDINGS = [Binding("escape", "close", "Return", id="signals.escape")]

    def __init__(self, session: Session) -> None:
        super().__init__()
        self.session = session
        self._shown: tuple[frozenset[int], str] | None = None

    @property
    def panel(self) -> SignalPanel:
        return self.session.interpreter.machine.signals

    def compose(self) -> ComposeResult:
        with Vertical(id="io-box"):
            yield Static("I/O PANEL", id="io-title")
            yield Static("", id="io-lamps")
            yield Static("", id="io-state")
            yield Static("", id="io-message")
            yield Static(legends.fill(self, KEYS), id="io-keys")
            yield Input(id="io-line", placeholder="INPUT OR SOFTWARE SIGNAL, e.g. 1001 or 2001 (TYPE HERE)")

    def on_mount(self) -> None:
        self.look()
        self.set_interval(LOOK_EVERY, self.look, name="io-panel")
        self.query_one("#io-line", Input).focus()

    # -- what it shows ----------------------------------------------------------------
    @property
    def lamps_text(self) -> str:
        return str(self.query_one("#io-lamps", Static).content)

    @property
    def message(self) -> str:
        return str(self.query_one("#io-message", Static).content)

    def look(self) -> None:
        """Redraw when a signal or the program's state changed since the last look."""
        now = (frozenset(self.panel.on), self._program_state())
        if now == self._shown:
            return
        self._shown = now
        self.query_one("#io-lamps", Static).update("\n".join(panel_lines(self.panel)))
        self.query_one("#io-state", Static).update(now[1])

    def _program_state(self) -> str:
        if not self.session.program_running:
            return "NO PROGRAM RUNNING"
        program = self.session.interpreter.program
        return f"PROGRAM {program} PAUSED" if self.session.program_paused else f"PROGRAM {program} RUNNING"

    # -- keys ---------------------------------------------------------------------------
    def on_input_submitted(self, event: Input.Submitted) -> None:
        event.stop()
        field = self.query_one("#io-line", Input)
        field.value = ""
        if not event.value.strip():
            return
        message = self.set_input(event.value)
        self.query_one("#io-message", Static).update(message)

    def set_input(self, typed: str) -> str:
        """One typed line: the input set, or why not (the message shown)."""
        try:
            number, on = parse_input_command(typed, self.panel)
            self.session.key_input(number, on)
        except ValtermError as error:
            return f"*** {str(error).upper()}"
        self.look()
        kind = "INPUT" if number in INPUTS else "SOFTWARE SIGNAL"
        return f"{kind} {number} {'ON' if on else 'OFF'}"

    def line_taking_keys(self) -> Input:
        return self.query_one("#io-line", Input)  # the panel's one line (typed ahead too)

    def action_close(self) -> None:
        self.dismiss(None)
