"""The line editor of Chapter 5 (valterm.core.editor), without the UI."""

from __future__ import annotations

from pathlib import Path

import pytest

from valterm.core.editor import EditorError, ProgramEditor, expand_tab, program_name
from valterm.core.files.programs import read_program
from valterm.core.workspace import Workspace


@pytest.fixture
def workspace(tmp_path: Path) -> Workspace:
    return Workspace.open(tmp_path / "ws")


def texts(editor: ProgramEditor) -> list[str]:
    return [step.text for step in editor.steps]


def test_new_program_is_reported_and_listed_in_datfiler(workspace: Workspace) -> None:
    assert "TEST" not in workspace.programs_directory()
    editor = ProgramEditor(workspace, "EDIT TEST.DAT")
    assert editor.new and editor.name == "TEST"
    assert "INPUT FILE TEST.DAT DOES NOT EXIST" in editor.messages
    assert "TEST" in workspace.programs_directory()  # §5.1: DATFILER.DAT updated at once
    assert editor.prompt() == "S. 1>"


def test_existing_program_opens_with_its_steps(workspace: Workspace) -> None:
    editor = ProgramEditor(workspace, "PROCESS")
    assert not editor.new and not editor.messages
    assert editor.steps[2].text == "READY"
    assert editor.listing()[2] == "   3.     READY"


def test_create_insert_delete_renumber_and_save(workspace: Workspace) -> None:
    editor = ProgramEditor(workspace, "TEST")
    for line in (" MOVE A", " MOVE B", " CLOSEI 50", " STOP"):
        editor.append(line)
    assert texts(editor) == ["MOVE A", "MOVE B", "CLOSEI 50", "STOP"]
    assert editor.prompt() == "S. 5>"
    assert editor.delete(3).text == "CLOSEI 50"  # Table C-2: D,3
    assert texts(editor) == ["MOVE A", "MOVE B", "STOP"]
    editor.insert(3, " MOVE E")  # I,3: the new step 3, STOP moves to 4
    assert texts(editor) == ["MOVE A", "MOVE B", "MOVE E", "STOP"]
    editor.insert(1, "10\tREADY")  # a label in columns 1-4, TAB to column 5
    assert editor.steps[0].label == 10 and editor.steps[0].text == "READY"
    assert editor.listing()[0] == "   1. 10  READY"
    path = editor.save()
    assert path.name == "TEST.DAT" and not editor.dirty
    saved = read_program(path)
    assert [s.text for s in saved.steps] == ["READY", "MOVE A", "MOVE B", "MOVE E", "STOP"]
    assert path.read_text().splitlines()[0] == "10  READY"
    assert not editor.journal_path.exists()


def test_bad_lines_are_rejected_with_a_message(workspace: Workspace) -> None:
    editor = ProgramEditor(workspace, "TEST")
    with pytest.raises(EditorError) as error:
        editor.append(" FLY TO THE MOON")
    assert "FLY" in str(error.value)
    with pytest.raises(EditorError):
        editor.append(" APPRO A")  # APPRO needs a distance
    with pytest.raises(EditorError):
        editor.append("")
    editor.append("100 TYPE DONE")
    with pytest.raises(EditorError, match="100"):
        editor.append("100 STOP")  # a label names one step
    with pytest.raises(EditorError, match="NO STEP"):
        editor.delete(5)
    with pytest.raises(EditorError, match="NO STEP"):
        editor.insert(9, " STOP")
    assert texts(editor) == ["TYPE DONE"]
    editor.append("; A COMMENT IS A STEP")
    assert len(editor.steps) == 2


def test_wrong_key_says_so_and_saves(workspace: Workspace) -> None:
    editor = ProgramEditor(workspace, "TEST")
    editor.append(" MOVE A")
    assert not editor.path.exists()
    message = editor.wrong_key("Q")
    assert "'Q' IS NOT AN EDITOR COMMAND" in message and "TEST.DAT SAVED" in message
    assert [s.text for s in read_program(editor.path).steps] == ["MOVE A"]
    assert "UNCHANGED" in editor.wrong_key("Z")


def test_journal_recovers_unsaved_edits(workspace: Workspace) -> None:
    editor = ProgramEditor(workspace, "TEST")
    editor.append(" MOVE A")
    editor.append(" MOVE B")
    assert editor.journal_path.exists()
    assert editor.journal_path.name == "TEST.~DAT"
    del editor  # the app is closed mid-edit: nothing saved
    again = ProgramEditor(workspace, "TEST")
    assert again.recovered and again.dirty
    assert texts(again) == ["MOVE A", "MOVE B"]
    assert any("RECOVERED" in m for m in again.messages)
    again.save()
    third = ProgramEditor(workspace, "TEST")
    assert not third.recovered and texts(third) == ["MOVE A", "MOVE B"]
    assert "TEST.~DAT" not in [p.name for p in workspace.root.iterdir()]
    assert "TEST" in workspace.list_programs()


def test_discard_drops_the_journal_and_keeps_the_file(workspace: Workspace) -> None:
    editor = ProgramEditor(workspace, "PROCESS")
    before = editor.path.read_text()
    editor.delete(1)
    editor.discard()
    assert editor.path.read_text() == before
    assert not ProgramEditor(workspace, "PROCESS").recovered


def test_names_and_tabs() -> None:
    assert program_name("EDIT test.dat") == "TEST"
    assert program_name("conv1") == "CONV1"
    assert expand_tab("\tMOVE A") == "    MOVE A"
    assert expand_tab("20\tSTOP") == "20  STOP"
    with pytest.raises(EditorError):
        program_name("EDIT ")


def test_bad_names_are_refused(workspace: Workspace) -> None:
    from valterm.core.workspace import WorkspaceError

    for bad in ("../ETC", "TOOLONGNAME", "DATFILER"):
        with pytest.raises(WorkspaceError):
            ProgramEditor(workspace, bad)


def test_a_saved_program_runs_headless(workspace: Workspace) -> None:
    interpreter_module = pytest.importorskip("valterm.core.val.interpreter", reason="the interpreter helper's valterm.core.val.interpreter")
    from valterm.core.session import Session

    editor = ProgramEditor(workspace, "TEST")
    for line in (" READY", " TYPE HELLO", "10 SPEED 50", " STOP"):
        editor.append(line)
    editor.save()
    session = Session(workspace.root, setup="PROCESS")
    interpreter = session.interpreter
    run = getattr(interpreter, "execute", None) or getattr(interpreter, "run")
    events = list(run("TEST"))
    kinds = [type(e).__name__ for e in events]
    assert "Error" not in kinds, events
    assert any(getattr(e, "text", "") == "HELLO" for e in events)
    assert session.simulator.speed == 50
    del interpreter_module
