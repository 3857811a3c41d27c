"""HELP names only commands that exist (issue 35, build item 5): every SYNTAX line of every
HELPER.DAT topic, its placeholders filled with sample values and its optional parts both kept
and left out, is accepted by the parser the VAL-II prompt uses; no topic names a VAL-II
command the simulator refuses; collision checks can be found from the HELP."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from valterm.core.files.commandfile import default_commands
from valterm.core.files.helpfile import HelpTopic, default_help
from valterm.core.session import Session
from valterm.core.val.parser import ValSyntaxError, parse_statement

# a value for each placeholder; a new placeholder fails the test until it is given one here
SAMPLES = {
    "location name": "P1", "location": "P1", "distance": "50", "dx": "10", "dy": "0", "dz": "-5",
    "z rotation": "90", "joint": "2", "change": "10", "speed": "50", "time": "1", "hand opening": "50",
    "label": "10", "program": "T1", "loops": "2", "step": "3", "message": "DONE", "percent": "50",
    "logical expression": "X == 1", "expression": "X + 1", "variable": "X", "variable name": "X",
    "character string": "HELLO", "topic": "MOVE", "file": "T1",
}

# topics whose SYNTAX is keys to press, not a line to type (each says where in WHEN)
KEY_TOPICS = {"ABORT", "VIEW", "COLLISIONS"}

# VAL-II's own words (the PUMA's monitor and program commands, Unimation's manual): a HELP text
# may name one only if the simulator accepts it; ABORT's topic says that it does not
VAL_II_WORDS = {
    "ABORT", "BASE", "CALIBRATE", "COMM", "COPY", "DELETE", "DELETEL", "DELETEP", "DIRECTORY",
    "DISABLE", "ENABLE", "EXECUTE", "FCOPY", "FDELETE", "FLIST", "FORMAT", "FRENAME", "HOLD",
    "LISTL", "LISTP", "LISTR", "LOAD", "PARAMETER", "PRIME", "PROCEED", "RENAME", "RESET", "RETRY",
    "SEE", "STORE", "STOREL", "STOREP", "STORER", "TEACH", "TOOL", "ZERO", "DETACH", "ATTACH",
}


def expansions(line: str) -> list[str]:
    """The line with each optional {...} part kept and left out (innermost first)."""
    inner = re.search(r"\{([^{}]*)\}", line)
    if inner is None:
        return [line]
    kept = line[:inner.start()] + inner.group(1) + line[inner.end():]
    dropped = line[:inner.start()] + line[inner.end():]
    return expansions(kept) + expansions(dropped)


def filled(line: str) -> str:
    def sample(match: re.Match[str]) -> str:
        assert match.group(1) in SAMPLES, f"HELPER.DAT placeholder <{match.group(1)}> has no sample here"
        return SAMPLES[match.group(1)]

    return re.sub(r"<([^<>]+)>", sample, line)


def typed_examples(topic: HelpTopic) -> list[str]:
    """What a user could type from the topic's SYNTAX lines (group-of-steps lines skipped)."""
    lines = []
    for syntax in topic.syntax:
        # `<group of steps>` is no line to type; `<variable> = <expression>` is one
        if (syntax.startswith(" ") or syntax.strip().strip("{}").startswith("<")) and "=" not in syntax:
            continue
        lines += [filled(text.replace("{", "").replace("}", "")) for text in expansions(syntax.strip())]
    return lines


TOPICS = [topic for topic in default_help() if topic.name not in KEY_TOPICS]


@pytest.mark.parametrize("topic", TOPICS, ids=[topic.name for topic in TOPICS])
def test_every_help_syntax_line_is_accepted_by_the_parser(topic: HelpTopic) -> None:
    table = default_commands()
    examples = typed_examples(topic)
    assert examples, f"HELP {topic.name} shows nothing to type"
    for example in examples:
        try:
            statement = parse_statement(example, table)
        except ValSyntaxError as error:
            raise AssertionError(f"HELP {topic.name}: {example!r} is refused: {error}") from None
        if topic.name != "COMMENT":
            assert statement.command, f"HELP {topic.name}: {example!r} is no command"


def test_the_key_topics_are_no_commands_and_say_where_to_press_their_keys() -> None:
    table = default_commands()
    for name in KEY_TOPICS:
        topic = default_help().find(name)
        assert name not in table, f"HELP {name} is a command: give it SYNTAX lines to type"
        assert any(word in topic.when.upper() for word in ("WHILE", "ON THE", "ON EVERY")), topic.when
    assert "KEYBOARD" in default_help().find("COLLISIONS").when


def test_no_help_text_names_a_val_ii_command_the_simulator_refuses(tmp_path: Path) -> None:
    session = Session(tmp_path, setup=None)
    for topic in default_help():
        if topic.name == "ABORT":  # its text says the simulator does not accept the word
            continue
        words = set(re.findall(r"\b[A-Z]{2,}\b", " ".join([*topic.syntax, topic.when, *topic.text])))
        for word in sorted(words & VAL_II_WORDS):
            errors = [e.message for e in session.command(word) if type(e).__name__ == "Error"]
            assert not any("NOT A COMMAND" in message.upper() for message in errors), \
                f"HELP {topic.name} names {word}, which the simulator refuses: {errors}"


def test_collision_checks_are_found_from_the_val_ii_help(tmp_path: Path) -> None:
    session = Session(tmp_path, setup=None)
    [menu] = [e for e in session.command("HELP") if type(e).__name__ == "Help"]
    assert "COLLISIONS" in " ".join(menu.lines)
    for word in ("COLL", "COLLISION", "SMOOTH"):
        [found] = [e for e in session.command(f"HELP {word}") if type(e).__name__ == "Help"]
        text = "\n".join(found.lines)
        assert found.topic == "COLLISIONS" and "S_SMOOTH" in text and "KEYBOARD" in text, word
