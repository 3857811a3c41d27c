"""``valterm grade`` on warm workers (issue 40 item 5): the task's cell is read once for the
class, not once a student, and each student still gets a fresh copy of it; the worker
processes are started once with an initializer that loads the interpreter and the collision
check before the first student."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from valterm.cli import main
from valterm.core import grading

DATA = Path(__file__).parent / "data" / "grade"
TASK = DATA / "PICK.toml"
STUDENTS = DATA / "students"


def test_the_cell_is_read_once_and_each_student_gets_a_fresh_copy(
        monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    reads: list[Path] = []
    real = grading.read_setup

    def counted(path: str | Path, **options: bool) -> object:
        reads.append(Path(path))
        return real(path, **options)

    monkeypatch.setattr(grading, "read_setup", counted)
    grading.forget_cells()
    students = [str(STUDENTS / f"{name}.DAT") for name in ("GOOD", "MISS", "GOOD", "CRASH")]
    assert main(["grade", str(TASK), *students, "--jobs", "1", "--json", "-"]) == 1
    assert len(reads) == 1  # check_task's read; every student after it from the cache
    results = {r["student"]: r for r in json.loads(capsys.readouterr().out)["results"]}
    # GOOD moved part 1 to C; MISS, graded after it, still finds part 1 on the right-hand table
    assert results["MISS"]["parts"][0]["position"] == [440.0, -50.0, -320.0]
    assert results["GOOD"]["passed"]


def test_a_changed_setup_file_is_read_again(tmp_path: Path) -> None:
    cell = tmp_path / "CELL.SET"
    cell.write_text((Path(grading.resources.data_path(grading.resources.CELLS, "PROCESS.SET"))).read_text())
    first = grading.task_cell(cell)
    text = cell.read_text().replace("440.00", "441.00", 1)
    cell.write_text(text + "\n\n")  # another size: another file
    assert grading.task_cell(cell).objects[0].reference[0] == pytest.approx(441.0)
    assert first.objects[0].reference[0] == pytest.approx(440.0)


def test_the_workers_are_warm_before_the_first_student() -> None:
    from valterm.commands.grade import worker_pool

    task = grading.read_task(TASK)
    with worker_pool(task, 2) as pool:
        assert all(pool.map(grading.worker_ready, range(4)))


WARMED = """
import sys
from valterm.core import grading
task = grading.read_task(sys.argv[1])
grading.check_task(task)
grading.warm_worker(task)
before = set(sys.modules)
grading.grade(task, sys.argv[2])
print(sorted(set(sys.modules) - before))
"""


def test_a_warm_worker_imports_nothing_more_for_its_students() -> None:
    """In a fresh process (as a worker starts), the warm-up leaves nothing for the first
    student to load: a pick-and-place with the collision check imports no module."""
    import subprocess
    import sys

    done = subprocess.run([sys.executable, "-c", WARMED, str(TASK), str(STUDENTS / "GOOD.DAT")],
                          capture_output=True, text=True, timeout=60,
                          env={**__import__("os").environ, "PYTHONPATH": str(Path(__file__).resolve().parent.parent)})
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"
