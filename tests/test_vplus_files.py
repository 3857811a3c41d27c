"""V+ program files with .PROGRAM blocks, and the simulated I/O panel (issue 14 items 2-3)."""

from __future__ import annotations

from pathlib import Path

import pytest

from valterm.core.files.errors import FileFormatError
from valterm.core.files.vplus import format_vplus, parse_vplus
from valterm.core.signals import FALSE, TRUE, SignalError, SignalPanel, parse_inputs

SOURCE = """\
; a V+ file: two programs and a data section
.PROGRAM pick.place(part, count) ; move COUNT parts
    AUTO i
    FOR i = 1 TO count
        CALL pick(part)
    END
10  TYPE "done"
.END

.PROGRAM pick(part)
    APPRO part, 50
    MOVES part
    CLOSEI
    DEPARTS 50
.END
.LOCATIONS
a  100 200 300 0 90 0
.END
"""


def test_every_block_becomes_a_program_with_its_dotted_name() -> None:
    blocks = parse_vplus(SOURCE, "PICK.V2")
    assert [b.program.name for b in blocks] == ["PICK.PLACE", "PICK"]
    first = blocks[0]
    assert first.parameters == ["PART", "COUNT"] and first.comment == "move COUNT parts"
    assert [s.text for s in first.program.steps] == [
        "AUTO i", "FOR i = 1 TO count", "CALL pick(part)", "END", 'TYPE "done"']
    assert first.program.steps[-1].label == 10 and first.program.steps[0].line == 3


def test_round_trip_through_the_writer() -> None:
    blocks = parse_vplus(SOURCE, "PICK.V2")
    again = parse_vplus(format_vplus(blocks), "OUT.V2")
    assert [(b.program.name, b.parameters, [(s.label, s.text) for s in b.program.steps]) for b in again] == \
        [(b.program.name, b.parameters, [(s.label, s.text) for s in b.program.steps]) for b in blocks]


@pytest.mark.parametrize(("text", "line", "reason"), [
    (".PROGRAM a()\n  MOVE x\n", 0, "has no .END"),
    ("MOVE x\n", 1, "outside .PROGRAM"),
    (".PROGRAM a()\n.PROGRAM b()\n.END\n", 2, ".END missing"),
    (".END\n", 1, ".END without .PROGRAM"),
    (".PROGRAM 9lives()\n.END\n", 1, "is not a program name"),
    (".PROGRAM a()\n.END\n.PROGRAM A()\n.END\n", 0, "defined twice"),
    ("; nothing\n", 0, "no .PROGRAM block"),
])
def test_malformed_files_give_located_reasons(text: str, line: int, reason: str) -> None:
    with pytest.raises(FileFormatError) as error:
        parse_vplus(text, Path("BAD.V2"))
    assert error.value.line == line and reason in error.value.reason
    assert str(error.value).startswith("BAD.V2")


def test_signals_outputs_inputs_and_sig() -> None:
    panel = SignalPanel()
    assert panel.set_by_program(3) == 3 and panel.sig(3) == TRUE and panel.sig(-3) == FALSE
    panel.set_by_program(-3)
    assert panel.sig(3) == FALSE and panel.outputs_on() == []
    panel.set_input(1001, True)
    assert panel.sig(1001) == TRUE and panel.inputs_on() == [1001]
    with pytest.raises(SignalError, match="is an input"):
        panel.set_by_program(1001)
    with pytest.raises(SignalError, match="there is no signal 700"):
        panel.sig(700)


def test_inputs_script_is_sorted_and_checked() -> None:
    changes = parse_inputs("# time signal value\n2.5 1002 ON\n\n0.5 1001 1\n", "IN.TXT")
    assert [(c.time, c.signal, c.on) for c in changes] == [(0.5, 1001, True), (2.5, 1002, True)]
    with pytest.raises(FileFormatError, match="IN.TXT:1: signal 5 is not an input"):
        parse_inputs("1 5 1\n", "IN.TXT")
    with pytest.raises(FileFormatError, match="IN.TXT:2: expected TIME SIGNAL VALUE"):
        parse_inputs("1 1001 1\n1 1001\n", "IN.TXT")
