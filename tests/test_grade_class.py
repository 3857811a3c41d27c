"""``valterm grade`` on a class as an instructor has it (issue 38): submissions are read only
inside themselves, never through a link (a program linked to /etc/passwd, a program or a
student folder linked outside, a FIFO named like a program); students are found by folder
whatever the shell expands (``subs`` and ``subs/*`` grade the same students under the same
unique names, an empty student is a FAIL row); nonsensical task values are refused by key."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from valterm.cli import main
from valterm.core.grading import TaskError, read_task

DATA = Path(__file__).parent / "data" / "grade"
GOOD = (DATA / "students" / "GOOD.DAT").read_text()
TASK = DATA / "PICK.toml"
SECRET = "ROOTSECRET:x:0:0:root:/root:/bin/bash\nDAEMONSECRET:x:1:1\n"


def grade_all(capsys: pytest.CaptureFixture[str], *arguments: Path | str, task: Path = TASK) -> tuple[int, str]:
    """The command's status and everything it wrote: the table, the JSON, the JUnit file."""
    out = Path(os.environ["GRADE_OUT"])
    json_file, junit_file = out / "r.json", out / "r.xml"
    status = main(["grade", str(task), *map(str, arguments), "--json", str(json_file), "--junit", str(junit_file),
                   "--jobs", "1"])
    captured = capsys.readouterr()
    return status, captured.out + captured.err + json_file.read_text() + junit_file.read_text()


@pytest.fixture(autouse=True)
def reports(tmp_path_factory: pytest.TempPathFactory, monkeypatch: pytest.MonkeyPatch) -> None:
    """The reports go to a folder of their own, beside no submission."""
    monkeypatch.setenv("GRADE_OUT", str(tmp_path_factory.mktemp("reports")))


def results(everything: str) -> dict[str, dict]:  # type: ignore[type-arg]
    start = everything.index("{\n")
    document, _ = json.JSONDecoder().raw_decode(everything[start:])
    return {r["student"]: r for r in document["results"]}


# -- confinement ----------------------------------------------------------------------------

@pytest.fixture
def outside(tmp_path: Path) -> Path:
    """A folder outside the submissions: a secret and a program that would pass."""
    folder = tmp_path / "outside"
    folder.mkdir()
    (folder / "passwd").write_text(SECRET)
    (folder / "GOOD.DAT").write_text(GOOD)
    (folder / "alice").mkdir()
    (folder / "alice" / "MAIN.DAT").write_text(GOOD)
    return folder


def test_a_main_program_linked_to_a_secret_is_refused_and_none_of_it_shown(
        tmp_path: Path, outside: Path, capsys: pytest.CaptureFixture[str]) -> None:
    subs = tmp_path / "subs"
    (subs / "alice").mkdir(parents=True)
    (subs / "alice" / "MAIN.DAT").write_text(GOOD)
    (subs / "bob").mkdir()
    (subs / "bob" / "MAIN.DAT").symlink_to(outside / "passwd")
    status, everything = grade_all(capsys, subs)
    assert status == 1
    assert "SECRET" not in everything and "ROOT" not in everything  # not a byte of the target
    found = results(everything)
    assert found["alice"]["passed"]
    (failure,) = found["bob"]["failures"]
    assert failure["kind"] == "file" and "MAIN.DAT: is a link" in failure["message"]


def test_a_program_or_a_student_folder_linked_outside_is_not_run(
        tmp_path: Path, outside: Path, capsys: pytest.CaptureFixture[str]) -> None:
    subs = tmp_path / "subs"
    subs.mkdir()
    (subs / "carol").symlink_to(outside / "alice", target_is_directory=True)  # the student folder a link
    (subs / "erin").mkdir()
    (subs / "erin" / "MAIN.DAT").symlink_to(outside / "GOOD.DAT")  # a passing program, outside
    for arguments in ([subs], sorted(subs.iterdir())):
        status, everything = grade_all(capsys, *arguments)
        found = results(everything)
        assert status == 1 and sorted(found) == ["carol", "erin"]
        for name in ("carol", "erin"):
            assert not found[name]["passed"] and found[name]["cycle_time_s"] == 0  # never run
            assert [f["kind"] for f in found[name]["failures"]] == ["file"]
        assert "carol: is a link" in found["carol"]["failures"][0]["message"]


def test_a_called_program_linked_outside_or_a_fifo_is_refused(tmp_path: Path, outside: Path,
                                                              capsys: pytest.CaptureFixture[str]) -> None:
    subs = tmp_path / "subs"
    (subs / "bob").mkdir(parents=True)
    (subs / "bob" / "MAIN.DAT").write_text("    CALL PICKIT\n")
    (subs / "bob" / "PICKIT.DAT").symlink_to(outside / "passwd")
    status, everything = grade_all(capsys, subs)
    assert status == 1 and "SECRET" not in everything
    assert "PICKIT.DAT: is a link" in results(everything)["bob"]["failures"][0]["message"]


def test_a_hard_link_is_the_file_itself_and_is_read(tmp_path: Path, outside: Path,
                                                    capsys: pytest.CaptureFixture[str]) -> None:
    """The documented choice: a hard link is a regular file in the submission (a link to a
    file the student cannot write is stopped by the system's protected_hardlinks)."""
    subs = tmp_path / "subs"
    (subs / "alice").mkdir(parents=True)
    os.link(outside / "GOOD.DAT", subs / "alice" / "MAIN.DAT")
    status, everything = grade_all(capsys, subs)
    assert status == 0 and results(everything)["alice"]["passed"]


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
@pytest.mark.parametrize("name", ["MAIN.DAT", "PICKIT.DAT"])
def test_a_fifo_named_like_a_program_fails_at_once_never_blocking(tmp_path: Path, name: str) -> None:
    subs = tmp_path / "subs"
    (subs / "bob").mkdir(parents=True)
    if name != "MAIN.DAT":
        (subs / "bob" / "MAIN.DAT").write_text("    CALL PICKIT\n")
    os.mkfifo(subs / "bob" / name)
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).parent.parent)}
    done = subprocess.run([sys.executable, "-m", "valterm", "grade", str(TASK), str(subs), "--json", "-"],
                          capture_output=True, text=True, timeout=60, env=env, cwd=tmp_path)
    assert done.returncode == 1, done.stderr
    (result,) = json.loads(done.stdout)["results"]
    assert result["student"] == "bob" and result["failures"][0]["kind"] == "file"
    assert f"{name}: is a FIFO (a named pipe), not a program file" in result["failures"][0]["message"]


# -- students by folder ---------------------------------------------------------------------

@pytest.fixture
def klass(tmp_path: Path) -> Path:
    """alice: one program; bob: MAIN CALLs PICKIT; dave: nothing to run; eve: a V+ file."""
    subs = tmp_path / "subs"
    for name in ("alice", "bob", "dave"):
        (subs / name).mkdir(parents=True)
    (subs / "alice" / "MAIN.DAT").write_text(GOOD)
    good = GOOD.splitlines()
    (subs / "bob" / "PICKIT.DAT").write_text("\n".join(good[6:]) + "\n")
    (subs / "bob" / "MAIN.DAT").write_text("\n".join([*good[:6], "    CALL PICKIT"]) + "\n")
    (subs / "dave" / "NOTES.TXT").write_text("I ran out of time\n")
    return subs


def test_a_class_folder_and_its_glob_grade_the_same_students(klass: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                             capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(tmp_path)  # the paths as the instructor types them
    graded = []
    for arguments in (["subs"], ["subs/"], sorted(f"subs/{p.name}" for p in klass.iterdir())):
        status, everything = grade_all(capsys, *arguments)
        assert status == 1
        found = results(everything)
        graded.append({name: (r["passed"], r["program"]) for name, r in found.items()})
        assert "dave" in found and found["dave"]["failures"][0]["kind"] == "file"
        assert "0 program files" in found["dave"]["failures"][0]["message"]
        junit = ET.fromstring(everything[everything.index("<?xml"):].encode())
        names = [case.get("name") for case in junit.iter("testcase")]
        assert sorted(names) == ["alice", "bob", "dave"]  # unique, PICKIT no student of its own
        assert "3 GRADED, 2 PASSED, 1 FAILED" in everything
    assert graded[0] == graded[1] == graded[2] == {
        "alice": (True, "MAIN.DAT"), "bob": (True, "MAIN.DAT"), "dave": (False, "")}


def test_two_classes_keep_their_students_apart(klass: Path, tmp_path: Path,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    other = tmp_path / "other"
    shutil.copytree(klass, other)
    status, everything = grade_all(capsys, klass, other)
    assert sorted(results(everything)) == ["other/alice", "other/bob", "other/dave",
                                           "subs/alice", "subs/bob", "subs/dave"]


def test_the_main_program_is_the_one_no_other_calls_else_the_tasks(klass: Path, tmp_path: Path,
                                                                  capsys: pytest.CaptureFixture[str]) -> None:
    (klass / "alice" / "SPARE.DAT").write_text("    READY\n")  # two programs, neither CALLed
    status, everything = grade_all(capsys, klass)
    message = results(everything)["alice"]["failures"][0]["message"]
    assert "2 programs that no other CALLs (MAIN, SPARE)" in message and "program = " in message
    task = tmp_path / "T.toml"
    task.write_text(TASK.read_text().replace('name = "PICK"', 'name = "PICK"\nprogram = "MAIN"'))
    status, everything = grade_all(capsys, klass, task=task)
    assert results(everything)["alice"]["passed"]


def test_loose_program_files_named_one_by_one_are_students(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    status, everything = grade_all(capsys, *sorted((DATA / "students").glob("*.DAT")))
    assert sorted(results(everything)) == ["CRASH", "GOOD", "MISS", "REACH", "SYNTAX"]


# -- the task's values ----------------------------------------------------------------------

BASE = 'cell = "PROCESS"\nlocations = ["PROCESS"]\n'
PART = '[[part]]\nnumber = 1\nposition = [-174.6, 576.4, -279.6]\n'


@pytest.mark.parametrize("text, reason", [
    (BASE + PART + "tolerance = -5\n", "T.toml: part 1 tolerance: -5 must be 0 or more"),
    (BASE + "cycle_time = -1\n", "T.toml: cycle_time: -1 must be more than 0"),
    (BASE + "loops = 0\n", "T.toml: loops: 0 must be a whole number, 1 or more"),
    (BASE + "loops = 1.5\n", "T.toml: loops: 1.5 must be a whole number, 1 or more"),
    (BASE + PART + PART, "T.toml: part 1: two [[part]] tables for one part"),
    (BASE + "cycle_time = " + "9" * 400 + "\n", "T.toml: cycle_time: a 400-digit number is out of range"),
    (BASE + "loops = " + "9" * 5000 + "\n", "T.toml: a number of more than 4300 digits"),
    (BASE + PART.replace("-174.6", "1" + "0" * 399), "T.toml: part 1 position: a 400-digit number is out of range"),
])
def test_nonsensical_task_values_are_refused_by_key(tmp_path: Path, text: str, reason: str,
                                                    capsys: pytest.CaptureFixture[str]) -> None:
    task = tmp_path / "T.toml"
    task.write_text(text)
    with pytest.raises(TaskError, match="T.toml"):
        read_task(task)
    assert main(["grade", str(task), str(DATA / "students" / "GOOD.DAT")]) == 1
    err = capsys.readouterr().err
    assert reason in err and "Traceback" not in err


def test_the_off_target_message_gives_the_target(capsys: pytest.CaptureFixture[str]) -> None:
    main(["grade", str(TASK), str(DATA / "students" / "MISS.DAT"), "--json", "-"])
    (result,) = json.loads(capsys.readouterr().out)["results"]
    assert result["failures"][0]["message"].startswith(
        "PART 1 IS AT 440.0, -50.0, -320.0, NOT AT -174.6, 576.4, -279.6: 878.5 MM AWAY (TOLERANCE 5 MM)")


# -- limits from the task -------------------------------------------------------------------

def loop_task(tmp_path: Path, extra: str) -> Path:
    task = tmp_path / "T.toml"
    task.write_text(BASE + extra)
    return task


def test_the_task_sets_the_limits_and_the_command_line_overrides_them(tmp_path: Path) -> None:
    from valterm.core.grading import grade
    from valterm.core.val.limits import RunLimits

    (tmp_path / "LOOP.DAT").write_text("10  X = 1\n    GOTO 10\n")  # silent: no output, no robot time
    task = read_task(loop_task(tmp_path, "max_steps = 50\n"))
    verdict = grade(task, tmp_path / "LOOP.DAT")
    assert [(f.kind, f.message) for f in verdict.failures] == [
        ("limit", "LOOP STEP 1: DID NOT FINISH WITHIN 50 STEPS: AN ENDLESS LOOP?")]
    from valterm.core.grading import run_limits

    assert run_limits(task, steps=70) == RunLimits(steps=70)
    assert run_limits(read_task(loop_task(tmp_path, "max_lines = 9\nmax_seconds = 0\n"))) == RunLimits(
        lines=9, seconds=0)


def test_by_default_a_run_is_cut_at_ten_times_the_cycle_time(tmp_path: Path,
                                                              capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "LOOP.DAT").write_text("10  DELAY 1\n    GOTO 10\n")
    (tmp_path / "LATE.DAT").write_text("    READY\n    DELAY 100000\n")
    task = loop_task(tmp_path, "cycle_time = 2\n")
    assert main(["grade", str(task), str(tmp_path / "LOOP.DAT"), str(tmp_path / "LATE.DAT"), "--json", "-"]) == 1
    found = {r["student"]: r for r in json.loads(capsys.readouterr().out)["results"]}
    assert found["LOOP"]["failures"][0] == {
        "kind": "limit", "message": "LOOP STEP 2: DID NOT FINISH WITHIN 20 S OF ROBOT TIME: AN ENDLESS LOOP?"}
    assert 20 < found["LOOP"]["cycle_time_s"] <= 21.5
    assert found["LATE"]["failures"][0] == {
        "kind": "limit", "message": "LATE STEP 2: DID NOT FINISH WITHIN 20 S OF ROBOT TIME: AN ENDLESS LOOP?"}
    # the instructor's --max-seconds wins over the default, for a last DELAY too
    assert main(["grade", str(task), str(tmp_path / "LATE.DAT"), "--max-seconds", "60", "--json", "-"]) == 1
    (late,) = json.loads(capsys.readouterr().out)["results"]
    assert late["failures"][0]["message"] == "LATE STEP 2: DID NOT FINISH WITHIN 60 S OF ROBOT TIME: AN ENDLESS LOOP?"


@pytest.mark.parametrize("text, reason", [
    ("max_steps = -1\n", "T.toml: max_steps: -1 must be a whole number, 0 (no limit) or more"),
    ("max_seconds = -2\n", "T.toml: max_seconds: -2 must be 0 (no limit) or more"),
    ("max_lines = 2.5\n", "T.toml: max_lines: 2.5 must be a whole number, 0 (no limit) or more"),
])
def test_a_wrong_limit_in_the_task_is_refused_by_key(tmp_path: Path, text: str, reason: str) -> None:
    with pytest.raises(TaskError, match=reason.replace("(", r"\(").replace(")", r"\)")):
        read_task(loop_task(tmp_path, text))
