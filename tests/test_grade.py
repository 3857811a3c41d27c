"""``valterm grade``: five student variants of a pick-and-place on the bundled PROCESS cell
(tests/data/grade), graded by one command; the JUnit file read back with xml.etree; run
--json's end event with every part; findings located by program, step and clamp."""

from __future__ import annotations

import io
import json
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from valterm.cli import main
from valterm.core.grading import Task, TaskError, grade, read_task

DATA = Path(__file__).parent / "data" / "grade"
TASK = DATA / "PICK.toml"
STUDENTS = DATA / "students"


@pytest.fixture(scope="module")
def graded(tmp_path_factory: pytest.TempPathFactory) -> tuple[int, dict, ET.Element]:
    out = tmp_path_factory.mktemp("grade")
    files = [str(path) for path in sorted(STUDENTS.glob("*.DAT"))]  # as the shell expands students/*.DAT
    status = main(["grade", str(TASK), *files, "--json", str(out / "r.json"), "--junit", str(out / "r.xml"),
                   "--jobs", "2"])
    return status, json.loads((out / "r.json").read_text()), ET.parse(out / "r.xml").getroot()


def test_five_variants_one_passes_four_fail_each_named(graded: tuple[int, dict, ET.Element]) -> None:
    status, report, _ = graded
    assert status == 1  # not every student passed
    results = {r["student"]: r for r in report["results"]}
    assert sorted(results) == ["CRASH", "GOOD", "MISS", "REACH", "SYNTAX"]
    assert results["GOOD"]["passed"] and results["GOOD"]["failures"] == []
    first = {name: r["failures"][0] for name, r in results.items() if not r["passed"]}
    assert {name: f["kind"] for name, f in first.items()} == {
        "MISS": "part", "CRASH": "collision", "REACH": "error", "SYNTAX": "syntax"}
    assert first["MISS"]["message"].startswith("PART 1 IS AT 440.0, -50.0, -320.0, NOT AT -174.6, 576.4, -279.6: ")
    assert "MISS STEP 7: CLOSEI: NOTHING BETWEEN THE FINGERS, THE CLAMP CLOSED ON AIR" in first["MISS"]["message"]
    assert first["CRASH"]["message"] == "CLAMP COLLIDES WITH 1 (FIRST PART) (CRASH STEP 5, CLAMP AT 464.13 -44.98 -294.99)"
    assert first["REACH"]["message"] == "REACH STEP 10: LOCATION OUT OF REACH"
    assert first["SYNTAX"]["message"].startswith("SYNTAX STEP 10: MOVEZ is not a command")
    assert (report["passed"], report["failed"]) == (1, 4)
    # the good student put part 1 down where the task wants it, in the cycle time allowed
    part1 = results["GOOD"]["parts"][0]
    assert part1["part"] == 1 and not part1["held"]
    assert part1["position"] == pytest.approx([-174.564, 576.404, -279.583], abs=0.01)
    assert 7.0 < results["GOOD"]["cycle_time_s"] < 12.0
    assert "GRASPED PART 1 (GOOD STEP 7, CLAMP AT 465.00 -45.00 -245.00)" in results["GOOD"]["findings"]


def test_the_junit_file_is_a_valid_junit_report(graded: tuple[int, dict, ET.Element]) -> None:
    root = graded[2]
    assert root.tag == "testsuites"
    (suite,) = list(root)
    assert suite.tag == "testsuite" and suite.get("name") == "PICK"
    cases = suite.findall("testcase")
    assert len(cases) == int(suite.get("tests", "")) == int(root.get("tests", "")) == 5
    failed = [c for c in cases if c.find("failure") is not None]
    assert len(failed) == int(suite.get("failures", "")) == 4
    assert int(suite.get("errors", "")) == 0
    assert float(suite.get("time", "")) == pytest.approx(sum(float(c.get("time", "")) for c in cases), abs=0.01)
    for case in cases:
        assert case.get("classname") == "PICK" and case.get("name")
        float(case.get("time", ""))
        assert case.find("system-out") is not None
        for failure in case.findall("failure"):
            assert failure.get("type") and failure.get("message") == failure.text
    by_name = {c.get("name"): c for c in cases}
    assert by_name["GOOD"].find("failure") is None
    assert by_name["CRASH"].find("failure").get("type") == "collision"  # type: ignore[union-attr]
    assert "CLAMP COLLIDES WITH 1 (FIRST PART) (CRASH STEP 5" in (by_name["CRASH"].findtext("system-out") or "")


def test_the_table_names_each_students_first_failure(capsys: pytest.CaptureFixture[str]) -> None:
    status = main(["grade", str(TASK), *(str(STUDENTS / f"{n}.DAT") for n in ("GOOD", "REACH")), "--jobs", "1"])
    lines = capsys.readouterr().out.splitlines()
    assert status == 1
    assert lines[0].split() == ["STUDENT", "RESULT", "FAILURE", "CYCLE", "S", "TIME", "S", "WHAT"]
    assert lines[1].split()[:2] == ["GOOD", "PASS"]
    assert lines[2].split()[:3] == ["REACH", "FAIL", "error"]
    assert lines[2].endswith("REACH STEP 10: LOCATION OUT OF REACH")
    assert lines[3].startswith("PICK: 2 GRADED, 1 PASSED, 1 FAILED IN ")


def test_all_passing_is_exit_0_and_json_to_standard_output(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["grade", str(TASK), str(STUDENTS / "GOOD.DAT"), "--json", "-"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["results"][0]["passed"]


def write_task(folder: Path, text: str) -> Path:
    path = folder / "T.toml"
    path.write_text(text)
    return path


BASE = 'cell = "PROCESS"\nlocations = ["PROCESS"]\n'
PART = '[[part]]\nnumber = 1\nposition = [-174.6, 576.4, -279.6]\n'


def test_collisions_allowed_and_the_cycle_time_are_the_tasks_choice(tmp_path: Path) -> None:
    lenient = read_task(write_task(tmp_path, BASE + "collisions = true\n" + PART))
    assert grade(lenient, STUDENTS / "CRASH.DAT").passed
    strict = read_task(write_task(tmp_path, BASE + "cycle_time = 5\n" + PART))
    failures = grade(strict, STUDENTS / "GOOD.DAT").failures
    assert [(f.kind, f.message) for f in failures] == [("cycle-time", "CYCLE TIME 7.33 S IS OVER THE 5 S ALLOWED")]


def test_a_runaway_student_fails_at_the_limit(tmp_path: Path) -> None:
    (tmp_path / "LOOP.DAT").write_text("10  TYPE HELLO\n    GOTO 10\n")
    task = read_task(write_task(tmp_path, BASE + PART))
    from valterm.core.val.limits import RunLimits

    verdict = grade(task, tmp_path / "LOOP.DAT", RunLimits(steps=50))
    assert verdict.first is not None and verdict.first.kind == "limit"
    assert verdict.first.message == "LOOP STEP 1: DID NOT FINISH WITHIN 50 STEPS: AN ENDLESS LOOP?"


def test_a_folder_submission_calls_its_own_subprograms(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    student = tmp_path / "class" / "ADA"
    student.mkdir(parents=True)
    good = (STUDENTS / "GOOD.DAT").read_text().splitlines()
    (student / "MAIN.DAT").write_text("\n".join([*good[:6], "    CALL PLACE"]) + "\n")
    (student / "PLACE.DAT").write_text("\n".join(good[6:]) + "\n")
    (tmp_path / "class" / "BOB").mkdir()
    shutil.copy(STUDENTS / "MISS.DAT", tmp_path / "class" / "BOB" / "MAIN.DAT")
    task = write_task(tmp_path, BASE + 'program = "MAIN"\n' + PART)
    assert main(["grade", str(task), str(tmp_path / "class"), "--json", "-"]) == 1
    results = {r["student"]: r for r in json.loads(capsys.readouterr().out)["results"]}
    assert results["ADA"]["passed"] and results["ADA"]["program"] == "MAIN.DAT"
    assert "GRASPED PART 1 (PLACE STEP 1, CLAMP AT 465.00 -45.00 -245.00)" in results["ADA"]["findings"]
    assert not results["BOB"]["passed"]
    assert not (student / "CHECK.DAT").exists()  # nothing is written into a submission


@pytest.mark.parametrize("text, reason", [
    (BASE + "colisions = false\n", "T.toml: unknown key 'colisions'"),
    ('locations = ["PROCESS"]\n', "T.toml: no cell"),
    (BASE + "[[part]]\nnumber = 1\nposition = [1, 2]\n", "T.toml: part 1: position needs 3 numbers"),
    (BASE + "[[part]]\nnumber = 99\nposition = [1, 2, 3]\n", "the task names part 99; the cell has 14"),
    ('cell = "NOSUCH"\n', "T.toml: NOSUCH: no such SET file"),
    ("cell = [\n", "T.toml: not a TOML file"),
    (BASE + 'dialect = "basic"\n', "T.toml: dialect: 'basic' is not a dialect: use 1985 or v+"),
])
def test_a_wrong_task_file_is_one_message_and_exit_1(tmp_path: Path, text: str, reason: str,
                                                      capsys: pytest.CaptureFixture[str]) -> None:
    task = write_task(tmp_path, text)
    assert main(["grade", str(task), str(STUDENTS / "GOOD.DAT")]) == 1
    err = capsys.readouterr().err
    assert reason in err and "Traceback" not in err


def test_a_missing_or_unreadable_submission_is_a_file_failure(tmp_path: Path) -> None:
    task: Task = read_task(TASK)
    (tmp_path / "EMPTY").mkdir()
    verdict = grade(task, tmp_path / "EMPTY")
    assert [f.kind for f in verdict.failures] == ["file"]
    with pytest.raises(TaskError):
        read_task(write_task(tmp_path, "cell = 3\n"))


def test_run_json_end_event_has_every_part_and_findings_are_located(tmp_path: Path,
                                                                    capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["run", str(STUDENTS / "REACH.DAT"), "--cell", "PROCESS", "--loc", "PROCESS", "--json", "--collisions",
            "--workspace", str(tmp_path / "ws")]
    assert main(argv) == 1
    events = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    end = events[-1]
    assert end["event"] == "end" and len(end["parts"]) == 14
    held = [p["part"] for p in end["parts"] if p["held"]]
    assert held == [1]  # it stopped out of reach, part 1 still in the clamp
    assert end["parts"][1] == {"part": 2, "position": [440.0, 105.83, -320.0], "held": False}
    grasp = next(e for e in events if e["event"] == "grasp")
    assert (grasp["program"], grasp["step"], grasp["part"]) == ("REACH", 7, 1)
    assert grasp["clamp"] == pytest.approx([465.0, -45.0, -245.0], abs=0.01)
    near = next(e for e in events if e["event"] == "near")
    assert near["program"] == "REACH" and near["step"] == 5 and len(near["clamp"]) == 3


def test_closing_on_air_is_said_typed_too_and_a_grasp_is_not(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                              capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.setattr("sys.stdin", io.StringIO("CLOSEI\nOPENI\nLEFTY\nMOVE A\nCLOSEI\n"))
    assert main(["monitor", "--setup", "PROCESS", "--workspace", str(tmp_path / "ws")]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[out.index(". CLOSEI") + 1] == "CLOSEI: NOTHING BETWEEN THE FINGERS, THE CLAMP CLOSED ON AIR"
    assert out[-1] == "IT IS POSSIBLE TO GRASP THIS PART"  # the second CLOSEI, at A, grasps part 1


def test_a_vplus_submission_reaches_the_precision_points_of_the_tasks_location_file(tmp_path: Path) -> None:
    from valterm.core import resources

    shutil.copy(resources.data_path("programs", "vplus", "STATIONS.LOC"), tmp_path / "STATIONS.LOC")
    task = read_task(write_task(tmp_path, 'cell = "PROCESS"\nlocations = ["STATIONS"]\ncollisions = true\n'
                                          "[[part]]\nnumber = 1\nposition = [-174.6, 576.4, -279.6]\ntolerance = 1\n"))
    verdict = grade(task, resources.data_path("programs", "vplus", "precision.v2"))
    assert verdict.failures == [] and verdict.program == "precision.v2"
    assert verdict.parts[0]["held"] is False


def test_a_task_names_its_rules_and_a_bad_name_is_refused(tmp_path: Path) -> None:
    from valterm.core.grading import TaskError, read_task

    good = tmp_path / "T.toml"
    good.write_text('cell = "PROCESS"\nrules = "controller"\n')
    assert read_task(good).rules == "controller"
    bad = tmp_path / "B.toml"
    bad.write_text('cell = "PROCESS"\nrules = "sideways"\n')
    with pytest.raises(TaskError, match="rules"):
        read_task(bad)
