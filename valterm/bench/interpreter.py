"""The interpreter's speed figure for ``valterm bench``: statements per second, headless."""

from __future__ import annotations

import time

from valterm.core.val.interpreter import Interpreter, program_from_lines
from valterm.core.val.limits import NO_LIMITS

# A simple arithmetic loop: 3 statements a pass (WHILE, assignment, END), no motion.
LOOP = [
    "    I=0",
    "    S=0",
    "    WHILE I .LT. N DO",
    "    I=I+1",
    "    S=S+I*2-1",
    "    END",
    "    STOP",
]


class _NoRobot:
    """The loop never moves the robot; STATUS would read this speed."""

    speed = 100.0


def bench_interpreter(passes: int = 100_000, repeat: int = 3) -> float:
    """Statements per second for the arithmetic loop (best of `repeat` runs), Step events included."""
    program = program_from_lines("BENCH", LOOP)
    best = 0.0
    for _ in range(repeat):
        interpreter = Interpreter(_NoRobot(), lambda name: program, {"N": float(passes)}, limits=NO_LIMITS)
        start = time.perf_counter()
        count = sum(1 for event in interpreter.execute("BENCH") if event.event == "step")
        elapsed = time.perf_counter() - start
        best = max(best, count / elapsed)
    return best


if __name__ == "__main__":
    print(f"{bench_interpreter():,.0f} statements/s")
