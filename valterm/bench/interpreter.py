"""The interpreter's speed figure for ``valterm bench``: statements per second, headless."""

from __future__ import annotations

from typing import TYPE_CHECKING, TextIO

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


def _no_motion() -> Simulator:
    """The loop never moves the robot: a plain simulator, made before the clock starts."""
    from valterm.core.simulator import Simulator

    return Simulator()


def bench_interpreter(passes: int = 100_000, repeat: int = 3) -> float:
    """Statements per second for the arithmetic loop (best of `repeat` runs), Step events included."""
    program = program_from_lines("BENCH", LOOP)
    best = 0.0
    for _ in range(repeat):
        interpreter = Interpreter(_no_motion(), lambda name: program, {"N": float(passes)}, limits=NO_LIMITS)
        start = time.perf_counter()
        count = sum(1 for event in interpreter.execute("BENCH") if event.event == "step")
        elapsed = time.perf_counter() - start
        best = max(best, count / elapsed)
    return best


def loop_statements(passes: int) -> int:
    """The steps LOOP runs for N = `passes`: its four first and last ones, four a pass."""
    return 4 * passes + 4


def unbuffered_devnull() -> TextIO:
    """The null device as standard output is with ``PYTHONUNBUFFERED=1``: no buffer under the
    text layer, which writes each string through at once (CPython's ``create_stdio``)."""
    import io
    import os

    return io.TextIOWrapper(io.FileIO(os.devnull, "w"), encoding="utf-8", write_through=True)


def bench_run_output(passes: int = 50_000, repeat: int = 3, as_json: bool = True, unbuffered: bool = False) -> float:
    """Statements per second as ``valterm run`` writes them (``--json``, or its text transcript):
    its very loop (``write_events``) writing in its blocks to the null device, as ``run`` writes
    to standard output that is no terminal, buffered or as with ``PYTHONUNBUFFERED=1``
    (with no limits: ``run``'s default ones would stop it at 100 000 lines, and the loop's steps
    are counted, not its lines)."""
    import os

    from valterm.core.text.transcript import blocks_for, write_events

    program = program_from_lines("BENCH", LOOP)
    best = 0.0
    with unbuffered_devnull() if unbuffered else open(os.devnull, "w", encoding="utf-8") as out:
        for _ in range(repeat):
            interpreter = Interpreter(_no_motion(), lambda name: program, {"N": float(passes)},
                                      limits=NO_LIMITS)
            start = time.perf_counter()
            write_events(interpreter.execute("BENCH"), blocks_for(out), as_json=as_json)
            best = max(best, loop_statements(passes) / (time.perf_counter() - start))
    return best


def bench_run_json(passes: int = 50_000, repeat: int = 3) -> float:
    """``run --json``'s statements per second, buffered standard output (issue 25's figure)."""
    return bench_run_output(passes, repeat)


if __name__ == "__main__":
    print(f"{bench_interpreter():,.0f} statements/s")
