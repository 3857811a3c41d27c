"""STOREL and LOAD (issue 35, build items 4 and 5): STOREL never silently replaces a file (one
this session did not store, one another session stored since, or any file with no locations),
writes the thesis's numbers and never a file the reader refuses; LOAD reads locations and
programs back. Sessions share one workspace folder as two users in a classroom would."""

from __future__ import annotations

import io
import random
import re
from pathlib import Path

import numpy as np
import pytest

from valterm.cli import main
from valterm.core.events import Error, Message
from valterm.core.files.limits import MAX_LOCATIONS
from valterm.core.files.locations import read_location_file, read_locations
from valterm.core.kinematics import Location, fk
from valterm.core.session import Session


def said(session: Session, line: str) -> tuple[list[str], list[str]]:
    """The messages and the errors one typed line gives."""
    events = list(session.command(line))
    return ([e.text for e in events if isinstance(e, Message)],
            [e.message for e in events if isinstance(e, Error)])


def teach(session: Session, name: str, jt1: float) -> None:
    list(session.command(f"DRIVE 1,{jt1},100"))
    list(session.command(f"HERE {name}"))


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    Session(tmp_path, setup=None)  # seeded with the thesis's cells and programs (PROCESS.LOC)
    return tmp_path


# -- never silently replaced --------------------------------------------------------------

def test_storel_of_nothing_keeps_the_thesis_file_in_a_fresh_session(folder: Path) -> None:
    before = (folder / "PROCESS.LOC").read_bytes()
    session = Session(folder, setup=None)
    for _ in range(2):  # typed again it is still refused: nothing is no replacement
        messages, [error] = said(session, "STOREL PROCESS")
        assert not messages
        assert "NO LOCATIONS ARE DEFINED" in error and "PROCESS.LOC (6 LOCATIONS) IS KEPT" in error
    assert (folder / "PROCESS.LOC").read_bytes() == before
    _, [error] = said(session, "STOREL EMPTY")
    assert "NOTHING TO STORE" in error and not (folder / "EMPTY.LOC").exists()


def test_storel_over_a_file_it_did_not_write_refuses_then_the_same_storel_replaces_it(folder: Path) -> None:
    before = (folder / "PROCESS.LOC").read_bytes()
    session = Session(folder, setup=None)
    teach(session, "P1", 10)
    messages, [error] = said(session, "STOREL PROCESS")
    assert not messages
    assert error == ("STOREL: PROCESS.LOC (6 LOCATIONS) WAS NOT STORED BY THIS SESSION: NOTHING WRITTEN. "
                     "STOREL PROCESS AGAIN REPLACES IT; STOREL <ANOTHER NAME> KEEPS IT")
    assert (folder / "PROCESS.LOC").read_bytes() == before
    assert session.simulator.unsaved_locations() == ["P1"]  # the quit prompt still asks
    assert said(session, "STOREL PROCESS") == (["1 LOCATION STORED IN PROCESS.LOC"], [])
    assert list(read_locations(folder / "PROCESS.LOC")) == ["P1"]
    teach(session, "P2", 10)  # a file this session stored: replaced without a question
    assert said(session, "STOREL process.loc") == (["2 LOCATIONS STORED IN PROCESS.LOC"], [])
    assert list(read_locations(folder / "PROCESS.LOC")) == ["P1", "P2"]


def test_two_sessions_storing_one_name_the_second_is_told_and_nothing_is_lost(folder: Path) -> None:
    first, second = Session(folder, setup=None), Session(folder, setup=None)
    teach(first, "A1", 10)
    teach(second, "B1", -10)
    assert said(first, "STOREL PICK") == (["1 LOCATION STORED IN PICK.LOC"], [])
    messages, [error] = said(second, "STOREL PICK")
    assert not messages and "PICK.LOC CHANGED ON DISK SINCE THIS SESSION BEGAN (ANOTHER SESSION STORED IT)" in error
    assert "STOREL PICK AGAIN REPLACES IT" in error
    assert list(read_locations(folder / "PICK.LOC")) == ["A1"]  # the first session's set is there
    assert said(second, "STOREL PICK") == (["1 LOCATION STORED IN PICK.LOC"], [])  # told, then asked again
    _, [error] = said(first, "STOREL PICK")  # the first wrote it, but the second stored it since
    assert "PICK.LOC CHANGED ON DISK SINCE THIS SESSION LAST SAW IT" in error
    assert list(read_locations(folder / "PICK.LOC")) == ["B1"]


def test_a_repeat_after_a_refusal_is_refused_again_when_another_session_stored_meanwhile(folder: Path) -> None:
    first, second = Session(folder, setup=None), Session(folder, setup=None)
    teach(first, "A1", 10)
    teach(second, "B1", -10)
    assert "NOT STORED BY THIS SESSION" in said(first, "STOREL PROCESS")[1][0]
    assert "NOT STORED BY THIS SESSION" in said(second, "STOREL PROCESS")[1][0]
    assert said(second, "STOREL PROCESS")[0] == ["1 LOCATION STORED IN PROCESS.LOC"]
    assert "CHANGED ON DISK" in said(first, "STOREL PROCESS")[1][0]  # not the file it was told of
    assert list(read_locations(folder / "PROCESS.LOC")) == ["B1"]


# -- the thesis's numbers, read back to 0.01 mm ---------------------------------------------

def test_storel_writes_two_decimals_and_reads_back_within_a_hundredth_of_a_millimetre(folder: Path) -> None:
    session = Session(folder, setup="PROCESS")
    rng = random.Random(35)
    taught = {}
    for index in range(12):
        for joint, change in enumerate((rng.uniform(-60, 60), rng.uniform(-40, 40), rng.uniform(-40, 40),
                                        rng.uniform(-90, 90), rng.uniform(-60, 60), rng.uniform(-90, 90)), 1):
            list(session.command(f"DRIVE {joint},{change:.6f},100"))
        list(session.command(f"HERE P{index}"))
        taught[f"P{index}"] = session.simulator.location(f"P{index}")
    session.simulator.locations["ODD"] = Location((1 / 3, -2 / 3, 1e-7), (179.999999, -0.5, 12.3456))
    assert said(session, "STOREL ROUND")[0] == ["13 LOCATIONS STORED IN ROUND.LOC"]
    for line in (folder / "ROUND.LOC").read_text().splitlines():
        fields = [f.strip() for f in line.split(",")]
        assert all(re.fullmatch(r"-?\d+\.\d\d", f) for f in fields[1:7]), line  # X Y Z O A T
        assert all(re.fullmatch(r"-?\d+\.\d{2,5}", f) for f in fields[8:]), line  # JT1..JT6
    back = Session(folder, setup=None)
    assert said(back, "LOAD ROUND.LOC")[1] == []
    assert back.simulator.location("ODD").xyz == (0.33, -0.67, 0.0)
    for name, location in taught.items():
        again = back.simulator.location(name)
        assert again.config == location.config and location.config is not None
        assert np.allclose(again.xyz, location.xyz, atol=0.005 + 1e-9)
        assert location.joints is not None and again.joints is not None
        # the pose the stored joints make is where the taught ones put the tool
        assert np.linalg.norm(fk(again.joints).xyz - fk(location.joints).xyz) < 0.01
        for word in location.config.words:  # the 1985 rules move only to a location's own configuration
            list(back.command(word))
        assert said(back, f"MOVE {name}")[1] == []
        assert np.linalg.norm(np.array(back.simulator.where().xyz) - np.array(location.xyz)) < 0.01


def test_storel_refuses_more_locations_than_a_file_holds_and_writes_the_most_it_may(folder: Path) -> None:
    session = Session(folder, setup=None)
    spot = Location((400.0, 0.0, 100.0), (90.0, 90.0, 0.0))
    session.simulator.locations.update({f"L{i}": spot for i in range(MAX_LOCATIONS + 1)})
    messages, [error] = said(session, "STOREL MANY")
    assert not messages and f"{MAX_LOCATIONS + 1} locations are more than one location file holds" in error
    assert not (folder / "MANY.LOC").exists()
    del session.simulator.locations[f"L{MAX_LOCATIONS}"]
    assert said(session, "STOREL MANY")[0] == [f"{MAX_LOCATIONS} LOCATIONS STORED IN MANY.LOC"]
    assert len(read_locations(folder / "MANY.LOC")) == MAX_LOCATIONS  # what --loc reads


def test_precision_points_are_stored_and_loaded(folder: Path) -> None:
    session = Session(folder, setup=None)
    session.interpreter.machine.precision["#SAFE"] = (0.0, -90.0, 90.0, 12.3456789, 0.0, 0.0)
    assert said(session, "STOREL SAFE")[0] == ["1 LOCATION STORED IN SAFE.LOC"]
    assert read_location_file(folder / "SAFE.LOC")[1]["#SAFE"] == (0.0, -90.0, 90.0, 12.34568, 0.0, 0.0)
    back = Session(folder, setup=None)
    assert said(back, "LOAD SAFE")[0] == ["1 LOCATION READ FROM SAFE.LOC: #SAFE"]
    assert back.interpreter.machine.precision["#SAFE"][3] == pytest.approx(12.3456789, abs=1e-5)


# -- LOAD ---------------------------------------------------------------------------------------

def test_load_reads_the_locations_and_checks_the_program_of_one_name(folder: Path) -> None:
    session = Session(folder, setup="PROCESS")
    messages, errors = said(session, "LOAD PROCESS")
    assert errors == []
    assert messages == ["6 LOCATIONS READ FROM PROCESS.LOC: A, B, C, D, E, F",
                        "PROGRAM PROCESS.DAT READ: 35 STEPS, 0 ERRORS; EXECUTE PROCESS RUNS IT"]
    assert session.simulator.location("A") == Location((465.0, -45.0, -245.0), (89.0, 91.0, 0.0))
    assert session.simulator.unsaved_locations() == []  # a file holds them
    events = list(session.command("EXEC PROCESS"))
    assert not [e for e in events if isinstance(e, Error)]


def test_load_names_what_is_missing_or_wrong_and_reports_a_programs_errors(folder: Path) -> None:
    (folder / "BAD.DAT").write_text("    MOVE A\n    JUMP 3\n")
    session = Session(folder, setup=None)
    events = list(session.command("LOAD BAD"))
    [error] = [e for e in events if isinstance(e, Error)]
    assert (error.program, error.step) == ("BAD", 2) and "JUMP IS NOT A COMMAND THE SIMULATOR ACCEPTS" in error.message.upper()
    messages = [e.text for e in events if isinstance(e, Message)]
    assert messages == ["PROGRAM BAD.DAT READ: 2 STEPS, 1 ERROR; LISTP OR EDIT SHOWS THE STEPS TO MEND"]
    assert said(session, "LOAD NONE")[1] == [
        "LOAD: THERE IS NO NONE.LOC OR NONE.DAT IN THE WORKSPACE (LISTL AND LISTF LIST THEM)"]
    assert "LOAD NAME READS NAME.LOC" in said(session, "LOAD")[1][0]
    assert "LOAD NAME READS NAME.LOC" in said(session, "LOAD PROCESS.SET")[1][0]
    assert "NOT A VALID NAME" in said(session, "LOAD A/B")[1][0].upper()
    assert said(session, "LOAD PROCESS.DAT")[0] == [
        "PROGRAM PROCESS.DAT READ: 35 STEPS, 0 ERRORS; EXECUTE PROCESS RUNS IT"]  # only the program
    assert session.simulator.locations == {}


# -- the line-mode monitor ------------------------------------------------------------------------

def test_the_monitor_refuses_then_stores_and_loads_back(folder: Path, monkeypatch: pytest.MonkeyPatch,
                                                        capsys: pytest.CaptureFixture[str]) -> None:
    lines = ["STOREL PROCESS", "HERE P1", "STOREL PROCESS", "STOREL PROCESS", "LOAD PROCESS.LOC"]
    monkeypatch.setattr("sys.stdin", io.StringIO("".join(f"{line}\n" for line in lines)))
    status = main(["monitor", "--workspace", str(folder)])
    out = capsys.readouterr().out.splitlines()
    assert status == 1  # the refusals are errors
    assert out == [
        ". STOREL PROCESS",
        "*** STOREL: NO LOCATIONS ARE DEFINED: PROCESS.LOC (6 LOCATIONS) IS KEPT AS IT IS",
        ". HERE P1",
        ". STOREL PROCESS",
        "*** STOREL: PROCESS.LOC (6 LOCATIONS) WAS NOT STORED BY THIS SESSION: NOTHING WRITTEN. "
        "STOREL PROCESS AGAIN REPLACES IT; STOREL <ANOTHER NAME> KEEPS IT",
        ". STOREL PROCESS",
        "1 LOCATION STORED IN PROCESS.LOC",
        ". LOAD PROCESS.LOC",
        "1 LOCATION READ FROM PROCESS.LOC: P1",
    ]
