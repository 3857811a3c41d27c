"""V+ forms found in published programs (issue 23 follow-up): each test is a small program of
our own that uses the same statement or function, with values worked out from the V+ reference."""

from __future__ import annotations

from pathlib import Path

import pytest

from valterm.cli import main
from valterm.core.events import Event, TypeOut
from valterm.core.files.vplus import parse_vplus
from valterm.core.simulator import Simulator
from valterm.core.val.interpreter import Interpreter


def vplus(text: str) -> tuple[Interpreter, list[Event]]:
    programs = {b.program.name: b.program for b in parse_vplus(text, "T.v2")}
    interpreter = Interpreter(Simulator(None), lambda name: programs[name], {})
    return interpreter, list(interpreter.execute(next(iter(programs))))


def body(*lines: str) -> str:
    return ".PROGRAM t()\n" + "\n".join(f"    {line}" for line in lines) + "\n.END\n"


def typed(*lines: str) -> list[str]:
    _, events = vplus(body(*lines))
    return [e.text for e in events if isinstance(e, TypeOut)]


def check(tmp_path: Path, capsys: pytest.CaptureFixture[str], text: str) -> tuple[int, list[str]]:
    program = tmp_path / "c.v2"
    program.write_text(text)
    capsys.readouterr()
    status = main(["--workspace", str(tmp_path / "ws"), "check", str(program)])
    return status, capsys.readouterr().out.splitlines()


def test_a_case_whose_selector_does_not_decode_is_reported_not_a_crash(
        capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    status, lines = check(tmp_path, capsys, body("CASE NOSUCH(5) OF", "  VALUE 1:", "    x = 1",
                                                 "  ANY", "    x = 2", "END", "TYPE 1"))
    assert status == 1
    assert any("T step 1: CASE: NOSUCH is not a V+ function" in line for line in lines), lines
    assert any(line.startswith("T: 7 steps, 1 error(s)") for line in lines), lines
