"""Issue 25: ``valterm run``'s write loop (``write_events``) is the one ``valterm bench`` times,
and it writes what run wrote before: every event's line, a step's JSON line read from it."""

from __future__ import annotations

import json

from valterm.bench.interpreter import LOOP, loop_statements
from valterm.core.events import Error, Event, LimitReached, Message, Pause, Step, TypeOut
from valterm.core.simulator import Simulator
from valterm.core.text.transcript import Blocks, event_lines, write_events
from valterm.core.val.interpreter import Interpreter, program_from_lines
from valterm.core.val.limits import NO_LIMITS

class Lines:
    """A stream that keeps each write (a Blocks' stream)."""

    def __init__(self) -> None:
        self.writes: list[str] = []
        self.flushes = 0

    def write(self, text: str) -> int:
        self.writes.append(text)
        return len(text)

    def flush(self) -> None:
        self.flushes += 1

    def lines(self) -> list[str]:
        return "".join(self.writes).splitlines(keepends=True)


def written(events: list[Event], as_json: bool = False) -> tuple[int, list[str]]:
    stream = Lines()
    errors = write_events(iter(events), Blocks(stream), as_json=as_json)
    return errors, stream.lines()


EVENTS = [Step("P", 1, "X=1"), Step("P", 1, "X=1"), TypeOut("A\nB"), Pause("P", 4, "HOLD"),
          Error("P", 2, "UNDEFINED VALUE: Y"), LimitReached("P", 3, "STEPS LIMIT"), Message("DONE")]


def test_json_lines_are_each_events_own_and_errors_are_counted() -> None:
    errors, lines = written(EVENTS, as_json=True)
    assert errors == 2  # LimitReached is an Error
    assert lines == [event.json_line() for event in EVENTS]
    assert [json.loads(line)["event"] for line in lines] == ["step", "step", "type", "pause", "error", "limit",
                                                                "message"]


def test_the_transcript_is_each_events_lines_and_a_pause_goes_on() -> None:
    errors, lines = written(EVENTS)
    assert errors == 2
    expected = [line + "\n" for event in EVENTS for line in event_lines(event)]
    expected.insert(expected.index("PAUSE HOLD\n") + 1, "(headless: PROCEED)\n")
    assert lines == expected


def test_the_bench_counts_the_steps_its_loop_runs() -> None:
    program = program_from_lines("BENCH", LOOP)
    for passes in (0, 1, 25):
        interpreter = Interpreter(Simulator(), lambda name: program, {"N": float(passes)},
                                  limits=NO_LIMITS)
        stream = Lines()
        assert write_events(interpreter.execute("BENCH"), Blocks(stream), as_json=True) == 0
        lines = stream.lines()
        assert sum(json.loads(line)["event"] == "step" for line in lines) == loop_statements(passes)
