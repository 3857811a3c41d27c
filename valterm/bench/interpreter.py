"""The interpreter's speed figure for ``valterm bench``: statements per second, headless."""

from __future__ import annotations

from typing import TYPE_CHECKING, cast

import time

from valterm.core.val.interpreter import Interpreter, program_from_lines
from valterm.core.val.limits import NO_LIMITS

if TYPE_CHECKING:
    from valterm.core.simulator import Simulator

# A simple arithmetic loop: 4 statements a pass (WHILE, two assignments, END), no motion.
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
        interpreter = Interpreter(cast("Simulator", _NoRobot()), lambda name: program, {"N": float(passes)}, limits=NO_LIMITS)
        start = time.perf_counter()
        count = sum(1 for event in interpreter.execute("BENCH") if event.event == "step")
        elapsed = time.perf_counter() - start
        best = max(best, count / elapsed)
    return best


def loop_statements(passes: int) -> int:
    """The steps LOOP runs for N = `passes`: its four first and last ones, four a pass."""
    return 4 * passes + 4


def bench_run_json(passes: int = 50_000, repeat: int = 3) -> float:
    """Statements per second as ``valterm run --json`` writes them: its very loop
    (``write_events``) writing each event's JSON line to a text file (the null device), as
    ``run`` writes to standard output (with no limits: ``run``'s default ones would stop it at
    100 000 lines, and the loop's steps are counted, not its lines)."""
    import os

    from valterm.core.text.transcript import write_events

    program = program_from_lines("BENCH", LOOP)
    best = 0.0
    with open(os.devnull, "w", encoding="utf-8") as out:
        for _ in range(repeat):
            interpreter = Interpreter(cast("Simulator", _NoRobot()), lambda name: program, {"N": float(passes)},
                                      limits=NO_LIMITS)
            start = time.perf_counter()
            write_events(interpreter.execute("BENCH"), out.write, as_json=True)
            best = max(best, loop_statements(passes) / (time.perf_counter() - start))
    return best

if __name__ == "__main__":
    print(f"{bench_interpreter():,.0f} statements/s")
