"""The workspace: first use, name rules, and nothing touched outside it."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from valterm.core.files.errors import FileFormatError
from valterm.core.files.programs import Program, ProgramLine
from valterm.core.kinematics import Location
from valterm.core import resources
from valterm.core.workspace import Workspace, WorkspaceError, check_name, default_root


def _tree(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): (p.read_bytes() if p.is_file() else b"") for p in sorted(folder.rglob("*"))}


def test_first_use_copies_the_bundled_data(tmp_path: Path) -> None:
    workspace = Workspace.open(tmp_path / "ws")
    names = sorted(p.name for p in workspace.root.iterdir())
    for expected in ("PROCESS.SET", "CONV.SET", "DEMO3.SET", "PROCESS.LOC", "CONV.LOC",
                     "PROCESS.DAT", "CONV1.DAT", "CONV2.DAT", "DATFILER.DAT", "CHECK.DAT"):
        assert expected in names
    assert "README.md" not in names
    assert workspace.programs_directory() == ["CONV1", "CONV2", "PROCESS"]
    assert workspace.list_programs() == ["CONV1", "CONV2", "PROCESS"]
    assert workspace.list_setups() == ["CONV", "DEMO3", "PROCESS"]
    assert workspace.list_locations() == ["CONV", "PROCESS"]
    assert workspace.read_variables() == {}
    assert len(workspace.read_setup("process").objects) == 14
    assert workspace.read_locations("PROCESS.LOC")["A"].xyz == (465.0, -45.0, -245.0)
    assert workspace.read_program("process.dat").name == "PROCESS"


def test_reopening_keeps_the_users_files(tmp_path: Path) -> None:
    workspace = Workspace.open(tmp_path)
    workspace.write_locations("PROCESS", {"Z": Location((1.0, 2.0, 3.0), (0.0, 90.0, 0.0))})
    (tmp_path / "CONV.SET").unlink()
    again = Workspace.open(tmp_path)
    assert list(again.read_locations("PROCESS")) == ["Z"]
    assert not (tmp_path / "CONV.SET").exists()  # first use only: a deleted file stays deleted


def test_bundled_data_ships_inside_the_package() -> None:
    names = {p.name for p in resources.bundled_files(resources.CELLS)}
    assert {"PROCESS.SET", "CONV.SET", "DEMO3.SET"} <= names
    assert "PROCESS.DAT" in {p.name for p in resources.bundled_files(resources.PROGRAMS)}
    assert resources.read_text("robot", "PUMA.toml").startswith("#") or "[links]" in resources.read_text("robot", "PUMA.toml")


def test_default_root_and_environment(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    monkeypatch.delenv("VALTERM_WORKSPACE", raising=False)
    assert default_root() == tmp_path / "home" / "valterm"
    monkeypatch.setenv("VALTERM_WORKSPACE", str(tmp_path / "elsewhere"))
    assert Workspace.open().root == tmp_path / "elsewhere"
    assert (tmp_path / "elsewhere" / "PROCESS.SET").is_file()
    assert Workspace.open(tmp_path / "given").root == tmp_path / "given"  # --workspace beats the variable


@pytest.mark.parametrize(
    "name, ext, expected",
    [("process", "SET", "PROCESS.SET"), ("PROCESS.SET", "SET", "PROCESS.SET"), ("conv1.dat", "DAT", "CONV1.DAT"),
     ("A", "LOC", "A.LOC"), ("ABCDEFGH9", ".loc", "ABCDEFGH9.LOC"), (" test ", "DAT", "TEST.DAT")],
)
def test_valid_names(name: str, ext: str, expected: str) -> None:
    assert check_name(name, ext) == expected


@pytest.mark.parametrize(
    "name, why",
    [("../x", "path"), ("a/b", "path"), ("a\\b", "path"), ("..", "path"), ("/etc/passwd", "path"), ("~/x", "path"),
     ("ABCDEFGHIJ", "at most 9"), ("A-B", "only the letters"), ("A B", "only the letters"), ("A_B", "only the letters"),
     ("", "1 to 9"), ("P.LOC", "ends in .SET"), ("A.B.SET", "only the letters"), ("NUL", "reserved"),
     ("É", "only the letters"), ("X.", "ends in .SET")],
)
def test_invalid_names_are_refused_clearly(name: str, why: str) -> None:
    with pytest.raises(WorkspaceError) as caught:
        check_name(name, "SET")
    assert str(caught.value).startswith(f"{name!r} is not a valid name: ")
    assert why in str(caught.value)


def test_nothing_is_written_outside_the_workspace(tmp_path: Path) -> None:
    root = tmp_path / "ws"
    outside = tmp_path / "outside.txt"
    outside.write_text("mine")
    workspace = Workspace.open(root)
    before = {p.name for p in tmp_path.iterdir()}
    cell = workspace.read_setup("PROCESS")
    workspace.write_setup("COPY", cell)
    workspace.write_locations("NEW", {"A": Location((0.0, 0.0, 0.0), (0.0, 0.0, 0.0))})
    workspace.write_program(Program("TEST", [ProgramLine(None, "MOVE A"), ProgramLine(None, "STOP")]))
    workspace.write_variables({"ROW": 10.0})
    for bad in ("../outside", "../../x", "/tmp/x", "..\\x"):
        with pytest.raises(WorkspaceError):
            workspace.write_setup(bad, cell)
        with pytest.raises(WorkspaceError):
            workspace.write_program(Program("X"), bad)
        with pytest.raises(WorkspaceError):
            workspace.read_locations(bad)
    assert {p.name for p in tmp_path.iterdir()} == before
    assert outside.read_text() == "mine"
    assert all(p.parent == root for p in root.rglob("*"))
    assert workspace.list_programs() == ["CONV1", "CONV2", "PROCESS", "TEST"]
    assert workspace.read_variables() == {"ROW": 10.0}
    np.testing.assert_allclose(workspace.read_setup("COPY").object(3).vertices, cell.object(3).vertices, atol=1e-6)


def test_system_files_are_not_programs(tmp_path: Path) -> None:
    workspace = Workspace.open(tmp_path)
    with pytest.raises(WorkspaceError, match="kept by the simulator"):
        workspace.write_program(Program("DATFILER"))
    assert "CHECK" not in workspace.list_programs()


def test_a_program_file_copied_in_is_listed_and_lower_case_is_found(tmp_path: Path) -> None:
    workspace = Workspace.open(tmp_path)
    (tmp_path / "extra.dat").write_text("    STOP\n")
    (tmp_path / "lower.set").write_text((tmp_path / "CONV.SET").read_text())
    assert workspace.list_programs()[-1] == "EXTRA"
    assert len(workspace.read_setup("LOWER").objects) == 5
    assert workspace.read_program("extra").step(1).text == "STOP"


@pytest.mark.skipif(not hasattr(os, "symlink"), reason="no symlinks")
def test_a_link_leading_outside_is_refused(tmp_path: Path) -> None:
    secret = tmp_path / "secret.SET"
    secret.write_text("x")
    workspace = Workspace.open(tmp_path / "ws")
    (workspace.root / "LINK.SET").symlink_to(secret)
    with pytest.raises(WorkspaceError, match="outside"):
        workspace.read_setup("LINK")


def test_a_damaged_file_in_the_workspace_is_a_located_error(tmp_path: Path) -> None:
    workspace = Workspace.open(tmp_path)
    (tmp_path / "BAD.SET").write_text("1\nMM\nW\n1,7\n")
    with pytest.raises(FileFormatError, match=r"^BAD.SET:4: "):
        workspace.read_setup("BAD")


def test_a_workspace_that_is_a_file_is_refused(tmp_path: Path) -> None:
    (tmp_path / "file").write_text("")
    with pytest.raises(WorkspaceError, match="is a file"):
        Workspace.open(tmp_path / "file")
