"""Two sessions on one workspace (issue 24): a save that would lose the other session's save
asks instead (FileChanged); CHECK.DAT merges per variable under the folder's lock; the
monitor writes CHECK.DAT once per batch of lines."""

from __future__ import annotations

import io
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from valterm.core.editor import EditorError, ProgramEditor
from valterm.core.files.atomic import LOCK_NAME, file_stamp, write_text_atomic
from valterm.core.files.errors import FileChanged
from valterm.core.files.programs import read_program
from valterm.core.files.setup import read_setup
from valterm.core.monitor import LineMonitor
from valterm.core.session import Session
from valterm.core.workspace import Workspace


@pytest.fixture
def root(tmp_path: Path) -> Path:
    Workspace.open(tmp_path / "ws")
    return tmp_path / "ws"


def texts(program) -> list[str]:  # type: ignore[no-untyped-def]
    return [step.text for step in program.steps]


# -- programs: the two-session EDIT sequence ---------------------------------------------------
def test_second_save_of_a_program_is_refused_not_lost(root: Path) -> None:
    a = ProgramEditor(Workspace(root), "CONV2")
    b = ProgramEditor(Workspace(root), "CONV2")
    original = texts(a.program)
    a.insert(1, " TYPE A")
    b.insert(1, " TYPE B")
    a.save()
    before = (root / "CONV2.DAT").read_bytes()
    with pytest.raises(FileChanged, match=r"CONV2\.DAT: changed on disk since this session read it"):
        b.save()
    assert (root / "CONV2.DAT").read_bytes() == before  # nothing written: A's step is there
    assert texts(read_program(root / "CONV2.DAT")) == ["TYPE A", *original]
    assert b.dirty  # B's change is still in B's editor, to overwrite, reload or save as


def test_overwrite_reload_and_save_as_answers(root: Path) -> None:
    a = ProgramEditor(Workspace(root), "CONV2")
    b = ProgramEditor(Workspace(root), "CONV2")
    original = texts(a.program)
    a.insert(1, " TYPE A")
    a.save()
    b.insert(1, " TYPE B")
    # save as: B's program goes to a new file, A's stays
    with pytest.raises(EditorError, match="CONV1.DAT EXISTS"):
        b.save_as("CONV1")
    path = b.save_as("CONV2B")
    assert path.name == "CONV2B.DAT" and b.name == "CONV2B"
    assert texts(read_program(path)) == ["TYPE B", *original]
    assert texts(read_program(root / "CONV2.DAT")) == ["TYPE A", *original]
    assert "CONV2B" in Workspace(root).programs_directory()
    # reload: take the other session's program
    c = ProgramEditor(Workspace(root), "CONV2")
    a.insert(1, " TYPE A2")
    a.save()
    c.insert(1, " TYPE C")
    with pytest.raises(FileChanged):
        c.save()
    c.reload()
    assert texts(c.program) == ["TYPE A2", "TYPE A", *original] and not c.dirty
    # overwrite: the user chose to replace the other session's save
    c.insert(1, " TYPE C")
    a.insert(1, " TYPE A3")
    a.save()
    with pytest.raises(FileChanged):
        c.save()
    c.save(overwrite=True)
    assert texts(read_program(root / "CONV2.DAT")) == ["TYPE C", "TYPE A2", "TYPE A", *original]
    # and a session's own saves in a row never ask
    c.insert(1, " TYPE C2")
    c.save()
    c.delete(1)
    c.save()


def test_a_program_made_by_another_session_meanwhile_is_a_change(root: Path) -> None:
    a = ProgramEditor(Workspace(root), "NEW1")
    b = ProgramEditor(Workspace(root), "NEW1")
    a.append(" TYPE A")
    b.append(" TYPE B")
    a.save()
    with pytest.raises(FileChanged):
        b.save()
    with pytest.raises(FileChanged):
        b.wrong_key("Q")  # a wrong key saves (§5.2): it asks too


def test_the_journal_is_the_first_editors_alone(root: Path) -> None:
    a = ProgramEditor(Workspace(root), "CONV2")
    a.insert(1, " TYPE A")  # unsaved, in A's journal
    b = ProgramEditor(Workspace(root), "CONV2")
    assert not b.recovered and "TYPE A" not in texts(b.program)  # A's unsaved step is A's
    assert any("OPEN IN ANOTHER SESSION" in m for m in b.messages)
    b.insert(1, " TYPE B")
    b.save()  # B's save neither removes nor rewrites A's journal
    assert a.journal_path.is_file() and "TYPE A" in a.journal_path.read_text()
    assert "TYPE B" not in a.journal_path.read_text()
    a.close()  # A's app ends mid-edit: the next open recovers A's step
    c = ProgramEditor(Workspace(root), "CONV2")
    assert c.recovered and texts(c.program)[0] == "TYPE A"
    with pytest.raises(FileChanged):  # A's changes were made before B's save: it asks
        c.save()


def test_a_checked_save_waits_for_the_folder_lock_file(root: Path) -> None:
    target = root / "X.DAT"
    write_text_atomic(target, "one\n", expected="")
    assert (root / LOCK_NAME).is_file()
    stamp = file_stamp(target)
    with pytest.raises(FileChanged):
        write_text_atomic(target, "two\n", expected="")  # it exists now
    write_text_atomic(target, "two\n", expected=stamp)
    assert target.read_text() == "two\n"
    assert "X" not in Workspace(root).list_setups() + Workspace(root).list_locations()
    assert LOCK_NAME not in [p.upper() for p in Workspace(root).list_programs()]


# -- setups: the two-session MANIPULATION sequence ------------------------------------------------
def test_second_save_of_a_setup_is_refused_not_lost(root: Path) -> None:
    a = Session(root, setup="CONV")
    b = Session(root, setup="CONV")
    a.simulator.cell.objects[0] = a.simulator.cell.objects[0].translated(np.array([10.0, 0, 0]))
    b.simulator.cell.objects[1] = b.simulator.cell.objects[1].translated(np.array([0, 20.0, 0]))
    a.save_setup()
    saved = (root / "CONV.SET").read_bytes()
    with pytest.raises(FileChanged, match=r"CONV\.SET"):
        b.save_setup()
    assert (root / "CONV.SET").read_bytes() == saved
    moved = read_setup(root / "CONV.SET").objects[0].vertices
    assert np.allclose(moved, a.simulator.cell.objects[0].vertices, atol=0.01)
    # save as a new name keeps both; overwrite replaces; reload takes A's
    b.save_setup("CONVB")
    assert (root / "CONVB.SET").is_file() and (root / "CONV.SET").read_bytes() == saved
    c = Session(root, setup="CONV")
    a.save_setup()  # A's own second save: no question
    c.simulator.cell.objects[0] = c.simulator.cell.objects[0].translated(np.array([0, 0, 5.0]))
    a.simulator.cell.objects[0] = a.simulator.cell.objects[0].translated(np.array([1.0, 0, 0]))
    a.save_setup()
    with pytest.raises(FileChanged):
        c.save_setup()
    c.save_setup(overwrite=True)
    c.save_setup()


# -- CHECK.DAT -----------------------------------------------------------------------------------
def test_variables_merge_per_variable(root: Path) -> None:
    a, b = Workspace(root), Workspace(root)
    a.write_variables({"ROW": 1.0})
    a.read_variables(), b.read_variables()
    assert a.merge_variables({"ROW": 1.0, "A": 5.0}) == {"ROW": 1.0, "A": 5.0}
    # B never saw A: it keeps A's variable and changes only what it changed
    assert b.merge_variables({"ROW": 2.0, "B": 7.0}) == {"ROW": 2.0, "A": 5.0, "B": 7.0}
    # A's unchanged ROW=1 does not undo B's ROW=2
    assert a.merge_variables({"ROW": 1.0, "A": 6.0}) == {"ROW": 2.0, "A": 6.0, "B": 7.0}
    assert Workspace(root).read_variables() == {"ROW": 2.0, "A": 6.0, "B": 7.0}


def test_a_session_learns_the_other_sessions_variables(root: Path) -> None:
    one, two = Session(root, setup=None), Session(root, setup=None)
    list(one.command("ROW=1"))
    list(two.command("COL=2"))
    list(one.command("ROW=5"))  # its write merges: COL=2 comes back with it
    assert one.interpreter.variables["COL"] == 2.0
    list(one.command("ROW=ROW+COL"))
    list(two.command("COL=COL+1"))  # two's ROW=1 is older than one's ROW=7: not written back
    assert Workspace(root).read_variables() == {"ROW": 7.0, "COL": 3.0}


def _count_writes(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    from valterm.core.files import variables

    writes: list[int] = []
    real = variables.write_variables

    def counted(path, values):  # type: ignore[no-untyped-def]
        writes.append(len(values))
        real(path, values)

    monkeypatch.setattr(variables, "write_variables", counted)
    return writes


def test_monitor_writes_check_dat_once_per_batch(root: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    writes = _count_writes(monkeypatch)
    out: list[str] = []
    monitor = LineMonitor(Session(root, setup=None), out.append)
    for i in range(200):
        monitor.line(f"V{i}={i}")
    assert writes == []
    monitor.keep()  # the end of the batch (the input waits)
    assert writes == [200]
    monitor.keep()  # nothing changed since: no write
    monitor.line("V1=100")
    assert monitor.end() == 0
    assert writes == [200, 200]
    assert Workspace(root).read_variables()["V1"] == 100.0


def test_valterm_monitor_keeps_piped_assignments_in_one_write(root: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import argparse

    from valterm.commands.monitor import run

    writes = _count_writes(monkeypatch)
    stdin = io.StringIO("".join(f"ROW=ROW+{i}\n" for i in range(500)) + "TYPE ROW\n")
    list(Session(root, setup=None).command("ROW=0"))
    writes.clear()
    out = io.StringIO()
    assert run(argparse.Namespace(workspace=str(root), loc=None), stdin=stdin, stdout=out) == 0
    assert writes == [1]
    assert Workspace(root).read_variables() == {"ROW": float(sum(range(500)))}


# long enough (a few tenths of a second) that both runs read CHECK.DAT before either writes it
RUN_PROGRAM = """\
   {name}=0
{label} {name}={name}+1
   IF {name} LT 30000 GOTO {label}
"""


def test_two_concurrent_runs_keep_every_variable(root: Path, tmp_path: Path) -> None:
    procs = []
    env = {**os.environ, "VALTERM_WORKSPACE": str(root)}
    for k in range(2):
        names = [f"R{k}V{j}" for j in range(3)]
        program = "".join(RUN_PROGRAM.format(name=n, label=10 + j) for j, n in enumerate(names))
        path = tmp_path / f"RUN{k}.DAT"
        path.write_text(program)
        procs.append(subprocess.Popen([sys.executable, "-m", "valterm", "run", str(path), "--max-lines", "0"], env=env,
                                      stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True))
    for proc in procs:
        out, err = proc.communicate(timeout=120)
        assert proc.returncode == 0, err
    kept = Workspace(root).read_variables()
    assert kept == {f"R{k}V{j}": 30000.0 for k in range(2) for j in range(3)}


def test_import_into_a_setup_another_session_saved_meanwhile_is_refused(
        root: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    import trimesh

    import valterm.core.cad.convert as cad  # `valterm import` loads it when run (issue 25: start)
    from valterm.cli import main as cli

    part = tmp_path / "part.stl"
    trimesh.creation.box(extents=(30, 30, 30)).export(part)
    real = cad.import_cad

    def other_session_saves_first(*args, **kwargs):  # type: ignore[no-untyped-def]
        other = Session(root, setup="CONV")
        other.simulator.cell.objects[0] = other.simulator.cell.objects[0].translated(np.array([0, 0, 7.0]))
        other.save_setup()
        return real(*args, **kwargs)

    original = read_setup(root / "CONV.SET")
    monkeypatch.setattr(cad, "import_cad", other_session_saves_first)
    assert cli(["--workspace", str(root), "import", str(part), "--into", "CONV"]) == 1
    assert "CONV.SET: changed on disk since this session read it" in capsys.readouterr().err
    kept = read_setup(root / "CONV.SET")  # the other session's save, not overwritten
    assert len(kept.objects) == len(original.objects)
    assert np.allclose(kept.objects[0].vertices, original.objects[0].vertices + [0, 0, 7.0], atol=0.01)
    monkeypatch.setattr(cad, "import_cad", real)
    before = len(read_setup(root / "CONV.SET").objects)
    assert cli(["--workspace", str(root), "import", str(part), "--into", "CONV"]) == 0
    assert len(read_setup(root / "CONV.SET").objects) == before + 1


def test_datfiler_additions_and_removals_keep_the_other_sessions_names(root: Path) -> None:
    from valterm.core.files.datfiler import add_program_name, read_datfiler, remove_program_name

    path = root / "DATFILER.DAT"
    before = read_datfiler(path)
    assert add_program_name(path, "NEWA") and add_program_name(path, "NEWB")
    assert remove_program_name(path, "NEWA") and not remove_program_name(path, "NEWA")
    assert read_datfiler(path) == [*before, "NEWB"]
