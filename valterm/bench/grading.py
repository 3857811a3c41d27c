"""``valterm grade``'s figure for ``valterm bench``: seconds per student, the whole command.

A class of students, each handing in the thesis's PROCESS program (bundled), graded against
a task on the bundled PROCESS cell by one ``valterm grade`` process, as an instructor runs
it: interpreter start-up, the process pool, the collision check at every step included.
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
import time
from pathlib import Path

from valterm.core import resources

TASK = """name = "BENCH"
cell = "PROCESS"
locations = ["PROCESS"]
collisions = true
"""


def bench_grade(students: int = 10, rounds: int = 3) -> float:
    """Seconds per student (the best of ``rounds`` runs of one ``valterm grade`` command)."""
    program = resources.data_path(resources.PROGRAMS, "PROCESS.DAT").read_text(encoding="utf-8")
    best = float("inf")
    with tempfile.TemporaryDirectory() as folder:
        root = Path(folder)
        (root / "TASK.toml").write_text(TASK)
        (root / "class").mkdir()
        for n in range(students):
            (root / "class" / f"S{n:03d}.DAT").write_text(program)
        argv = [sys.executable, "-m", "valterm", "grade", str(root / "TASK.toml"), str(root / "class"),
                "--json", str(root / "out.json")]
        for _ in range(rounds):
            start = time.perf_counter()
            subprocess.run(argv, capture_output=True, check=False, timeout=600)
            best = min(best, time.perf_counter() - start)
    return best / students


if __name__ == "__main__":
    print(f"{bench_grade():.3f} s a student")
