"""COMMAND.DAT, HELPER.DAT, expressions and statements of the VAL-II compiler."""

from __future__ import annotations

import pytest

from valterm.core.files.errors import FileFormatError
from valterm.core.files.commandfile import AmbiguousCommand, UnknownCommand, default_commands, parse_command_file
from valterm.core.val.expr import ExprError, compile_condition, compile_expr
from valterm.core.files.helpfile import NoHelpTopic, default_help, parse_help_file
from valterm.core.val.parser import ASSIGN, LocArg, ValSyntaxError, parse_statement

# -- COMMAND.DAT and HELPER.DAT ------------------------------------------------------


def test_command_file_lists_the_language() -> None:
    table = default_commands()
    for name in ("READY", "MOVE", "MOVES", "APPRO", "APPROS", "DEPART", "DEPARTS", "DRIVE", "DRAW",
                 "ALIGN", "DELAY", "OPEN", "OPENI", "CLOSE", "CLOSEI", "GRASP", "HERE", "WHERE",
                 "SET", "SHIFT", "BASE", "POINT", "LEFTY", "RIGHTY", "ABOVE", "BELOW", "FLIP",
                 "NOFLIP", "SPEED", "GOTO", "IF", "ELSE", "END", "ENDIF", "WHILE", "DO", "UNTIL",
                 "CALL", "RETURN", "PAUSE", "PROCEED", "STOP", "HALT", "EXECUTE", "TYPE", "STATUS",
                 "HELP", "LISTP", "LISTF", "LISTL", "EDIT"):
        assert name in table, name
    assert table.lookup("EXECUTE").use == "M"
    assert table.lookup("GOTO").use == "P"
    assert table.lookup("MOVE").use == "B"


def test_every_command_has_a_help_topic() -> None:
    topics = default_help()
    for spec in default_commands():
        topic = topics.find(spec.name)
        assert spec.name in topic.names
        assert topic.syntax and topic.when and topic.text
    assert "ABORT" in topics.names()  # CTRL-C is explained though ABORT is not accepted


def test_help_lookup_by_prefix_and_menu() -> None:
    topics = default_help()
    assert topics.find("EXEC").name == "EXECUTE"
    assert topics.find("appros").name == "APPRO"
    with pytest.raises(NoHelpTopic, match="AMBIGUOUS"):
        topics.find("D")
    with pytest.raises(NoHelpTopic, match="NO HELP"):
        topics.find("XYZZY")
    menu = topics.menu()
    assert menu[0] == "HELP MENU" and any("EXECUTE" in line for line in menu)


def test_abbreviations() -> None:
    table = default_commands()
    assert table.lookup("LE").name == "LEFTY"
    assert table.lookup("AB").name == "ABOVE"
    assert table.lookup("EXEC").name == "EXECUTE"
    assert table.lookup("end").name == "END"  # an exact name wins over ENDIF
    assert table.lookup("MOVE").name == "MOVE"
    with pytest.raises(AmbiguousCommand) as info:
        table.lookup("D")
    assert "DEPART" in info.value.candidates and "DRIVE" in info.value.candidates
    with pytest.raises(UnknownCommand):
        table.lookup("JUMP")


@pytest.mark.parametrize("text, reason", [
    ("MOVE", "expected NAME USE ARGUMENTS"),
    ("move B LOC", "not a command name"),
    ("MOVE X LOC", "use 'X'"),
    ("MOVE B WHAT", "not an argument item"),
    ("MOVE B LOC\nMOVE B LOC", "listed twice"),
])
def test_bad_command_file_lines_are_located(text: str, reason: str) -> None:
    with pytest.raises(FileFormatError, match=reason) as info:
        parse_command_file("; header\n" + text, "COMMAND.DAT")
    assert info.value.line >= 2


@pytest.mark.parametrize("text, reason", [
    ("SYNTAX X", "before the first TOPIC"),
    ("TOPIC X\nWHEN now\ntext", "no SYNTAX"),
    ("TOPIC X\nSYNTAX X\ntext", "no WHEN"),
    ("TOPIC X\nSYNTAX X\nWHEN now\nTOPIC X", "already on line"),
])
def test_bad_help_file_lines_are_located(text: str, reason: str) -> None:
    with pytest.raises(FileFormatError, match=reason):
        parse_help_file(text, "HELPER.DAT")


# -- expressions ------------------------------------------------------------------------


@pytest.mark.parametrize("text, value", [
    ("1+2*3", 7.0),
    ("(1+2)*3", 9.0),
    ("-2*3", -6.0),
    ("--2", 2.0),
    ("10/4", 2.5),
    ("8-2-1", 5.0),
    ("X*2+Y", 13.0),
    ("-(X-Y)", -2.0),
    (".5+2.", 2.5),
    ("1E2", 100.0),
])
def test_arithmetic(text: str, value: float) -> None:
    assert compile_expr(text)({"X": 5.0, "Y": 3.0}) == value


@pytest.mark.parametrize("text, value", [
    ("COL.EQ.2", True),
    ("COL .EQ. ROW.", False),  # the thesis's trailing dot
    ("COL. LT. ROW.", True),   # blanks inside the dotted operator, as printed
    ("COL .NE. 2", False),
    ("COL .GE. 2 AND ROW .LE. 3", True),
    ("COL == 3 OR ROW <> 3", False),
    ("NOT COL > 2", True),
    ("COL < 3 AND NOT (ROW >= 4 OR COL = 0)", True),
    ("COL+1 .EQ. ROW", True),
    ("COL", True),
])
def test_conditions(text: str, value: bool) -> None:
    assert bool(compile_condition(text)({"COL": 2.0, "ROW": 3.0})) is value


def test_undeclared_variable_raises_key_error_naming_it() -> None:
    with pytest.raises(KeyError, match="ROW"):
        compile_condition("COL .LT. ROW")({"COL": 1.0})


@pytest.mark.parametrize("text, reason", [
    ("1+", "ends too soon"),
    ("(1+2", "missing '\\)'"),
    ("A B", "unexpected 'B'"),
    ("ABCDEFGHIJ", "longer than 9"),
    ("1/0", "division by zero"),
    ("2 $ 3", "unexpected character"),
    ("", "missing value"),
])
def test_expression_errors(text: str, reason: str) -> None:
    with pytest.raises(ExprError, match=reason):
        compile_condition(text)


def test_constants_are_folded() -> None:
    assert compile_expr("2*(3+4)").const == 14.0
    assert compile_expr("X+1").const is None
    assert compile_expr("X+1").names == ("X",)


# -- statements ---------------------------------------------------------------------


def args(text: str) -> tuple:
    st = parse_statement(text)
    return tuple(
        a.const if hasattr(a, "const") and a.const is not None else (a.text if hasattr(a, "src") else a)
        for a in st.args
    )


@pytest.mark.parametrize("text, command", [
    ("READY", "READY"), ("LE", "LEFTY"), ("AB", "ABOVE"), ("RIGHTY", "RIGHTY"), ("BELOW", "BELOW"),
    ("FLIP", "FLIP"), ("NOFLIP", "NOFLIP"), ("ALIGN", "ALIGN"), ("WHERE", "WHERE"),
    ("STATUS", "STATUS"), ("RETURN", "RETURN"), ("ELSE", "ELSE"), ("END", "END"),
    ("ENDIF", "ENDIF"), ("DO", "DO"), ("PROCEED", "PROCEED"), ("LISTF", "LISTF"),
    ("LISTL", "LISTL"), ("EXEC PROCESS,1", "EXECUTE"), ("HERE P1", "HERE"),
    ("CALL CONV2", "CALL"), ("GOTO 300", "GOTO"), ("SPEED 50", "SPEED"), ("DELAY 1", "DELAY"),
    ("MOVE A", "MOVE"), ("MOVES E", "MOVES"), ("APPRO A, -50", "APPRO"), ("APPROS C,-50", "APPROS"),
    ("DEPART 100", "DEPART"), ("DEPARTS 100", "DEPARTS"), ("DRIVE 2, -30, 100", "DRIVE"),
    ("DRAW 10,0,-5", "DRAW"), ("OPEN", "OPEN"), ("OPENI 100", "OPENI"), ("CLOSE 40", "CLOSE"),
    ("CLOSEI 50", "CLOSEI"), ("GRASP 50, 100", "GRASP"), ("SET P1=P2", "SET"),
    ("SHIFT E, 0, 0, -200", "SHIFT"), ("BASE ,,300,", "BASE"), ("POINT A", "POINT"),
    ("TYPE HELLO", "TYPE"), ("PAUSE", "PAUSE"), ("STOP", "STOP"), ("HALT", "HALT"),
    ("HELP MOVE", "HELP"), ("LISTP CONV1", "LISTP"), ("EDIT TEST.DAT", "EDIT"),
    ("IF X .EQ. 1 THEN", "IF"), ("WHILE X .LT. 3 DO", "WHILE"), ("UNTIL X .EQ. 3", "UNTIL"),
    ("COL=COL+1", ASSIGN),
])
def test_every_statement_parses(text: str, command: str) -> None:
    assert parse_statement(text).command == command


def test_arguments() -> None:
    assert args("APPRO A, -50") == (LocArg("A"), -50.0)
    assert args("EXEC PROCESS,1") == ("PROCESS", 1.0)
    assert args("EXECUTE CONV1.DAT") == ("CONV1",)
    assert args("DRIVE 2, -30, 100") == (2.0, -30.0, 100.0)
    assert args("BASE ,,300,") == (None, None, 300.0, None)
    assert args("BASE 0,0,300,0") == (0.0, 0.0, 300.0, 0.0)
    assert args("BASE ,,300") == (None, None, 300.0, None)
    assert args("SHIFT E, 0, 0, -200") == ("E", 0.0, 0.0, -200.0)
    assert args("SHIFT E BY 0,0,-200") == ("E", 0.0, 0.0, -200.0)
    assert args("SHIFT E BY ,,10") == ("E", None, None, 10.0)
    assert args("SET P1 = P2") == ("P1", LocArg("P2"))
    assert args("OPENI") == (None,)
    assert args("CLOSEI(50)") == (50.0,)
    assert args("DRAW 10") == (10.0, None, None)
    assert args("GRASP 50, 100") == (50.0, 100)
    assert args("GRASP 50") == (50.0,)
    assert args("GOTO 300") == (300,)
    assert args("COL=COL+1") == ("COL", "COL+1")


def test_type_forms_keep_the_text_as_written() -> None:
    st = parse_statement("TYPE Pick up the first part ; a comment")
    assert st.shape == 1 and st.args == ("Pick up the first part",)
    st = parse_statement("TYPE COL=")
    assert st.shape == 0 and st.args == ("COL",)
    assert parse_statement("TYPE").args == (None,)


def test_if_forms() -> None:
    st = parse_statement("IF COL.EQ.2, THEN")  # the thesis's comma before THEN
    assert st.keywords == ("THEN",)
    assert st.args[0]({"COL": 2.0})
    st = parse_statement("IF COL .GT. 1 GOTO 100")
    assert st.keywords == ("GOTO",) and st.args[1] == 100
    st = parse_statement("WHILE COL .LT. ROW. DO")
    assert st.args[0]({"COL": 1.0, "ROW": 3.0})
    assert parse_statement("UNTIL COL .EQ. ROW.").args[0]({"COL": 3.0, "ROW": 3.0})


def test_shifted_location_argument() -> None:
    loc = parse_statement("MOVE SHIFT(A BY 10, ,-5)").args[0]
    assert loc.name == "A"
    assert [e.const if e is not None else None for e in loc.shift] == [10.0, None, -5.0]
    st = parse_statement("APPROS SHIFT(B BY 0,0,X), 50")
    assert st.args[0].shift[2].names == ("X",) and st.args[1].const == 50.0


def test_comments_and_empty_statements() -> None:
    assert parse_statement("; PROGRAM CONV1").command == ""
    assert parse_statement("   ").command == ""
    assert parse_statement("READY ; back to the start").command == "READY"


@pytest.mark.parametrize("text, reason", [
    ("D", "ambiguous: it could be DELAY, DEPART, DEPARTS, DO, DRAW, DRIVE"),
    ("JUMP 10", "JUMP is not a command the simulator accepts"),
    ("ABORT", "CTRL-C"),
    ("MOVE", "expected MOVE <location>"),
    ("MOVE 1A", "not a location name"),
    ("MOVE ABCDEFGHIJ", "longer than 9"),
    ("APPRO A", "expected APPRO <location>, <value>"),
    ("DEPART 1+", "ends too soon"),
    ("DRIVE 1, 2", "DRIVE"),
    ("GOTO X", "not a step label"),
    ("SPEED 50 60", "unexpected '60'"),
    ("WHILE X .LT. 3", "WHILE"),
    ("IF X .LT. 3", "IF"),
    ("SET P1", "SET"),
    ("ROWCOLUMNXX=1", "longer than 9"),
    ("X=", "needs a value"),
    ("BASE 1,2,3,4,5", "BASE"),
    ("READY NOW", "READY"),
    ("123", "not a VAL-II command"),
])
def test_statement_errors(text: str, reason: str) -> None:
    with pytest.raises(ValSyntaxError) as info:
        parse_statement(text)
    assert reason in str(info.value)
