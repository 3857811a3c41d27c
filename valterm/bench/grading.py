"""``valterm grade``'s figures for ``valterm bench``: seconds per student, the whole command,
and what ``--jobs 2`` gains in wall-clock time over ``--jobs 1`` (issue 40: >= 1.7x on two idle
cores).

A class of students, each a folder holding the thesis's PROCESS program (bundled), as a
class hands in (one folder a student), graded against a task on the bundled PROCESS cell by
one ``valterm grade`` process, as an instructor runs it: interpreter start-up, the worker
processes, the collision check at every step included.
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


def write_class(root: Path, students: int) -> Path:
    """``root``/TASK.toml and ``root``/class/Snnn/PROCESS.DAT for ``students`` students."""
    program = resources.data_path(resources.PROGRAMS, "PROCESS.DAT").read_text(encoding="utf-8")
    (root / "TASK.toml").write_text(TASK)
    for n in range(students):
        folder = root / "class" / f"S{n:03d}"
        folder.mkdir(parents=True)
        (folder / "PROCESS.DAT").write_text(program)
    return root / "class"


def _grade_seconds(root: Path, jobs: int | None, students: int) -> float:
    """Wall-clock seconds of one ``valterm grade`` of the class (its exit checked: every
    student must pass, or the figure would time a failure)."""
    argv = [sys.executable, "-m", "valterm", "grade", str(root / "TASK.toml"), str(root / "class"),
            "--json", str(root / "out.json")]
    if jobs is not None:
        argv += ["--jobs", str(jobs)]
    start = time.perf_counter()
    done = subprocess.run(argv, capture_output=True, text=True, check=False, timeout=600)
    seconds = time.perf_counter() - start
    if done.returncode != 0 or f"{students} PASSED" not in done.stdout:
        raise RuntimeError(f"the bench's class did not pass: {done.stdout[-400:]}{done.stderr[-400:]}")
    return seconds


def bench_grade(students: int = 10, rounds: int = 3) -> float:
    """Seconds per student (the best of ``rounds`` runs of one ``valterm grade`` command)."""
    with tempfile.TemporaryDirectory() as folder:
        root = Path(folder)
        write_class(root, students)
        best = min(_grade_seconds(root, None, students) for _ in range(rounds))
    return best / students


def bench_grade_jobs(students: int = 60, rounds: int = 2) -> dict[str, float]:
    """``--jobs 1`` and ``--jobs 2`` on the same class, taken in turn (the best of ``rounds``
    each), and their ratio. A wall-clock figure: it needs two idle cores to mean anything."""
    with tempfile.TemporaryDirectory() as folder:
        root = Path(folder)
        write_class(root, students)
        times: dict[int, list[float]] = {1: [], 2: []}
        for _ in range(rounds):
            for jobs in (1, 2):
                times[jobs].append(_grade_seconds(root, jobs, students))
    one, two = min(times[1]), min(times[2])
    return {"grade_jobs1_s": one, "grade_jobs2_s": two, "grade_jobs2_speedup_x": one / two}


if __name__ == "__main__":
    print(f"{bench_grade():.3f} s a student")
    print(bench_grade_jobs())
