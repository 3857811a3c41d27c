"""``valterm cell show``: the objects of a setup file in world millimetres."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from valterm.cli import main

REPO = Path(__file__).resolve().parent.parent  # the repository: the bundled data (cells/, programs/)
def test_json_of_the_process_cell(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--workspace", str(tmp_path), "cell", "show", "PROCESS.SET", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["units"] == "MM"
    assert [o["number"] for o in data["objects"]] == list(range(1, 15))
    assert data["objects"][0]["vertices"] == [
        [440, -50, -320], [440, -50, -250], [440, -20, -250], [440, -20, -320],
        [490, -50, -320], [490, -50, -250], [490, -20, -250], [490, -20, -320],
    ]


def test_text_of_a_cell_by_path(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["cell", "show", str(REPO / "cells" / "CONV.SET")]) == 0
    out = capsys.readouterr().out
    assert out.startswith("CONV.SET: 5 objects, units MM")
    assert "object 5: 8 vertices" in out
    assert "    1    -241.00     400.00    -330.00" in out


def test_inches_and_screen_frame_are_shown_in_world_mm(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    body = "\n".join(["0 0 0", "0 0 1", "0 1 1", "0 1 0", "1 0 0", "1 0 1", "1 1 1", "1 1 0"])
    path = tmp_path / "INCH.SET"
    path.write_text(f"1\nIN\nS\n1,8\n1 2 3\n{body}\n")
    assert main(["cell", "show", str(path), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["system"] == "S"
    assert data["objects"][0]["vertices"][0] == pytest.approx([76.2, 25.4, 50.8 - 26.0])


def test_malformed_file_exits_1_with_file_line_reason(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "BAD.SET"
    path.write_text("1\nMM\nW\n1,7\n")
    assert main(["cell", "show", str(path)]) == 1
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.strip() == "valterm: BAD.SET:4: object 1: N = 7 is odd; the two polygons need the same number of vertices"


def test_damaged_name_in_the_workspace(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "JUNK.SET").write_bytes(b"\x00\x01binary")
    assert main(["--workspace", str(tmp_path), "cell", "show", "junk"]) == 1
    assert capsys.readouterr().err.startswith("valterm: JUNK.SET:1: not a text setup file")


@pytest.mark.parametrize("argument, message", [("NOSUCH", "NOSUCH.SET: no such setup file"),
                                               ("../x", "../x: no such setup file"),  # a path, as given
                                               ("A-B", "'A-B' is not a valid name"),
                                               ("TOOLONGNAME", "is not a valid name")])
def test_missing_or_invalid_names(tmp_path: Path, capsys: pytest.CaptureFixture[str], argument: str, message: str) -> None:
    assert main(["--workspace", str(tmp_path), "cell", "show", argument]) == 1
    assert message in capsys.readouterr().err


def test_winding_warning_goes_to_stderr(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "WIND.SET"
    rows = ["50 0 0", "50 0 70", "50 30 70", "50 30 0", "0 0 0", "0 0 70", "0 30 70", "0 30 0"]
    path.write_text("1\nMM\nW\n1,8\n0 0 0\n" + "\n".join(rows) + "\n")
    assert main(["cell", "show", str(path), "--json"]) == 0
    captured = capsys.readouterr()
    assert "WIND.SET:4: object 1: vertices wind inward" in captured.err
    assert json.loads(captured.out)["warnings"]
