"""``valterm grade --merge`` (issue 40 item 5): a class graded in shares, on several machines
or by several jobs, combined into one JSON and one JUnit file; a student in two shares is
refused by name; GRADING.md's fan-out with GNU parallel run as written, on one machine."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from valterm.cli import main

ROOT = Path(__file__).resolve().parent.parent
DATA = ROOT / "tests" / "data" / "grade"
TASK = DATA / "PICK.toml"
STUDENTS = DATA / "students"


@pytest.fixture
def klass(tmp_path: Path) -> Path:
    """A class folder: one folder a student, each holding one of the five variants."""
    for name in ("CRASH", "GOOD", "MISS", "REACH", "SYNTAX"):
        (tmp_path / "subs" / name.lower()).mkdir(parents=True)
        shutil.copy(STUDENTS / f"{name}.DAT", tmp_path / "subs" / name.lower() / "MAIN.DAT")
    return tmp_path / "subs"


def share(klass: Path, out: Path, *names: str) -> Path:
    assert main(["grade", str(TASK), *(str(klass / n) for n in names), "--json", str(out), "--jobs", "1"]) in (0, 1)
    return out


def test_shares_merge_into_the_whole_class(klass: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    a = share(klass, tmp_path / "a.json", "crash", "good")
    b = share(klass, tmp_path / "b.json", "miss", "reach", "syntax")
    assert main(["grade", str(TASK), str(klass), "--json", str(tmp_path / "whole.json"), "--jobs", "1"]) == 1
    capsys.readouterr()
    status = main(["grade", "--merge", str(a), str(b), "--json", str(tmp_path / "m.json"),
                   "--junit", str(tmp_path / "m.xml")])
    assert status == 1  # some failed
    table = capsys.readouterr().out
    assert "PICK: 5 GRADED, 1 PASSED, 4 FAILED" in table and "MERGED FROM 2 FILES" in table
    merged, whole = (json.loads((tmp_path / f).read_text()) for f in ("m.json", "whole.json"))
    strip = [{k: v for k, v in r.items() if k != "seconds"} for r in whole["results"]]
    assert [{k: v for k, v in r.items() if k != "seconds"} for r in merged["results"]] == strip
    assert (merged["task"], merged["passed"], merged["failed"]) == ("PICK", 1, 4)
    suite = ET.parse(tmp_path / "m.xml").getroot().find("testsuite")
    assert suite is not None and suite.get("name") == "PICK" and suite.get("tests") == "5"
    assert [c.get("name") for c in suite.findall("testcase")] == ["crash", "good", "miss", "reach", "syntax"]
    crash = suite.findall("testcase")[0].find("failure")
    assert crash is not None and crash.get("type") == "collision"


def test_a_student_in_two_shares_is_refused_by_name(klass: Path, tmp_path: Path,
                                                    capsys: pytest.CaptureFixture[str]) -> None:
    a = share(klass, tmp_path / "a.json", "crash", "good")
    b = share(klass, tmp_path / "b.json", "good", "miss")
    capsys.readouterr()
    assert main(["grade", "--merge", str(a), str(b), "--junit", str(tmp_path / "m.xml")]) == 1
    err = capsys.readouterr().err
    assert "b.json: student good is in a.json too" in err
    assert not (tmp_path / "m.xml").exists()  # nothing half-written


@pytest.mark.parametrize(("text", "reason"), [
    ("not json", "not a JSON file"),
    ('{"task": "PICK"}', "not the JSON of valterm grade"),
    ('{"task": "PICK", "results": [{"student": 3}]}', "result 1: student must be"),
    pytest.param('[' * 100000 + ']' * 100000, "not a JSON file", id="100000-deep"),
])
def test_a_file_that_is_not_grades_is_refused_by_name(tmp_path: Path, text: str, reason: str,
                                                      capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "bad.json").write_text(text)
    assert main(["grade", "--merge", str(tmp_path / "bad.json")]) == 1
    err = capsys.readouterr().err
    assert "bad.json: " in err and reason in err and "Traceback" not in err


def test_results_of_two_tasks_are_not_merged(klass: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    a = share(klass, tmp_path / "a.json", "good")
    other = json.loads(a.read_text()) | {"task": "PLACE"}
    for result in other["results"]:
        result["student"] = "other"
    (tmp_path / "b.json").write_text(json.dumps(other))
    capsys.readouterr()
    assert main(["grade", "--merge", str(a), str(tmp_path / "b.json")]) == 1
    assert "b.json: task PLACE, not PICK as in a.json" in capsys.readouterr().err


def test_merge_and_submissions_do_not_mix(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["grade", str(TASK)]) == 2
    assert "name the submissions to grade" in capsys.readouterr().err
    assert main(["grade", "--merge", str(TASK), "--gradescope", str(tmp_path / "r.json")]) == 2
    assert "--gradescope" in capsys.readouterr().err


def recipe() -> str:
    """GRADING.md's GNU parallel fan-out, as written there."""
    text = (ROOT / "docs" / "GRADING.md").read_text()
    found = re.search(r"<!-- the fan-out recipe.*?-->\s*```sh\n(.*?)```", text, re.S)
    assert found, "GRADING.md has the GNU parallel recipe"
    return found.group(1)


@pytest.mark.skipif(shutil.which("parallel") is None, reason="GNU parallel is not installed (apt-get install parallel)")
def test_the_gnu_parallel_recipe_grades_the_class_in_shares(klass: Path, tmp_path: Path) -> None:
    bin_folder = tmp_path / "bin"
    bin_folder.mkdir()
    shim = bin_folder / "valterm"
    shim.write_text(f'#!/bin/sh\nexec "{sys.executable}" -m valterm "$@"\n')
    shim.chmod(0o755)
    shutil.copy(TASK, tmp_path / "PICK.toml")
    env = {**os.environ, "PATH": f"{bin_folder}{os.pathsep}{os.environ['PATH']}", "PYTHONPATH": str(ROOT),
           "SHARE": "2"}
    done = subprocess.run(["bash", "-c", recipe()], cwd=tmp_path, env=env, capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 1, done.stderr  # the merge: some students failed
    assert "PICK: 5 GRADED, 1 PASSED, 4 FAILED" in done.stdout
    assert len(list((tmp_path / "shares").glob("*.json"))) == 3  # 5 students, 2 a share
    report = ET.parse(tmp_path / "report.xml").getroot()
    assert sorted(c.get("name", "") for c in report.iter("testcase")) == ["crash", "good", "miss", "reach", "syntax"]
