"""The lasting status line of every screen: the set-up and whether it is saved, SPEED,
collision checks, back faces, axes, the user's configuration and the arm's, and the help key.

It reads the app's state each time it is drawn (``refresh`` after anything changes); the
text is plain so tests and ``valterm.testing`` read it back. Narrow terminals get the short
words.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, cast

from textual.dom import DOMNode
from textual.widgets import Static

from valterm.core.robot_choice import THESIS_ROBOT
from valterm.ui.legends import help_hint, short_help_hint

if TYPE_CHECKING:  # annotations only: widgets never import the app (the import contracts)
    from valterm.core.simulator import Simulator
    from valterm.ui.app import ValtermApp


def _short(word: str) -> str:
    return word[0] if word else "?"


def status_fields(app: ValtermApp, node: DOMNode | None = None) -> list[tuple[str, str]]:
    """(long, short) texts of each field, in the order shown (the help key as ``node``'s
    app has it bound now)."""
    session = app.session_read  # never reads --setup's set-up (the first frame)
    fields: list[tuple[str, str]] = []
    helps = (help_hint(node), short_help_hint(node))
    if session is None:
        if app.reading_setup:  # the moment after the first frame (--setup)
            return [("READING THE SET-UP FILE", "READING SET-UP"), helps]
        return [("NO SET-UP FILE READ", "NO SET-UP"), *_keys_1985(app), helps]
    sim = session.simulator
    name = f"{session.setup_name}.SET" if session.setup_name else "(NO NAME)"
    saved = "NOT SAVED" if app.setup_modified else "SAVED"
    fields.append((f"{name} {saved}", f"{name} UNSAVED" if saved == "NOT SAVED" else name))
    fields.append((f"SPEED {sim.speed:g}", f"SP {sim.speed:g}"))
    on = "ON" if sim.collision_checks else "OFF"
    fields.append((f"COLLISION CHECKS {on}", f"COLL {on}"))
    faces = "ON" if app.back_faces else "OFF"
    fields.append((f"BACK FACES {faces}", f"FACES {faces}"))
    axes = "ON" if app.axes else "OFF"
    fields.append((f"AXES {axes}", f"AXES {axes}"))
    user = sim.config.words
    arm = arm_configuration(sim)
    fields.append((f"CONFIG {' '.join(user)}", "CFG " + "".join(_short(w) for w in user)))
    fields.append((f"ARM {' '.join(arm)}", "ARM " + "".join(_short(w) for w in arm)))
    rules = "CONTROLLER" if sim.rules == "controller" else "1985"
    fields.append((f"RULES {rules}", f"R {rules[:4]}"))
    fields += _keys_1985(app)
    robot = sim.arm
    if robot.key != THESIS_ROBOT:  # the thesis's robot, the default, goes unsaid
        fields.append((f"ROBOT {robot.name}", f"RB {robot.key}"))
    fields.append(helps)
    return fields


def _keys_1985(app: ValtermApp) -> list[tuple[str, str]]:
    """``--keys 1985`` in force (the thesis's keyboard: docs/KEYBOARD.md); the modern one goes unsaid."""
    return [("KEYS 1985", "K 1985")] if app.keys_1985 else []


def arm_configuration(sim: Simulator) -> tuple[str, str, str]:
    """The configuration the arm is in now (RIGHTY/LEFTY, ABOVE/BELOW, FLIP/NOFLIP)."""
    words: tuple[str, str, str] = sim.arm.indicators(sim.joints).words
    return words


# what goes first when even the short words do not fit (80 columns, a set-up NOT SAVED)
DROPPED_FIRST = ("FACES ", "AXES ", "CFG ")


def status_text(app: ValtermApp, width: int, node: DOMNode | None = None) -> str:
    """The line for ``width`` columns: long words if they fit, else the short ones, else the
    short ones without back faces, axes and the asked configuration (the rules, the keyboard
    and the help key stay)."""
    fields = status_fields(app, node)
    long = "  ".join(f for f, _ in fields)
    if len(long) <= width:
        return long
    short = [s for _, s in fields]
    for prefix in DROPPED_FIRST:
        if len(" ".join(short)) <= width:
            break
        short = [s for s in short if not s.startswith(prefix)]
    return " ".join(short)[:max(width, 0)]


class StatusLine(Static):
    DEFAULT_CSS = "StatusLine { height: 1; background: $boost; color: $text-muted; padding: 0 0; }"

    _shown: str | None = None  # the line last drawn

    @property
    def text(self) -> str:
        return status_text(cast("ValtermApp", self.app), max(self.size.width, 20), self)

    def render(self) -> str:
        self._shown = self.text
        return self._shown

    def refresh_if_changed(self) -> None:
        """Repaint when the line would read differently: a motion redraws its screen at every
        pose, and a repainted status line is a row of the terminal written again (issue 40)."""
        if self.text != self._shown:
            self.refresh()
