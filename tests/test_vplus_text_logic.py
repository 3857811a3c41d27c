"""Issue 36, items 1-3: V+ text keeps its case, V+ logic gives TRUE (-1) / FALSE (0), and a
run-time error stops a V+ program at its step (the Adept V+ Language User's Guide, "Logical
Operators" and "Logical (Boolean) Expressions": x = 6, y = 10 give -1 for NOT(x == 7) and
(x > 2) AND (y =< 10), 0 for NOT(x == 6) and (x < 2) OR (y > 10))."""

from __future__ import annotations

from pathlib import Path

import pytest

from test_vplus_lang import body, completed, errors, typed, vplus
from valterm.cli import main
from valterm.core.events import Step

# -- item 1: text keeps its case; `;` starts a comment only outside quotes ------------------


def test_a_condition_compares_text_in_the_case_it_was_written() -> None:
    _, events = vplus(body('$s = "zero"', 'IF $s == "zero" THEN', 'TYPE "THEN"', "ELSE", 'TYPE "ELSE"', "END"))
    assert typed(events) == ["THEN"]


def test_a_while_on_text_ends() -> None:
    _, events = vplus(body('$s = "one"', "n = 0", 'WHILE $s <> "zero" DO', "n = n+1",
                           'IF n == 3 THEN', '$s = "zero"', "END", "END", 'TYPE "n=", n'))
    assert typed(events) == ["n=3"] and completed(events)


def test_until_and_a_goto_condition_keep_the_case_too() -> None:
    _, events = vplus(body('$s = "a"', "DO", '$s = $s + "b"', 'UNTIL $s == "abbb"', "TYPE $s",
                           'IF $s <> "ABBB" GOTO 10', 'TYPE "WRONG"', '10 TYPE "RIGHT"'))
    assert typed(events) == ["abbb", "RIGHT"]


def test_a_call_argument_keeps_its_case() -> None:
    text = body('CALL show("Mixed Case")', '$w = "lower"', "CALL show($w)") + ".PROGRAM show($t)\n    TYPE $t\n.END\n"
    _, events = vplus(text)
    assert typed(events) == ["Mixed Case", "lower"]


def test_names_stay_case_insensitive() -> None:
    _, events = vplus(body("Count = 2", "COUNT = count+1", "$Name = \"Ab\"", "TYPE $NAME, count"))
    assert typed(events) == ["Ab3"]


def test_a_semicolon_inside_quotes_is_text() -> None:
    _, events = vplus(body('TYPE "a;b"   ; a comment', '$s = "x;y" ; another', "TYPE $s",
                           'IF $s == "x;y" THEN ; here too', 'TYPE "EQUAL"', "END"))
    assert typed(events) == ["a;b", "x;y", "EQUAL"]
    shown = [e.text for e in events if isinstance(e, Step)]
    assert shown[0] == 'TYPE "a;b"'  # the step as it scrolls: its text, not its comment


# -- item 2: V+ logic ----------------------------------------------------------------------

def test_and_or_xor_not_give_true_or_false() -> None:
    _, events = vplus(body("TYPE 6 AND 10, 0 OR 10, 0 AND 10, 0 OR 0",
                           "TYPE 6 XOR 0, 6 XOR 10, NOT 5, NOT 0"))
    assert typed(events) == ["-1 -1 0 0", "-1 0 0 -1"]


def test_the_users_guide_examples() -> None:
    _, events = vplus(body("x = 6", "y = 10", "TYPE NOT(x == 7), (x > 2) AND (y =< 10)",
                           "TYPE NOT(x == 6), (x < 2) OR (y > 10)"))
    assert typed(events) == ["-1 -1", "0 0"]


def test_a_stored_conjunction_is_true() -> None:
    _, events = vplus(body("x = 6", "y = 10", "ok = x AND y", "IF ok == TRUE THEN", 'TYPE "TRUE"', "END",
                           "no = 0 OR 0", "IF no == FALSE THEN", 'TYPE "FALSE"', "END"))
    assert typed(events) == ["TRUE", "FALSE"]


def test_comparisons_give_true_or_false() -> None:
    _, events = vplus(body('same = $CHR(65) == "A"', 'other = "a" <> "a"', "TYPE 3 > 2, 3 < 2, 2 == 2, same, other"))
    assert typed(events) == ["-1 0 -1 -1 0"]


def test_bitwise_operators_stay_bitwise() -> None:
    _, events = vplus(body("TYPE 6 BAND 10, 6 BOR 10, 6 BXOR 10, 12 BAND 5"))
    assert typed(events) == [f"{6 & 10} {6 | 10} {6 ^ 10} {12 & 5}"]


# -- item 3: a run-time error stops the program at its step ----------------------------------

@pytest.mark.parametrize("line, reason", [
    ("x = y+1", "VARIABLE Y IS NOT DECLARED"),
    ("x = 1/0", "DIVISION BY ZERO"),
    ("x = SQRT(-1)", "NOT A NUMBER"),
    ("IF q > 1 THEN", "VARIABLE Q IS NOT DECLARED"),
    ("TYPE 1/0", "DIVISION BY ZERO"),
    ("WHILE w DO", "VARIABLE W IS NOT DECLARED"),
])
def test_a_run_time_error_stops_a_vplus_program(line: str, reason: str) -> None:
    closing = ["END"] if line.startswith(("IF", "WHILE")) else []
    _, events = vplus(body('TYPE "BEFORE"', line, 'TYPE "INSIDE"', *closing, 'TYPE "AFTER"', "MOVE #PPOINT(10)"))
    found = errors(events)
    assert len(found) == 1 and found[0].step == 2 and reason in found[0].message
    assert typed(events) == ["BEFORE"] and not completed(events)
    assert not any(isinstance(e, Step) and e.step > 2 for e in events)


def test_an_error_in_a_subroutine_stops_the_whole_run() -> None:
    text = body("CALL sub()", 'TYPE "BACK"') + ".PROGRAM sub()\n    x = 1/0\n    TYPE \"SUB\"\n.END\n"
    _, events = vplus(text)
    assert [(e.program, e.step) for e in errors(events)] == [("SUB", 1)]
    assert typed(events) == [] and not completed(events)


def test_run_exits_1_naming_the_step(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    program = tmp_path / "bad.v2"
    program.write_text(body("x = 1", "x = x/0", "MOVE #PPOINT(10)", 'TYPE "AFTER"'))
    code = main(["run", str(program), "--workspace", str(tmp_path / "ws")])
    out = capsys.readouterr().out
    assert code == 1
    assert "T STEP 2" in out.upper() and "DIVISION BY ZERO" in out
    assert "COMPLETED" not in out and "AFTER" not in out.split("DIVISION BY ZERO")[1].split("WHERE")[0]
