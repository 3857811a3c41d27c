"""COMMAND.DAT: the commands the simulator accepts and the shape of their arguments.

The file is data (see its header for the format); this module reads it into a
``CommandTable`` that resolves unique-prefix abbreviations (App. C section 6:
"If a VAL-II command does not match one of the entries in the COMMAND.DAT file, it
can not be simulated and an error message is displayed").
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

from valterm.core import resources
from valterm.core.errors import ValtermError
from valterm.core.files._text import read_parsed
from valterm.core.files.errors import FileFormatError

COMMAND_FILE = resources.data_path("COMMAND.DAT")

SLOT_KINDS = ("LOC", "NAME", "EXPR", "COND", "LABEL", "PROG", "TEXT", "VAR")
USES = {"B": "program and monitor", "P": "program", "M": "monitor"}

# How a slot reads in a usage line (`APPRO <location>, <distance>`).
_SLOT_WORDS = {
    "LOC": "<location>",
    "NAME": "<name>",
    "EXPR": "<value>",
    "COND": "<condition>",
    "LABEL": "<label>",
    "PROG": "<program>",
    "TEXT": "<text>",
    "VAR": "<variable>=",
}


@dataclass(frozen=True)
class Slot:
    """An argument to fill: its kind (LOC, EXPR, ...) and whether it may be left out."""

    kind: str
    optional: bool = False


@dataclass(frozen=True)
class Literal:
    """A separator or keyword that must (or, optional, may) appear: `,` `=` `then` `by/,`."""

    options: tuple[str, ...]
    optional: bool = False


Item = Slot | Literal


@dataclass(frozen=True)
class CommandSpec:
    name: str
    use: str  # B | P | M
    shapes: tuple[tuple[Item, ...], ...]
    shape_text: str
    line: int = 0

    @property
    def in_program(self) -> bool:
        return self.use in ("B", "P")

    @property
    def typed(self) -> bool:
        return self.use in ("B", "M")

    def usage(self) -> str:
        """`APPRO <location>, <value>` for error messages; alternatives joined by ` or `."""
        forms = []
        for shape in self.shapes:
            words = [self.name]
            for item in shape:
                if isinstance(item, Slot):
                    word = _SLOT_WORDS[item.kind]
                    words.append(f"{{{word}}}" if item.optional else word)
                elif not item.optional:
                    option = item.options[0].upper()
                    if option == ",":
                        words[-1] += option
                    else:
                        words.append(option)
            forms.append(" ".join(words))
        return " or ".join(forms)


class UnknownCommand(ValtermError, ValueError):
    pass


class AmbiguousCommand(ValtermError, ValueError):
    def __init__(self, word: str, candidates: list[str]) -> None:
        self.word = word
        self.candidates = candidates
        super().__init__(f"{word} is ambiguous: {', '.join(candidates)}")


class CommandTable:
    """The accepted commands, looked up by full name or unique prefix."""

    def __init__(self, specs: list[CommandSpec]) -> None:
        self.specs = {spec.name: spec for spec in specs}
        self.names = sorted(self.specs)
        self._cache: dict[str, CommandSpec] = {}

    def __contains__(self, name: str) -> bool:
        return name.upper() in self.specs

    def __iter__(self) -> Iterator[CommandSpec]:
        return iter(self.specs.values())

    def __len__(self) -> int:
        return len(self.specs)

    def lookup(self, word: str) -> CommandSpec:
        """The command `word` names: exact name first, else the one it is a prefix of."""
        word = word.upper()
        spec = self._cache.get(word)
        if spec is not None:
            return spec
        spec = self.specs.get(word)
        if spec is None:
            candidates = [name for name in self.names if name.startswith(word)]
            if not candidates:
                raise UnknownCommand(f"{word} is not a VAL-II command the simulator accepts")
            if len(candidates) > 1:
                raise AmbiguousCommand(word, candidates)
            spec = self.specs[candidates[0]]
        self._cache[word] = spec
        return spec


_NAME = re.compile(r"^[A-Z][A-Z0-9]*$")


def _parse_shape(text: str, path: Path, number: int) -> tuple[tuple[Item, ...], ...]:
    shapes: list[tuple[Item, ...]] = []
    for alternative in text.split(" | "):
        items: list[Item] = []
        words = alternative.split()
        if words == ["-"]:
            shapes.append(())
            continue
        for word in words:
            optional = word.endswith("?")
            core = word[:-1] if optional else word
            if core in SLOT_KINDS:
                items.append(Slot(core, optional))
            elif core in (",", "=") or (core.islower() and all(
                    part in (",", "=") or part.isalpha() for part in core.split("/"))):
                items.append(Literal(tuple(core.upper().split("/")), optional))
            else:
                raise FileFormatError(path, number, f"{word!r} is not an argument item "
                                      f"({', '.join(SLOT_KINDS)}, a separator or a lowercase keyword)")
        shapes.append(tuple(items))
    return tuple(shapes)


def parse_command_file(text: str, path: Path | str = COMMAND_FILE) -> CommandTable:
    """Read COMMAND.DAT text; a FileFormatError names the line of any bad entry."""
    path = Path(path)
    specs: list[CommandSpec] = []
    seen: dict[str, int] = {}
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if not line or line.startswith(";"):
            continue
        fields = line.split(None, 2)
        if len(fields) < 3:
            raise FileFormatError(path, number, "expected NAME USE ARGUMENTS (use - for no arguments)")
        name, use, shape_text = fields[0], fields[1], fields[2].strip()
        if not _NAME.match(name):
            raise FileFormatError(path, number, f"{name!r} is not a command name (uppercase letters and digits)")
        if use not in USES:
            raise FileFormatError(path, number, f"use {use!r} must be B, P or M")
        if name in seen:
            raise FileFormatError(path, number, f"{name} is listed twice (first on line {seen[name]})")
        seen[name] = number
        specs.append(CommandSpec(name, use, _parse_shape(shape_text, path, number), shape_text, number))
    if not specs:
        raise FileFormatError(path, 0, "lists no commands")
    return CommandTable(specs)


def load_commands(path: Path | str = COMMAND_FILE) -> CommandTable:
    return read_parsed(path, "command", parse_command_file)  # located errors, size limit, no binary junk


@lru_cache(maxsize=1)
def default_commands() -> CommandTable:
    """The bundled COMMAND.DAT, read once."""
    return load_commands(COMMAND_FILE)
