"""Expressions nested deeper than MAX_NESTING are refused with the step named, never a
RecursionError (issue 27 item 4): the parsers of both dialects, check, run and monitor."""

from __future__ import annotations

from pathlib import Path

import pytest

from valterm.cli import main
from valterm.core.val.expr import MAX_NESTING, ExprError, compile_expr
from valterm.core.val.dialects.vplus.expr import compile_number

DEEP = "X = " + "(" * 124 + "1" + ")" * 124  # 252 characters: the line


def nested(levels: int) -> str:
    return "(" * levels + "1" + ")" * levels


def test_the_limit_is_exact_in_both_dialects() -> None:
    assert compile_expr(nested(MAX_NESTING)).fn({}) == 1.0
    assert compile_number(nested(MAX_NESTING))({}) == 1.0
    for parse in (compile_expr, compile_number):
        with pytest.raises(ExprError, match=f"(?i)nested deeper than {MAX_NESTING} levels"):
            parse(nested(MAX_NESTING + 1))


@pytest.mark.parametrize("text", ["-" * 300 + "1", "NOT " * 60 + "1", "-(" * 100 + "1" + ")" * 100,
                                  "(" * 124 + "1" + ")" * 124])
def test_signs_and_brackets_count_and_nothing_recurses_past_python(text: str) -> None:
    for parse in (compile_expr, compile_number):
        with pytest.raises(ExprError, match="(?i)nested deeper"):
            parse(text)


def test_long_flat_expressions_are_no_nesting() -> None:
    flat = "+".join(["1"] * 120)  # a long line of sums is one level deep
    assert compile_expr(flat).fn({}) == 120.0
    assert compile_number("-1 - -2 * (3 + -4)")({}) == -3.0  # signs after an operand are operators


def _program(tmp_path: Path) -> Path:
    path = tmp_path / "DEEP.DAT"
    path.write_text(f"1 {DEEP}\n")
    return path


def test_check_and_run_name_the_step_and_exit_1(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    program = _program(tmp_path)
    for command in ("check", "run"):
        assert main(["--workspace", str(tmp_path / "ws"), command, str(program)]) == 1
        captured = capsys.readouterr()
        text = (captured.out + captured.err).upper()
        assert "DEEP STEP 1" in text and "NESTED DEEPER THAN" in text, text
        assert "RECURSION" not in text and "INTERNAL ERROR" not in text


def test_monitor_refuses_the_line_and_goes_on(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                              monkeypatch: pytest.MonkeyPatch) -> None:
    import io

    monkeypatch.setattr("sys.stdin", io.StringIO(f"{DEEP}\nX = 5*7\nTYPE X\n"))
    status = main(["--workspace", str(tmp_path / "ws"), "monitor"])
    out = capsys.readouterr()
    text = (out.out + out.err).upper()
    assert "NESTED DEEPER THAN" in text and ". TYPE X" in text, text  # the next lines still run
    assert "INTERNAL ERROR" not in text and status != 70
