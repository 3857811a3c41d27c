"""Issue 25: ``to_json`` and ``json_line`` without ``dataclasses.asdict`` give what it gave,
for every event the PROCESS run yields with collision checks on (and the End event)."""

from __future__ import annotations

import json
from dataclasses import asdict

from valterm.core import resources
from valterm.core.cell.workcell import WorkCell
from valterm.core.events import End, Event, Step, TypeOut, Where
from valterm.core.files.locations import read_locations
from valterm.core.files.programs import read_program
from valterm.core.files.setup import read_setup
from valterm.core.simulator import Simulator
from valterm.core.val.interpreter import Interpreter


def _same(event: Event) -> None:
    expected = {"event": event.event, **asdict(event)}
    if isinstance(event, Step):
        del expected["json"], expected["line"]  # its lines, kept on it once made: not its fields
    if isinstance(event, Where) and event.ypr is None:
        del expected["ypr"]  # a 1985 WHERE is written without V+'s angles (issue 23)
    assert event.to_json() == expected
    assert event.json_line() == json.dumps(expected) + "\n"


def test_every_event_of_the_process_run_is_written_as_before() -> None:
    cell: WorkCell = read_setup(resources.data_path("cells", "PROCESS.SET"))
    sim = Simulator(cell)
    sim.locations.update(read_locations(resources.data_path("programs", "PROCESS.LOC")))
    sim.collision_checks = True
    interpreter = Interpreter(sim, lambda name: read_program(resources.data_path("programs", f"{name}.DAT")), {})
    kinds = set()
    for event in interpreter.execute("PROCESS", 2):
        _same(event)
        kinds.add(event.event)
    assert {"step", "pose", "motion", "grasp", "release", "collision", "near"} <= kinds, kinds
    where = sim.where()
    _same(End(where=where.to_json(), variables={"X": 1.0}, cycle_time_s=1.5, signals_on=(1, 2)))
    _same(where)


def test_a_step_line_is_kept_per_step_and_right_for_each() -> None:
    one, other = Step("P", 1, 'TYPE "A"'), Step("P", 2, "X=1")
    assert json.loads(one.json_line()) == {"event": "step", "program": "P", "step": 1, "text": 'TYPE "A"'}
    assert one.json_line() is Step("P", 1, 'TYPE "A"').json_line()       # made once
    assert json.loads(other.json_line())["step"] == 2
    assert one.json == one.json_line() and not Step("P", 3, "X=2").json  # what run's loop reads
    assert one == Step("P", 1, 'TYPE "A"') and hash(one) == hash(Step("P", 1, 'TYPE "A"'))  # made or not
    assert TypeOut("Ü").json_line() == json.dumps({"event": "type", "text": "Ü"}) + "\n"
