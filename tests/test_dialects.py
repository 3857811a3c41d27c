"""Dialects as packages (issue 37): the shared core runs any dialect that fills in ``Dialect``;
a new one is a package of its own and a line in the registry (docs/ARCHITECTURE.md, "Adding a
dialect"). A toy dialect made here from the shared core alone runs, calls and is checked."""

from __future__ import annotations

import pytest
from test_val_interpreter import FakeSim

from valterm.core.events import Error, TypeOut
from valterm.core.files.programs import Program
from valterm.core.val import dialects
from valterm.core.val.builders import STRUCTURE, Build
from valterm.core.val.checker import check_program
from valterm.core.val.compiler import Grammar
from valterm.core.val.dialect import Dialect
from valterm.core.val.interpreter import Interpreter, program_from_lines
from valterm.core.val.ops import Events, Op
from valterm.core.val.parser import Statement, ValSyntaxError


def _parse(text: str) -> Statement:
    """The toy language: SAY text, CALL name, RETURN, END (and nothing else)."""
    word, _, rest = text.strip().upper().partition(" ")
    if word == "SAY":
        return Statement("SAY", (rest,), text)
    if word == "CALL" and rest:
        return Statement("CALL", (rest,), text)
    if word in ("RETURN", "END") and not rest:
        return Statement(word, (), text)
    raise ValSyntaxError(f"{word}: NOT A TOY WORD")


def _say(c: Build, st: Statement) -> Op:
    def run() -> Events:
        yield TypeOut(st.args[0])
        return c.next
    return c.action(run)


TOY = Dialect(Grammar("toy", _parse, lambda text: None, ends_close="NOTHING"), "TOY (A TEST)",
              {**STRUCTURE, "SAY": _say}, missing_program="{name} (TOY)")


@pytest.fixture
def toy(monkeypatch: pytest.MonkeyPatch) -> Dialect:
    monkeypatch.setattr(dialects, "NAMES", (*dialects.NAMES, "toy"))
    monkeypatch.setattr(dialects, "_PACKAGES", {**dialects._PACKAGES, "toy": lambda: TOY})
    return TOY


def _toy_program(name: str, lines: list[str]) -> Program:
    program = program_from_lines(name, lines)
    program.dialect = "toy"
    return program


def test_a_new_dialect_runs_and_calls_through_the_shared_core(toy: Dialect) -> None:
    programs = {"MAIN": ["SAY HELLO", "CALL SUB", "SAY BACK"], "SUB": ["SAY IN SUB", "RETURN"]}
    interpreter = Interpreter(FakeSim(), lambda name: _toy_program(name, programs[name]), {}, dialect="toy")
    lines = [e.text for e in interpreter.execute("MAIN") if isinstance(e, TypeOut)]
    assert lines == ["HELLO", "IN SUB", "BACK"]


def test_the_shared_call_depth_stops_a_new_dialect_too(toy: Dialect) -> None:
    interpreter = Interpreter(FakeSim(), lambda name: _toy_program(name, ["CALL LOOP"]), {}, dialect="toy")
    errors = [e.message for e in interpreter.execute("LOOP") if isinstance(e, Error)]
    assert errors == ["CALL LOOP: MORE THAN 20 NESTED CALLS"]


def test_the_checker_speaks_the_new_dialects_words(toy: Dialect) -> None:
    program = _toy_program("MAIN", ["SAY HI", "END", "CALL GONE", "JUMP"])
    report = check_program(program, program_exists=lambda name: False)
    assert report.against == "DIALECT TOY (A TEST)"
    assert [str(d) for d in report.diagnostics] == [
        "MAIN step 2: END without NOTHING",
        "MAIN step 3: warning: CALL GONE: there is no program GONE (TOY)",
        "MAIN step 4: JUMP: NOT A TOY WORD",
    ]


@pytest.mark.parametrize("name", dialects.NAMES)
def test_each_registered_dialect_is_the_package_of_its_name(name: str) -> None:
    language = dialects.dialect(name)
    assert language.name == name
    assert set(STRUCTURE) <= set(language.builders)  # the shared block structure and CALL
    assert all(callable(builder) for builder in language.builders.values())


def test_an_unknown_dialect_is_refused_naming_the_known_ones() -> None:
    with pytest.raises(ValueError, match=r"'AS' is not a dialect: use 1985 or v\+"):
        dialects.dialect("AS")

