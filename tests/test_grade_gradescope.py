"""``valterm grade --gradescope FILE`` (issue 38 item 5): Gradescope's results.json, one test a
check with its score and max_score, the student's output; validated against the fields
Gradescope documents."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from valterm.cli import main

DATA = Path(__file__).parent / "data" / "grade"
TASK = DATA / "PICK.toml"
STUDENTS = DATA / "students"

# The fields of results.json as Gradescope documents them ("Autograder Specifications",
# https://gradescope-autograders.readthedocs.io/en/latest/specs/#output-format, and the
# gradescope/autograder_samples repository's docs/specs.md): every key optional; a top-level
# "score" or a score on every test; "status" is "passed" or "failed"; the visibilities and
# formats are the listed ones.
TOP_LEVEL = {"score": (int, float), "execution_time": (int, float), "output": str, "output_format": str,
             "test_output_format": str, "test_name_format": str, "visibility": str,
             "stdout_visibility": str, "extra_data": dict, "tests": list, "leaderboard": list}
TEST = {"score": (int, float), "max_score": (int, float), "status": str, "name": str, "name_format": str,
        "number": str, "output": str, "output_format": str, "tags": list, "visibility": str, "extra_data": dict}
STATUS = {"passed", "failed"}
VISIBILITY = {"hidden", "after_due_date", "after_published", "visible"}
FORMATS = {"text", "html", "simple_format", "md", "ansi"}


def validate(document: dict) -> None:  # type: ignore[type-arg]
    """results.json as Gradescope reads it: no field it does not document, each of its type."""
    assert set(document) <= set(TOP_LEVEL), set(document) - set(TOP_LEVEL)
    for key, kind in TOP_LEVEL.items():
        if key in document:
            assert isinstance(document[key], kind) and not isinstance(document[key], bool), key
    tests = document.get("tests", [])
    assert "score" in document or all("score" in test for test in tests)
    for key in ("visibility", "stdout_visibility"):
        assert document.get(key, "visible") in VISIBILITY
    for key in ("output_format", "test_output_format", "test_name_format"):
        assert document.get(key, "text") in FORMATS
    for test in tests:
        assert set(test) <= set(TEST), set(test) - set(TEST)
        for key, kind in TEST.items():
            if key in test:
                assert isinstance(test[key], kind) and not isinstance(test[key], bool), key
        assert test.get("status", "passed") in STATUS
        assert test.get("visibility", "visible") in VISIBILITY
        assert test.get("output_format", "text") in FORMATS and test.get("name_format", "text") in FORMATS
        assert 0 <= test["score"] <= test.get("max_score", test["score"])


def gradescope(tmp_path: Path, student: str, task: Path = TASK) -> tuple[int, dict]:  # type: ignore[type-arg]
    out = tmp_path / "results" / "results.json"
    out.parent.mkdir()  # /autograder/results is there on Gradescope
    status = main(["grade", str(task), str(STUDENTS / f"{student}.DAT"), "--gradescope", str(out)])
    return status, json.loads(out.read_text())


def test_a_passing_student_scores_every_check(tmp_path: Path) -> None:
    status, document = gradescope(tmp_path, "GOOD")
    validate(document)
    assert status == 0
    tests = document["tests"]
    names = [test["name"] for test in tests]
    assert names[:5] == ["PROGRAM READ", "SYNTAX", "RUNS WITHOUT AN ERROR", "FINISHES WITHIN THE LIMITS",
                         "NO COLLISION"]
    assert "PART 1 AT -174.6, 576.4, -279.6 (TOLERANCE 5 MM), NOT HELD" in names
    assert "CYCLE TIME AT MOST 12 S" in names
    assert all(test["status"] == "passed" and test["score"] == test["max_score"] == 1 for test in tests)
    assert document["score"] == len(tests) == 7
    assert "GOOD: PASS" in document["output"]
    assert "GRASPED PART 1 (GOOD STEP 7" in document["output"]


def test_a_colliding_student_loses_the_collision_check_with_the_message(tmp_path: Path) -> None:
    status, document = gradescope(tmp_path, "CRASH")
    validate(document)
    assert status == 1
    by_name = {test["name"]: test for test in document["tests"]}
    assert by_name["NO COLLISION"]["status"] == "failed" and by_name["NO COLLISION"]["score"] == 0
    assert by_name["NO COLLISION"]["output"].startswith("CLAMP COLLIDES WITH 1 (FIRST PART) (CRASH STEP 5")
    assert by_name["SYNTAX"]["status"] == "passed"
    assert document["score"] == sum(test["score"] for test in document["tests"]) < len(document["tests"])


def test_a_syntax_error_fails_the_checks_of_the_run_not_run(tmp_path: Path) -> None:
    _, document = gradescope(tmp_path, "SYNTAX")
    validate(document)
    by_name = {test["name"]: test for test in document["tests"]}
    assert by_name["PROGRAM READ"]["status"] == "passed"
    assert by_name["SYNTAX"]["output"].startswith("SYNTAX STEP 10: MOVEZ is not a command")
    assert by_name["NO COLLISION"]["status"] == "failed"
    assert by_name["NO COLLISION"]["output"] == "NOT RUN: THE PROGRAM HAS SYNTAX ERRORS"
    assert document["score"] == 1  # read; nothing else was checked

def test_the_students_typed_output_is_in_the_output(tmp_path: Path) -> None:
    (tmp_path / "HELLO.DAT").write_text('    TYPE "HELLO FROM THE STUDENT"\n')
    out = tmp_path / "results.json"
    assert main(["grade", str(TASK), str(tmp_path / "HELLO.DAT"), "--gradescope", str(out)]) == 1
    document = json.loads(out.read_text())
    validate(document)
    assert "HELLO FROM THE STUDENT" in document["output"]


def test_gradescope_grades_one_submission(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "results.json"
    status = main(["grade", str(TASK), str(STUDENTS / "GOOD.DAT"), str(STUDENTS / "MISS.DAT"), "--gradescope", str(out)])
    assert status == 2
    assert "--gradescope writes one submission's results" in capsys.readouterr().err  # two named
    assert not out.exists()


def test_a_submission_of_several_folders_is_one_student_with_nothing_to_run(tmp_path: Path) -> None:
    """Gradescope's /autograder/submission is one student whatever it holds: two folders of
    programs are that student's mistake (a results.json that says so), not a failed autograder."""
    for name in ("first", "second"):
        (tmp_path / "submission" / name).mkdir(parents=True)
        shutil.copy(STUDENTS / "GOOD.DAT", tmp_path / "submission" / name / "MAIN.DAT")
    out = tmp_path / "results.json"
    assert main(["grade", str(TASK), str(tmp_path / "submission"), "--gradescope", str(out)]) == 1
    document = json.loads(out.read_text())
    validate(document)
    read = document["tests"][0]
    assert read["name"] == "PROGRAM READ" and read["status"] == "failed"
    assert "0 program files" in read["output"] and "submission" in read["output"]
    assert document["score"] == 0
