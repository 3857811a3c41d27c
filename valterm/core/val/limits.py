"""The limits of one run (docs/LIMITS.md): steps, simulated seconds, transcript lines.

A runaway program (``10 GOTO 10`` with a TYPE) must end by itself, whoever runs it: the
app, ``valterm run``, ``valterm monitor`` or ``valterm grade``. The interpreter counts
against one ``RunLimits`` per EXECUTE and stops the program with a ``LimitReached`` event
naming the limit; every front end only chooses the numbers (its flags).

The defaults are far above what the thesis's programs need (PROCESS: 33 steps, about 40
lines, 18 s of robot time; a program of its size repeated 1000 times, EXECUTE name,-1, is
33 000 steps and 5 hours) and low enough that a runaway ends in about a second, having
written a few megabytes. 0 means no limit.
"""

from __future__ import annotations

from dataclasses import dataclass

DEFAULT_STEPS = 1_000_000       # program steps executed (CALLed programs' and every loop's too)
DEFAULT_SECONDS = 86_400.0      # the robot's simulated time: one day
DEFAULT_LINES = 100_000         # transcript lines: a scrolled step is one, TYPE output, messages

# limit -> (the command-line flag that changes it, the unit said in the message)
FLAGS = {"steps": ("--max-steps", "STEPS"), "seconds": ("--max-seconds", "SECONDS OF ROBOT TIME"),
         "lines": ("--max-lines", "LINES OF OUTPUT")}


@dataclass(frozen=True)
class RunLimits:
    """How far one EXECUTE may go; 0 (or less) for a limit means none."""

    steps: int = DEFAULT_STEPS
    seconds: float = DEFAULT_SECONDS
    lines: int = DEFAULT_LINES

    def allowed(self, limit: str) -> float:
        """The limit as a number to count down from (infinite when there is none)."""
        value = float(getattr(self, limit))
        return value if value > 0 else float("inf")

    def message(self, limit: str) -> str:
        """`RUN LIMIT REACHED: 1000000 STEPS`: what the stop says (the flag follows it)."""
        value = float(getattr(self, limit))
        shown = str(int(value)) if value.is_integer() else f"{value:g}"
        return f"RUN LIMIT REACHED: {shown} {FLAGS[limit][1]}"

    @staticmethod
    def flag(limit: str) -> str:
        return FLAGS[limit][0]


NO_LIMITS = RunLimits(0, 0.0, 0)
"""For measuring (``valterm bench``): nothing stops the run but its end."""
