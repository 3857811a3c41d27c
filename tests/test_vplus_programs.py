"""The bundled V+ programs (programs/vplus): they pass `check` as V+, and the
pick-and-place ones put every part where it belongs on the bundled cells."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from valterm.cli import main
from valterm.core import resources

VPLUS = resources.data_path("programs", "vplus")
PROGRAMS = sorted(p.name for p in VPLUS.glob("*.v2"))


def run_json(capsys: pytest.CaptureFixture[str], workspace: Path, *argv: str) -> tuple[int, list[dict]]:
    capsys.readouterr()
    status = main(["--workspace", str(workspace), "run", *argv, "--json"])
    out = capsys.readouterr().out
    return status, [json.loads(line) for line in out.splitlines()]


def releases(events: list[dict]) -> dict[int, np.ndarray]:
    return {e["part"]: np.array(e["position"]) for e in events if e["event"] == "release"}


def test_there_are_at_least_ten_programs_each_saying_what_it_exercises() -> None:
    assert len(PROGRAMS) >= 10
    for name in PROGRAMS:
        head = (VPLUS / name).read_text().splitlines()[:20]
        assert any("V+ features:" in line for line in head), name
        assert any("original code" in line for line in head), name


def test_every_program_passes_check_as_vplus(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    status = main(["--workspace", str(tmp_path), "check", *(str(VPLUS / name) for name in PROGRAMS)])
    out = capsys.readouterr().out
    assert status == 0, out
    summaries = [line for line in out.splitlines() if "steps," in line]
    assert len(summaries) > len(PROGRAMS)  # the subroutines are checked too
    assert all("no errors" in line and "DIALECT V+" in line for line in summaries), out


@pytest.fixture(scope="module")
def process_releases(tmp_path_factory: pytest.TempPathFactory) -> dict[int, np.ndarray]:
    """Where the thesis's own PROCESS program puts the two parts (Chapter 7)."""
    import contextlib
    import io

    workspace = tmp_path_factory.mktemp("process")
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["--workspace", str(workspace), "run", "PROCESS", "--cell", "PROCESS.SET",
                     "--loc", "PROCESS.LOC", "--json"]) == 0
    return releases([json.loads(line) for line in out.getvalue().splitlines()])


@pytest.mark.parametrize(("program", "extra"), [
    ("pick.place.v2", ()),
    ("palletize.v2", ()),
    ("frame.v2", ()),
    ("handshake.v2", ("--inputs", str(VPLUS / "handshake.inputs"))),
    ("precision.v2", ("--loc", str(VPLUS / "STATIONS.LOC"))),
])
def test_process_cell_programs_put_both_parts_on_the_left_table(
        capsys: pytest.CaptureFixture[str], tmp_path: Path, process_releases: dict[int, np.ndarray],
        program: str, extra: tuple[str, ...]) -> None:
    locations = extra if "--loc" in extra else ("--loc", "PROCESS.LOC", *extra)
    status, events = run_json(capsys, tmp_path, str(VPLUS / program), "--cell", "PROCESS.SET", *locations)
    assert status == 0, [e for e in events if e["event"] == "error"]
    assert [(e["event"], e["part"]) for e in events if e["event"] in ("grasp", "release")] == [
        ("grasp", 1), ("release", 1), ("grasp", 2), ("release", 2)]
    placed = releases(events)
    expected = dict(process_releases)
    if program == "palletize.v2":
        # its second pick is A shifted 165 mm along Y, keeping A's orientation (O 89, A 91),
        # not B's (90, 90): the part is gripped a little differently and lands 1.6 mm away
        expected[2] = np.array([-85.395848, 576.563808, -279.580505])
    for part in (1, 2):  # at C and D, standing on the left-hand table (top Z = -280)
        assert placed[part] == pytest.approx(expected[part], abs=1e-5)
        assert placed[part][2] == pytest.approx(-280.0, abs=1.0)


def test_conveyor_unloads_three_parts_onto_the_table(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    status, events = run_json(capsys, tmp_path, str(VPLUS / "conveyor.v2"), "--cell", "CONV.SET", "--loc", "CONV.LOC")
    assert status == 0
    placed = releases(events)
    assert sorted(placed) == [1, 2, 3]
    expected = {1: (545.187454, 353.061143, -494.951539), 2: (481.781638, 341.247475, -495.732496),
                3: (406.669483, 358.300717, -494.0)}
    for part, position in expected.items():
        assert placed[part] == pytest.approx(np.array(position), abs=1e-4)
        assert -500.0 < placed[part][2] < -490.0  # put down on the table (top Z = -500), off the belt
    signals = [(e["number"], e["on"]) for e in events if e["event"] == "signal"]
    assert signals == [(3, True), (3, False)] * 3  # the belt stopped for each pick


def test_swap_exchanges_the_two_parts_of_demo3(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    from valterm.core.files.setup import read_setup

    cell = read_setup(resources.data_path("cells", "DEMO3.SET"))
    status, events = run_json(capsys, tmp_path, str(VPLUS / "swap.v2"), "--cell", "DEMO3.SET")
    assert status == 0
    hand = [(e["event"], e["part"]) for e in events if e["event"] in ("grasp", "release")]
    assert hand == [("grasp", 1), ("release", 1), ("grasp", 2), ("release", 2), ("grasp", 1), ("release", 1)]
    placed = releases(events)  # the last release of each part: where it stays
    assert placed[1] == pytest.approx(np.asarray(cell.object(2).reference), abs=1e-6)
    assert placed[2] == pytest.approx(np.asarray(cell.object(1).reference), abs=1e-6)


def test_handshake_waits_for_its_inputs_and_pulses_its_outputs(capsys: pytest.CaptureFixture[str],
                                                                tmp_path: Path) -> None:
    status, events = run_json(capsys, tmp_path, str(VPLUS / "handshake.v2"), "--cell", "PROCESS.SET",
                              "--loc", "PROCESS.LOC", "--inputs", str(VPLUS / "handshake.inputs"))
    assert status == 0
    changes = [(e["number"], e["on"]) for e in events if e["event"] == "signal"]
    assert changes[:4] == [(1, False), (2, False), (1003, True), (1001, True)]
    second = changes.index((1002, True))
    assert changes[second - 1] == (2, False) and changes[second + 1] == (1, True)
    arrival = next(e["time"] for e in events if e["event"] == "signal" and e["number"] == 1002)
    assert arrival == pytest.approx(40.0, abs=0.2)  # it waited for the scripted input
    typed = [e["text"] for e in events if e["event"] == "type"]
    assert "WAITING FOR THE SECOND PART" in typed
    assert events[-1]["signals_on"] == [1001, 1002, 1003]  # the outputs were all turned off again


def test_handshake_reacts_when_the_cell_stops_during_a_wait(capsys: pytest.CaptureFixture[str],
                                                             tmp_path: Path) -> None:
    inputs = tmp_path / "stop.inputs"
    inputs.write_text("0 1003 1\n0 1001 1\n20 1003 0\n")  # the cell stops before part 2 comes
    status, events = run_json(capsys, tmp_path, str(VPLUS / "handshake.v2"), "--cell", "PROCESS.SET",
                              "--loc", "PROCESS.LOC", "--inputs", str(inputs))
    assert status == 0
    texts = [e.get("text") for e in events if e["event"] in ("type", "message")]
    assert texts[-3:] == ["REACT -1003: CALL STOP.ALL", "STOP REQUESTED", "PROGRAM HANDSHAKE COMPLETED: 1 LOOP"]
    assert [e["part"] for e in events if e["event"] == "release"] == [1]  # part 2 never came


def test_handshake_without_its_inputs_stops_at_the_wait(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    status, events = run_json(capsys, tmp_path, str(VPLUS / "handshake.v2"), "--cell", "PROCESS.SET",
                              "--loc", "PROCESS.LOC")
    assert status == 1
    (error,) = [e for e in events if e["event"] == "error"]
    assert error["program"] == "HANDSHAKE" and "WAIT SIG(1001)" in error["message"]


@pytest.mark.parametrize(("program", "wanted"), [
    ("hanoi.v2", ["MOVES: 15 (2^4-1 = 15)"]),
    ("menu.v2", ["JOB 4: CODE 7 IS UNKNOWN", "4 JOBS DONE, 2 EVEN CODES, 3 = INT(7/2)"]),
    ("report.v2", ["SHIFT REPORT / CELL PROCESS", "SHIFT 1:   11 12 13", "TOTAL   102",
                   "HAND TIME 0.35 S", "MASK 5 CP -1 MESSAGES 0", "XOR WORKS"]),
    ("circle.v2", ["LARGEST RADIUS ERROR   0.000000 MM", "SMALLEST OF 3, 1, 2: 1"]),
])
def test_programs_without_parts_type_what_they_compute(capsys: pytest.CaptureFixture[str], tmp_path: Path,
                                                       program: str, wanted: list[str]) -> None:
    status, events = run_json(capsys, tmp_path, str(VPLUS / program), "--cell", "PROCESS.SET", "--loc", "PROCESS.LOC")
    assert status == 0, [e for e in events if e["event"] == "error"]
    typed = [e["text"] for e in events if e["event"] == "type"]
    for line in wanted:
        assert line in typed
    if program == "hanoi.v2":
        assert sum(line.startswith("DISC ") for line in typed) == 15
