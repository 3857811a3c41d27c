"""Reliability of the file layer: the one write path, the one read path, seeding, numbers, limits.

Issue 16: nothing outside the workspace is read or written through any name or link; every
write is whole; a damaged first use repairs itself; numbers and sizes have limits with
located messages.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from valterm.cli import main
from valterm.core import resources
from valterm.core.errors import ValtermError
from valterm.core.files.errors import FileFormatError
from valterm.core.files.programs import Program, ProgramLine, read_program
from valterm.core.files.setup import read_setup
from valterm.core.files.atomic import (
    is_temporary,
    remove_stale_temporaries,
    write_text_atomic,
)
from valterm.core.files.errors import FileWriteError, shown_name
from valterm.core.files.limits import MAX_LINE, MAX_PARTS, MAX_STEPS, MAX_VERTICES
from valterm.core.files.locations import parse_locations
from valterm.core.files.programs import parse_program, write_program
from valterm.core.files.setup import parse_setup
from valterm.core.files.variables import parse_variables
from valterm.core.numbers import (
    MAX_MAGNITUDE,
    MAX_NUMBER_CHARS,
    NumberError,
    finite,
    parse_count,
    parse_number,
)
from valterm.core.workspace import (
    Workspace,
    WorkspaceError,
    bundled_workspace_files,
    check_name,
)

links = pytest.mark.skipif(not hasattr(os, "symlink"), reason="no symbolic links")


def _bundled(name: str) -> bytes:
    return dict(bundled_workspace_files())[name].read_bytes()


# -- the one write path ---------------------------------------------------------------

def test_atomic_write_replaces_whole_and_leaves_no_temporary(tmp_path: Path) -> None:
    target = tmp_path / "X.LOC"
    write_text_atomic(target, "old\n")
    target.chmod(0o640)
    write_text_atomic(target, "new\n")
    assert target.read_text() == "new\n"
    assert (target.stat().st_mode & 0o777) == 0o640  # a rewritten file keeps its permissions
    assert sorted(p.name for p in tmp_path.iterdir()) == ["X.LOC"]


@links
def test_atomic_write_refuses_a_link_dangling_or_not(tmp_path: Path) -> None:
    outside = tmp_path / "outside"
    outside.mkdir()
    folder = tmp_path / "ws"
    folder.mkdir()
    (folder / "LIVE.SET").symlink_to(outside / "secret")
    (outside / "secret").write_text("keep\n")
    (folder / "DEAD.SET").symlink_to(outside / "nowhere")
    for name in ("LIVE.SET", "DEAD.SET"):
        with pytest.raises(FileWriteError, match=f"{name}: is a symbolic link"):
            write_text_atomic(folder / name, "evil\n")
    assert (outside / "secret").read_text() == "keep\n"
    assert not (outside / "nowhere").exists()
    assert sorted(p.name for p in outside.iterdir()) == ["secret"]
    assert not [p for p in folder.iterdir() if is_temporary(p.name)]


def test_atomic_write_refuses_a_folder_and_reports_a_failing_disk(tmp_path: Path) -> None:
    (tmp_path / "D.SET").mkdir()
    with pytest.raises(FileWriteError, match="D.SET: is a folder"):
        write_text_atomic(tmp_path / "D.SET", "x")
    with pytest.raises(FileWriteError, match="X.SET: cannot write the file") as caught:
        write_text_atomic(tmp_path / "missing" / "X.SET", "x")
    assert isinstance(caught.value, OSError) and isinstance(caught.value, ValtermError)


def test_temporaries_have_random_names_and_are_recognised(tmp_path: Path) -> None:
    assert is_temporary(".PROCESS.LOC.0123456789abcdef.tmp")
    assert is_temporary(".CONV.SET.k3j_x9q2.tmp")  # tempfile.mkstemp's, from older versions
    assert not is_temporary("PROCESS.LOC")
    assert not is_temporary("PROCESS.OBJ.tmp")  # the old fixed name: not ours to remove
    assert not is_temporary(".PROCESS.LOC.tmp")


@links
def test_stale_temporaries_are_removed_when_the_workspace_opens(tmp_path: Path) -> None:
    workspace = Workspace.open(tmp_path / "ws")
    outside = tmp_path / "outside.txt"
    outside.write_text("keep\n")
    stale = [".PROCESS.LOC.0123456789abcdef.tmp", ".CONV.SET.abcdefgh.tmp"]
    for name in stale:
        (workspace.root / name).write_text("half a fi")
    (workspace.root / ".X.SET.aaaaaaaaaaaaaaaa.tmp").symlink_to(outside)
    (workspace.root / ".KEEP.SET.tmp").write_text("not a temporary of ours\n")
    Workspace.open(workspace.root)
    left = sorted(p.name for p in workspace.root.iterdir() if p.name.startswith("."))
    assert left == [".KEEP.SET.tmp"]
    assert outside.read_text() == "keep\n"


def test_a_temporary_being_written_is_not_removed(tmp_path: Path) -> None:
    fcntl = pytest.importorskip("fcntl")
    busy = tmp_path / ".A.SET.0123456789abcdef.tmp"
    with open(busy, "wb") as handle:
        fcntl.flock(handle.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        assert remove_stale_temporaries(tmp_path) == []
        assert busy.exists()
    assert remove_stale_temporaries(tmp_path) == [busy.name]


@links
def test_workspace_saves_never_write_through_links(tmp_path: Path) -> None:
    workspace = Workspace.open(tmp_path / "ws")
    inside_target = workspace.root / "REAL.LOC"
    inside_target.write_text("; NO LOCATIONS\n")
    (workspace.root / "ALIAS.LOC").symlink_to(inside_target)  # a link inside the workspace
    with pytest.raises(FileWriteError, match="ALIAS.LOC: is a symbolic link"):
        workspace.write_locations("ALIAS", {})
    outside = tmp_path / "outside.DAT"
    outside.write_text("    TYPE OUTSIDE\n")
    (workspace.root / "EVIL.DAT").symlink_to(outside)
    with pytest.raises(WorkspaceError, match="EVIL.DAT links outside the workspace"):
        workspace.write_program(Program("EVIL", [ProgramLine(None, "TYPE X")]))
    assert outside.read_text() == "    TYPE OUTSIDE\n"


# -- hardcopy and export ---------------------------------------------------------------------

@links
def test_hardcopy_names_skip_dangling_links(tmp_path: Path) -> None:
    from valterm.ui.hardcopy import next_name

    (tmp_path / "HCOPY1.SVG").symlink_to(tmp_path / "outside.svg")
    assert next_name(tmp_path) == "HCOPY2"
    assert not (tmp_path / "outside.svg").exists()


@links
def test_export_uses_no_fixed_temporary_and_refuses_a_link(tmp_path: Path) -> None:
    pytest.importorskip("trimesh")
    from valterm.core.cad.export import export_scene

    cell = Workspace.open(tmp_path / "ws").read_setup("CONV")
    outside = tmp_path / "outside.obj"
    outside.write_text("keep\n")
    planted = tmp_path / "ws" / "CONV.OBJ.tmp"
    planted.symlink_to(outside)
    written = export_scene(cell, [], tmp_path / "ws" / "CONV.OBJ")
    assert written.is_file() and not written.is_symlink()
    assert planted.is_symlink() and outside.read_text() == "keep\n"
    (tmp_path / "ws" / "CONV.GLB").symlink_to(outside)
    with pytest.raises(FileWriteError, match="CONV.GLB: is a symbolic link"):
        export_scene(cell, [], tmp_path / "ws" / "CONV.GLB")
    assert outside.read_text() == "keep\n"


# -- seeding ---------------------------------------------------------------------------------

def test_first_use_restores_empty_and_truncated_bundled_files(tmp_path: Path) -> None:
    root = tmp_path / "ws"
    root.mkdir()
    conv = _bundled("CONV.SET")
    (root / "CONV.SET").write_bytes(b"")                     # killed right after creating it
    (root / "PROCESS.SET").write_bytes(_bundled("PROCESS.SET")[:100])  # killed mid-copy
    user = b"1\nMM\nW\n" + b"x" * 10                            # not a prefix: the user's
    (root / "DEMO3.SET").write_bytes(user)
    Workspace.open(root)
    assert (root / "CONV.SET").read_bytes() == conv
    assert (root / "PROCESS.SET").read_bytes() == _bundled("PROCESS.SET")
    assert (root / "DEMO3.SET").read_bytes() == user


def test_after_first_use_only_an_empty_bundled_file_is_restored(tmp_path: Path) -> None:
    workspace = Workspace.open(tmp_path / "ws")
    shorter = _bundled("PROCESS.DAT").splitlines(keepends=True)[:-1]  # the user deleted the last step
    (workspace.root / "PROCESS.DAT").write_bytes(b"".join(shorter))
    (workspace.root / "CONV.LOC").write_bytes(b"")
    (workspace.root / "CONV1.DAT").unlink()  # deleted by the user: stays deleted
    Workspace.open(workspace.root)
    assert (workspace.root / "PROCESS.DAT").read_bytes() == b"".join(shorter)
    assert (workspace.root / "CONV.LOC").read_bytes() == _bundled("CONV.LOC")
    assert not (workspace.root / "CONV1.DAT").exists()


@links
def test_seeding_never_follows_a_planted_link(tmp_path: Path) -> None:
    root = tmp_path / "ws"
    root.mkdir()
    outside = tmp_path / "outside"
    (root / "CONV.SET").symlink_to(outside)  # dangling: seeding must not create `outside`
    Workspace.open(root)
    assert not outside.exists()
    assert (root / "CONV.SET").is_symlink()
    assert (root / "PROCESS.SET").read_bytes() == _bundled("PROCESS.SET")


# -- the one read path -------------------------------------------------------------------------

@pytest.fixture
def caller_workspace(tmp_path: Path) -> Path:
    if not hasattr(os, "symlink"):
        pytest.skip("no symbolic links")
    root = tmp_path / "ws"
    Workspace.open(root)
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "EVIL3.DAT").write_text("    TYPE SECRET OUTSIDE\n")
    (root / "CALLER.DAT").write_text("    CALL EVIL3\n")
    (root / "EVIL3.DAT").symlink_to(outside / "EVIL3.DAT")
    return root


def test_run_refuses_a_called_program_linked_outside(caller_workspace: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--workspace", str(caller_workspace), "run", "CALLER"]) == 1
    out = capsys.readouterr().out
    assert "SECRET" not in out
    assert "CALLER STEP 1: CALL EVIL3: EVIL3.DAT LINKS OUTSIDE THE WORKSPACE" in out


def test_run_by_path_refuses_a_called_program_linked_outside(caller_workspace: Path,
                                                              capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--workspace", str(caller_workspace), "run", str(caller_workspace / "CALLER.DAT")]) == 1
    assert "SECRET" not in capsys.readouterr().out


def test_check_refuses_a_called_program_linked_outside(caller_workspace: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--workspace", str(caller_workspace), "check", "CALLER"]) == 1
    assert "CALLER.DAT: EVIL3.DAT links outside the workspace" in capsys.readouterr().err
    assert main(["--workspace", str(caller_workspace), "check", str(caller_workspace / "CALLER.DAT")]) == 1
    assert "EVIL3.DAT links outside" in capsys.readouterr().err


def test_called_programs_inside_still_run(caller_workspace: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (caller_workspace / "EVIL3.DAT").unlink()
    (caller_workspace / "EVIL3.DAT").write_text("    TYPE INSIDE\n")
    assert main(["--workspace", str(caller_workspace), "run", "CALLER"]) == 0
    assert "INSIDE" in capsys.readouterr().out


@links
@links
def test_vplus_files_are_read_only_inside_the_workspace(tmp_path: Path) -> None:
    workspace = Workspace.open(tmp_path / "ws")
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "EVIL.V2").write_text('.PROGRAM evil.one()\n    TYPE "OUT"\n.END\n')
    (workspace.root / "EVIL.V2").symlink_to(outside / "EVIL.V2")
    (workspace.root / "GOOD.V2").write_text('.PROGRAM good.one()\n    TYPE "IN"\n.END\n'
                                            '.PROGRAM main()\n    CALL good.one()\n.END\n')
    (workspace.root / "my_prog.v2").write_text(".PROGRAM odd.one()\n.END\n")  # not a workspace name
    (workspace.root / "BAD.PG").write_text(".PROGRAM broken()\n")  # no .END
    assert list(workspace.vplus_programs()) == ["GOOD.ONE", "MAIN"]
    assert workspace.list_programs()[-2:] == ["GOOD.ONE", "MAIN"]
    with pytest.raises(WorkspaceError, match="links outside"):
        workspace.path("EVIL", "V2")
    for read in (workspace.read_program, workspace.program_loader()):
        assert read("good.one").dialect == "v+" and read("MAIN").steps[0].text == "CALL good.one()"
        with pytest.raises(WorkspaceError, match="BAD.PG CANNOT BE READ"):
            read("evil.one")  # the linked file is never opened; the damaged one says why
        with pytest.raises(WorkspaceError, match="not a valid name"):
            read("../outside/evil.one")
    exists = workspace.program_test()
    assert exists("GOOD.ONE") and exists("MAIN") and not exists("EVIL.ONE") and not exists("ODD.ONE")
    # NAME.DAT wins over a V+ program of the same name
    (workspace.root / "MAIN.DAT").write_text("    TYPE DAT\n")
    assert workspace.read_program("MAIN").dialect == "1985"


def test_editor_journal_linked_outside_is_refused(tmp_path: Path) -> None:
    from valterm.core.editor import ProgramEditor

    workspace = Workspace.open(tmp_path / "ws")
    outside = tmp_path / "journal"
    outside.write_text("secret\n")
    (workspace.root / "NEW.~DAT").symlink_to(outside)
    with pytest.raises(WorkspaceError, match="links outside the workspace"):
        ProgramEditor(workspace, "NEW")
    assert outside.read_text() == "secret\n"


# -- names in messages -----------------------------------------------------------------------

def test_a_long_name_is_cut_in_messages(tmp_path: Path) -> None:
    name = "A" * 10_000
    with pytest.raises(WorkspaceError) as caught:
        check_name(name, "DAT")
    assert len(str(caught.value)) < 200 and "AAAA..." in str(caught.value)
    assert shown_name("B" * 41) == "B" * 40 + "..."
    for bad in ("../X", "/abs", "CON", "~root", "A B", "X\x00Y"):
        with pytest.raises(WorkspaceError):
            check_name(bad, "DAT")


# -- numbers ----------------------------------------------------------------------------------

@pytest.mark.parametrize("text, value", [("465.", 465.0), ("-.27", -0.27), ("1.5D+02", 150.0),
                                         ("+1e3", 1000.0), ("-0", 0.0)])
def test_numbers_as_written(text: str, value: float) -> None:
    assert parse_number(text) == value


@pytest.mark.parametrize("text", ["nan", "inf", "-Infinity", "1e400", "1e16", "0x10", "1_000", "١٢",
                                  "", "1" * (MAX_NUMBER_CHARS + 1), "1.2.3", "--1"])
def test_numbers_refused(text: str) -> None:
    with pytest.raises(NumberError):
        parse_number(text)


def test_counts_and_computed_values() -> None:
    assert parse_count("007", 100) == 7
    for bad in ("9" * 5000, "101", "-1", "²", "1.0"):
        with pytest.raises(NumberError):
            parse_count(bad, 100)
    assert finite(MAX_MAGNITUDE) == MAX_MAGNITUDE
    with pytest.raises(NumberError, match="not a finite number"):
        finite(float("nan"))


# -- limits, each with a located message ---------------------------------------------------------

def _setup(count: str, n: int = 8) -> str:
    return f"{count}\nMM\nW\n1,{n}\n0 0 0\n" + "".join(f"{i} {i % 3} {i % 5}\n" for i in range(n))


@pytest.mark.parametrize("text, line, reason", [
    (_setup("9" * 200), 1, "too large"),
    (_setup("9" * 5000), 1, "5000 characters long"),
    (_setup(str(MAX_PARTS + 1)), 1, f"at most {MAX_PARTS}"),
    (_setup("1", MAX_VERTICES + 2), 4, f"at most {MAX_VERTICES}"),
    (_setup("²"), 1, "whole number"),
    ("1\nMM\nW\n1,8\n0 0 " + "1" * 300 + "\n", 5, f"at most {MAX_LINE}"),
    ("1\nMM\nW\n1,8\n0 0 1e300\n", 5, "out of range"),
], ids=["count-digits", "count-line", "parts", "vertices", "unicode-digit", "long-line", "huge-number"])
def test_setup_limits(text: str, line: int, reason: str) -> None:
    with pytest.raises(FileFormatError) as caught:
        parse_setup(text, "X.SET")
    assert (caught.value.line, reason in caught.value.reason) == (line, True), str(caught.value)


def test_program_limits(tmp_path: Path) -> None:
    with pytest.raises(FileFormatError, match=f"X.DAT:{MAX_STEPS + 1}: more than {MAX_STEPS} steps"):
        parse_program("    TYPE A\n" * (MAX_STEPS + 1), "X")
    with pytest.raises(FileFormatError, match="X.DAT:1: step label 9999999999"):
        parse_program("9999999999999 TYPE A\n", "X")
    big = Program("BIG", [ProgramLine(None, "TYPE A")] * (MAX_STEPS + 1))
    with pytest.raises(FileWriteError, match="too many"):
        write_program(tmp_path / "BIG.DAT", big)
    assert not (tmp_path / "BIG.DAT").exists()


def test_location_and_variable_numbers() -> None:
    with pytest.raises(FileFormatError, match="X.LOC:2: POINT B X: 1e999 is out of range"):
        parse_locations("POINT A, 1, 2, 3, 4, 5, 6\nPOINT B, 1e999, 2, 3, 4, 5, 6\n", "X.LOC")
    assert parse_variables("BIG=1e300\n") == {"BIG": 1e300}  # what a program computed reads back
    with pytest.raises(FileFormatError, match="CHECK.DAT:1: X: 'nan' is not a number"):
        parse_variables("X=nan\n")


def test_a_file_over_the_size_limit_is_refused_whole(tmp_path: Path) -> None:
    path = tmp_path / "HUGE.DAT"
    with open(path, "wb") as handle:
        handle.truncate(6 * 1024 * 1024)
    with pytest.raises(FileFormatError, match="HUGE.DAT: 6.0 MB is too large"):
        read_program(path)


def test_the_bundled_files_are_within_the_limits() -> None:
    for name, source in bundled_workspace_files():
        if name.endswith(".SET"):
            assert read_setup(source).objects
    assert resources.bundled_files(resources.CELLS)


def test_the_deepest_call_is_refused_with_a_message(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    Workspace.open(tmp_path)
    (tmp_path / "PING.DAT").write_text("    CALL PONG\n")
    (tmp_path / "PONG.DAT").write_text("    CALL PING\n")
    assert main(["--workspace", str(tmp_path), "run", "PING"]) == 1
    assert "CALL PONG: MORE THAN 20 NESTED CALLS" in capsys.readouterr().out


@links
def test_hardcopy_key_never_writes_through_a_dangling_link(tmp_path: Path) -> None:
    from app_helpers import make_app, sync

    root = tmp_path / "ws"
    outside = tmp_path / "outside.svg"
    Workspace.open(root)
    (root / "HCOPY1.SVG").symlink_to(outside)

    @sync
    async def press_h() -> None:
        app = make_app(root)
        async with app.run_test(size=(80, 24)) as pilot:
            await pilot.press("H")
            await pilot.pause()

    press_h()
    assert not outside.exists()
    assert (root / "HCOPY1.SVG").is_symlink()
    written = root / "HCOPY2.SVG"
    assert written.is_file() and not written.is_symlink()
    assert written.read_text().lstrip().startswith("<svg")


@pytest.mark.parametrize("argv", [["cell", "show", "A" * 10_000], ["run", "A" * 10_000], ["check", "A" * 10_000],
                                  ["import", "A" * 10_000, "--out", "X"], ["run", "PROCESS", "--loc", "A" * 10_000]],
                         ids=["cell", "run", "check", "import", "loc"])
def test_a_long_argument_gives_a_short_message(tmp_path: Path, argv: list[str],
                                               capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--workspace", str(tmp_path), *argv]) == 1
    err = capsys.readouterr().err
    assert "A" * 40 + "..." in err and len(err) < 300, err[:300]


def test_a_long_workspace_name_gives_a_short_message(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--workspace", str(tmp_path / ("W" * 10_000)), "check", "PROCESS"]) == 1
    err = capsys.readouterr().err
    assert "cannot create the workspace" in err and len(err) < 300, err[:300]
