"""HELPER.DAT: the on-line help topics (section 6.8.5).

"The user input is checked against individual entries in this list. Whenever the user
input matches one of the entries in the file, a pointer is set and the corresponding
information is displayed."  Format: see the header of assets/HELPER.DAT.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

from valterm.core import resources
from valterm.core.errors import ValtermError
from valterm.core.files._text import read_parsed
from valterm.core.files.errors import FileFormatError

HELPER_FILE = resources.data_path("HELPER.DAT")

_NAME = re.compile(r"^[A-Z][A-Z0-9_-]*$")


class NoHelpTopic(ValtermError):
    """A word that names no help topic, or more than one (the message says which)."""


@dataclass
class HelpTopic:
    names: tuple[str, ...]
    syntax: list[str] = field(default_factory=list)
    when: str = ""
    text: list[str] = field(default_factory=list)
    line: int = 0

    @property
    def name(self) -> str:
        return self.names[0]

    def lines(self) -> list[str]:
        """The topic as the help screen shows it: syntax, description, when to use."""
        out = [f"HELP: {' / '.join(self.names)}", ""]
        out += [f"  {s}" for s in self.syntax]
        out.append("")
        out += self.text
        out += ["", f"USE: {self.when}"]
        return out


class HelpTopics:
    def __init__(self, topics: list[HelpTopic]) -> None:
        self.topics = topics
        self._by_name = {name: topic for topic in topics for name in topic.names}

    def __iter__(self) -> Iterator[HelpTopic]:
        return iter(self.topics)

    def __len__(self) -> int:
        return len(self.topics)

    def names(self) -> list[str]:
        return sorted(self._by_name)

    def find(self, word: str) -> HelpTopic:
        """The topic named `word` or the one a unique prefix names; NoHelpTopic says why not."""
        word = word.strip().upper()
        if word in self._by_name:
            return self._by_name[word]
        topics: dict[str, HelpTopic] = {}
        for name, topic in self._by_name.items():
            if name.startswith(word):
                topics[topic.name] = topic
        if len(topics) == 1:
            return next(iter(topics.values()))
        if not topics:
            raise NoHelpTopic(f"NO HELP FOR {word}")
        raise NoHelpTopic(f"{word} IS AMBIGUOUS: {', '.join(sorted(topics))}")

    def menu(self, width: int = 72) -> list[str]:
        """The HELP MENU: every topic name, in rows."""
        lines = ["HELP MENU", "", "HELP IS AVAILABLE ON:"]
        row = ""
        for name in self.names():
            if len(row) + len(name) + 2 > width:
                lines.append(row.rstrip())
                row = ""
            row += f"{name:<10}  "
        if row:
            lines.append(row.rstrip())
        lines += ["", "TYPE HELP <TOPIC> FOR MORE INFORMATION"]
        return lines


def parse_help_file(text: str, path: Path | str = HELPER_FILE) -> HelpTopics:
    path = Path(path)
    topics: list[HelpTopic] = []
    seen: dict[str, int] = {}
    current: HelpTopic | None = None

    def finish(topic: HelpTopic | None) -> None:
        if topic is None:
            return
        if not topic.syntax:
            raise FileFormatError(path, topic.line, f"topic {topic.name} has no SYNTAX line")
        if not topic.when:
            raise FileFormatError(path, topic.line, f"topic {topic.name} has no WHEN line")
        while topic.text and not topic.text[-1].strip():
            topic.text.pop()
        topics.append(topic)

    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.rstrip()
        if line.startswith(";"):
            continue
        keyword, _, rest = line.partition(" ")
        if keyword == "TOPIC":
            finish(current)
            names = tuple(rest.upper().split())
            if not names:
                raise FileFormatError(path, number, "TOPIC needs a name")
            for name in names:
                if not _NAME.match(name):
                    raise FileFormatError(path, number, f"{name!r} is not a topic name")
                if name in seen:
                    raise FileFormatError(path, number, f"topic {name} is already on line {seen[name]}")
                seen[name] = number
            current = HelpTopic(names, line=number)
        elif current is None:
            if line.strip():
                raise FileFormatError(path, number, "text before the first TOPIC line")
        elif keyword == "SYNTAX":
            current.syntax.append(rest.rstrip())
        elif keyword == "WHEN":
            current.when = rest.strip()
        elif current.text or line.strip():
            current.text.append(line)
    finish(current)
    if not topics:
        raise FileFormatError(path, 0, "holds no help topics")
    return HelpTopics(topics)


def load_help(path: Path | str = HELPER_FILE) -> HelpTopics:
    return read_parsed(path, "help", parse_help_file)  # located errors, size limit, no binary junk


@lru_cache(maxsize=1)
def default_help() -> HelpTopics:
    return load_help(HELPER_FILE)
