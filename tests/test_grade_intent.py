"""``valterm grade`` says what an instructor means (issue 38 item 4): ``allowed_contacts`` in
the task file lets the contacts a task intends pass (the thesis's "put the part into the
processor": part 1 and the hand enter the processor, objects 13 and 14 of PROCESS, by design)
while any other collision still fails; parts are named from the setup file's ``; NAME`` lines
(the bundled PROCESS cell is named), so a message says which table; wrong pairs are refused
by key with the task file named."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from valterm.cli import main
from valterm.core.files.setup import read_setup
from valterm.core.grading import TaskError, check_task, grade, read_task
from valterm.core.resources import CELLS, data_path

DATA = Path(__file__).parent / "data" / "grade"
INSERT = DATA / "process" / "INSERT.DAT"   # part 1 from A into the processor (E, F), then to C
CRASH = DATA / "students" / "CRASH.DAT"
TASK = """name = "INSERT"
cell = "PROCESS"
locations = ["PROCESS"]
{extra}

[[part]]
number = 1
position = [-174.6, 576.4, -279.6]
held = false
"""
HAND_IN = '[[1, 13], ["1", "14"], ["CLAMP", "PART PROCESSOR"], ["finger", "13"], ["WRIST", "PART PROCESSOR"]]'


def task_file(tmp_path: Path, extra: str = "") -> Path:
    path = tmp_path / "INSERT.toml"
    path.write_text(TASK.format(extra=extra))
    return path


def test_the_bundled_process_cell_names_its_parts() -> None:
    names = [part.name for part in read_setup(data_path(CELLS, "PROCESS.SET")).objects]
    assert names[0] == "FIRST PART" and names[1] == "SECOND PART"
    assert names[2] == "LEFT-HAND TABLE" and names[7] == "RIGHT-HAND TABLE"
    assert names[12] == names[13] == "PART PROCESSOR"
    for cell in ("PROCESS", "CONV", "DEMO3"):  # every object of every bundled cell has a name of its own
        parts = read_setup(data_path(CELLS, f"{cell}.SET")).objects
        assert all(part.name != f"PART {n}" for n, part in enumerate(parts, start=1)), cell


def test_putting_the_part_into_the_processor_fails_unless_the_task_allows_it(tmp_path: Path) -> None:
    strict = grade(read_task(task_file(tmp_path)), INSERT)
    assert [f.kind for f in strict.failures] == ["collision"]
    assert strict.failures[0].message.startswith("1 (FIRST PART) COLLIDES WITH 13 (PART PROCESSOR) (INSERT STEP 10")
    task = read_task(task_file(tmp_path, f"allowed_contacts = {HAND_IN}"))
    check_task(task)
    allowed = grade(task, INSERT)
    assert allowed.passed, allowed.failures
    assert allowed.collisions == strict.collisions >= 5  # still counted and listed
    assert any(line.startswith("CLAMP COLLIDES WITH 13 (PART PROCESSOR)") for line in allowed.findings)


def test_an_allowed_pair_excuses_only_itself(tmp_path: Path) -> None:
    """Part 1 into 13 allowed, the hand not: the hand's entry still fails, named."""
    verdict = grade(read_task(task_file(tmp_path, 'allowed_contacts = [["1", "PART PROCESSOR"]]')), INSERT)
    assert [f.kind for f in verdict.failures] == ["collision"]
    assert verdict.failures[0].message.startswith("FINGER COLLIDES WITH 13 (PART PROCESSOR) (INSERT STEP 10")
    crash = grade(read_task(task_file(tmp_path, f"allowed_contacts = {HAND_IN}")), CRASH)
    assert crash.failures[0].message.startswith("CLAMP COLLIDES WITH 1 (FIRST PART) (CRASH STEP 5")


def test_a_named_table_in_the_findings_and_the_json(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["grade", str(task_file(tmp_path)), str(CRASH), "--json", "-"]) == 1
    result = json.loads(capsys.readouterr().out)["results"][0]
    assert any(line.startswith("FINGER COLLIDES WITH 8 (RIGHT-HAND TABLE) (CRASH STEP 5")
               for line in result["findings"])


@pytest.mark.parametrize(("value", "reason"), [
    ('[["1", "99"]]', "allowed_contacts: \"99\" is not a part"),
    ('[["TABEL", "1"]]', "allowed_contacts: \"TABEL\" is not a part"),
    ('[["1"]]', "allowed_contacts: each pair is two names"),
    ('[["1", "1"]]', "allowed_contacts: \"1\" with itself"),
    ('"1, 13"', "allowed_contacts must be a list"),
    ('[[1.5, 13]]', "allowed_contacts: 1.5 is not a part number"),
    ('[[true, 13]]', "allowed_contacts: true is not a part number"),
])
def test_a_wrong_pair_is_refused_by_key_with_the_file_named(tmp_path: Path, value: str, reason: str,
                                                           capsys: pytest.CaptureFixture[str]) -> None:
    path = task_file(tmp_path, f"allowed_contacts = {value}")
    assert main(["grade", str(path), str(INSERT)]) == 1
    err = capsys.readouterr().err
    assert "INSERT.toml" in err and reason in err, err
    assert "Traceback" not in err
    with pytest.raises(TaskError):
        check_task(read_task(path))
