"""The one error base class of the core.

Every error the core raises on purpose (a malformed file, a refused name, an unreachable
location, a VAL-II statement it cannot run) is a ``ValtermError``; the app and the command
line catch that and show its message. Anything else that escapes is a bug: the edges log
it with its traceback and say so in one line.
"""

from __future__ import annotations


class ValtermError(Exception):
    """A refusal the user can act on; ``str(error)`` is the message to show."""


class RefusedValue(ValtermError, ValueError):
    """A value the user gave (an argument, a typed word, a name) that is refused: a
    ValtermError the edges show, and a ValueError where a parse is expected to fail."""


class MotionRefused(ValtermError):
    """A motion the controller will not make: nothing moves (``valterm.core.motion`` raises it;
    it lives here so that what shows it needs no motion code).

    ``reason`` names what is wrong, ``joint`` the joint (0 if none), ``step`` the step of a
    straight line where it happens (0 for the goal itself).
    """

    def __init__(self, reason: str, joint: int = 0, step: int = 0) -> None:
        self.reason = reason
        self.joint = joint
        self.step = step
        where = f" at step {step} of the line" if step else ""
        super().__init__(f"{reason}{where}")


class JointAtStop(MotionRefused):
    """A motion refused because joint ``joint`` would pass its stop ``low..high``; ``angle`` is
    the angle it would need, as the readout would show it (so a hint can say what is true)."""

    def __init__(self, reason: str, joint: int, angle: float, low: float, high: float, step: int = 0) -> None:
        self.angle, self.low, self.high = angle, low, high
        super().__init__(reason, joint, step)
