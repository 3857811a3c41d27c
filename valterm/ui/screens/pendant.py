"""PENDANT MENU (Fig. 3-1, Fig. C-10): the teach pendant (Chapter 3).

1-6 turn a joint by the increment, O/C open and close the clamp, W or T then X/Y/Z move the
clamp along a world or tool axis, I/D/N raise, lower or negate the increment (by how much:
the rules, docs/MOTION.md). Refused moves show why (stops, indicators, the elbow
singularity, §3.1-§3.3); the Fig. 2-8 readout follows every move.
"""

from __future__ import annotations

from collections.abc import Iterator

from textual.app import ComposeResult
from textual.binding import Binding

from valterm.core.errors import JointAtStop
from valterm.core.events import Event, Message
from valterm.core.motion import OUT_OF_REACH_REASON, PENDANT_INCREMENT, PENDANT_STEP, MotionRefused
from valterm.ui.errors import error_text
from valterm.ui.messages import RunRequested
from valterm.ui.screens.base import MenuScreen
from valterm.ui.widgets.menus import PENDANT_MENU
from valterm.ui.widgets.readouts import PositionReadout

AXES = {"X": 0, "Y": 1, "Z": 2}
SINGULAR_HINT = ("HINT: THE ARM IS STRETCHED OR AT A SINGULARITY (AS AT READY): BEND IT FIRST, "
                 "KEYS 3 AND 5 A FEW TIMES (N CHANGES THE SIGN), THEN W OR T AGAIN")


def world_step(increment: float) -> float:
    """The millimetres a WORLD/TOOL key moves at this rotational increment."""
    return PENDANT_STEP * increment / PENDANT_INCREMENT


class PendantScreen(MenuScreen):
    MENU = PENDANT_MENU
    LETTERS_START_A_COMMAND = True  # HERE P2 typed without V: H is no pendant key, the line takes it
    UNKNOWN_KEY_HINT = "{val} FIRST TO TYPE A VAL-II COMMAND"  # V as bound now
    BINDINGS = [
        *(Binding(str(j), f"joint({j})", f"Joint {j}", id=f"pendant.joint{j}") for j in range(1, 7)),
        Binding("o,O", "open", "Open", id="pendant.open"),
        Binding("c,C", "close", "Close", id="pendant.close"),
        Binding("w,W", "world", "World", id="pendant.world"),
        Binding("t,T", "tool", "Tool", id="pendant.tool"),
        Binding("i,I", "increment('I')", "Increase", id="pendant.increase"),
        Binding("d,D", "increment('D')", "Decrease", id="pendant.decrease"),
        Binding("n,N", "increment('N')", "Negative", id="pendant.negative"),
        Binding("r,R", "return", "Return", id="pendant.return"),
        Binding("m,M", "model", "Model", id="pendant.model"),
        Binding("v,V", "val", "VAL-II command", id="pendant.val"),
    ]

    def compose_readout(self) -> ComposeResult:
        yield PositionReadout(id="readout")

    def update_readout(self) -> None:
        simulator = self.stage.simulator
        increment = simulator.pendant_increment
        self.query_one("#readout", PositionReadout).show_where(
            simulator.where(1),
            f"JOINT INCREMENT {increment:+.2f} DEG   WORLD/TOOL STEP {world_step(increment):+.2f} MM")

    def _move(self, events: Iterator[Event]) -> None:
        # the move's findings replace the last key's lines; those the core said before and
        # that still hold are listed again when it ends (MenuScreen.on_run_ended, Fig. C-12 a-d)
        self.show_model_if_narrow()
        self.app.post_message(RunRequested(_with_hint(events), self))

    def action_joint(self, joint: int) -> None:
        self._move(self.stage.simulator.pendant_joint(joint))

    def action_open(self) -> None:
        self._move(self.stage.simulator.open())

    def action_close(self) -> None:
        self._move(self.stage.simulator.close())

    def action_world(self) -> None:
        self.ask_key(f"WORLD MODE ({world_step(self.stage.simulator.pendant_increment):+.2f} MM): X, Y OR Z ?:",
                     lambda k: self._straight(self.stage.simulator.pendant_world(AXES[k])), "XYZ")

    def action_tool(self) -> None:
        self.ask_key(f"TOOL MODE ({world_step(self.stage.simulator.pendant_increment):+.2f} MM): X, Y OR Z ?:",
                     lambda k: self._straight(self.stage.simulator.pendant_tool(AXES[k])), "XYZ")

    def _straight(self, events: Iterator[Event]) -> None:
        """A WORLD/TOOL step; refused at once (READY is a stretched, singular pose): say what to do."""
        self.show_model_if_narrow()
        self.app.post_message(RunRequested(_with_hint(events), self))

    def action_increment(self, key: str) -> None:
        value = self.stage.simulator.change_pendant_increment(key)
        self.say(f"ROTATIONAL INCREMENT {value:+.2f} DEG (WORLD/TOOL STEP {world_step(value):+.2f} MM)")
        self.update_readout()

    def after_motion(self, aborted: bool) -> None:
        self.update_readout()

    def action_return(self) -> None:
        self.leave()

    def action_model(self) -> None:
        self.toggle_model()


def _with_hint(events: Iterator[Event]) -> Iterator[Event]:
    """A pendant step's events; a refusal is said with what to do about it, where that is known."""
    try:
        yield from events
    except MotionRefused as refusal:
        yield Message(error_text(refusal), "error")
        hint = refusal_hint(refusal)
        if hint:
            yield Message(hint, "warning")


def refusal_hint(refusal: MotionRefused) -> str:
    """The hint that is true for this refusal: a stop is passed by turning back; a step out of
    reach (the arm stretched), a singularity or a change of the indicators (which happens at
    one) by bending the arm; none for the rest."""
    if isinstance(refusal, JointAtStop):
        stop = refusal.high if refusal.angle > refusal.high else refusal.low
        return (f"HINT: THE STEP WOULD TURN JOINT {refusal.joint} PAST ITS STOP AT {stop:g}: "
                "N REVERSES IT, OR TRY ANOTHER KEY")
    if (refusal.reason.startswith(OUT_OF_REACH_REASON) or "singularity" in refusal.reason
            or "configuration indicators" in refusal.reason):
        return SINGULAR_HINT
    return ""
